#!/bin/sh
# voxlux's quality presets and its reference against Blender's Cycles on a matched scene: each
# render's mean luminance over Cycles', its RMSE against Cycles and against voxlux's reference, and
# its seconds. Needs build/voxlux and blender (Debian's package, 3.4) on the PATH. Run from the
# repository's root:
#   bench/cycles/compare_presets.sh [SCENE.json] [SPP]
# SCENE (default bench/cycles/smoke_environment.json) must hold what cycles_render.py matches.
# Cycles and the reference render it at SPP (default 256) with 16 bounces; a second reference of
# another seed shows what noise alone leaves in an RMSE. VOXLUX names another voxlux binary.
set -eu
voxlux=${VOXLUX:-build/voxlux}
here=$(dirname "$0")
scene=${1:-$here/smoke_environment.json}
spp=${2:-256}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
march_seconds() { sed -n 's/.* march \([0-9.]*\) s.*/\1/p'; }
render() {  # NAME, then voxlux's arguments
    name=$1
    shift
    seconds=$("$voxlux" render "$scene" -o "$out/$name.exr" --set render.reference.spp=$spp --set render.reference.max_bounces=16 "$@" 2>&1 | march_seconds)
    [ -n "$seconds" ] || { echo "compare_presets.sh: $voxlux failed to render $scene ($name)" >&2; exit 1; }
    echo "$name $seconds" >> "$out/times"
}
seconds=$(blender -b --factory-startup -P "$here/cycles_render.py" -- "$scene" "$out/cycles.exr" $spp 1 16 2>&1 | sed -n 's/^cycles_seconds //p')
[ -n "$seconds" ] || { echo "compare_presets.sh: blender failed to render $scene" >&2; exit 1; }
echo "cycles $seconds" >> "$out/times"
render reference --set render.reference.seed=1
render seed2 --set render.reference.seed=2
for preset in draft preview final; do render $preset --quality $preset; done
cat "$out/times"
blender -b --factory-startup -P "$here/image_stats.py" -- "$out/cycles.exr" "$out/reference.exr" reference="$out/reference.exr" \
    seed2="$out/seed2.exr" draft="$out/draft.exr" preview="$out/preview.exr" final="$out/final.exr" 2>&1 | grep -v "^Blender\|^$\|^Read\|quit"

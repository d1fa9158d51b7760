#!/bin/sh
# voxlux's Monte Carlo reference side by side with Blender's Cycles on a matched scene: the image
# means, and the seconds each needs for equal noise, in single and multiple scattering. Needs
# build/voxlux and blender (Debian's package, 3.4) on the PATH. Run from the repository's root:
#   bench/cycles/compare_cycles.sh [SCENE.json] [SPP]
# SCENE (default bench/cycles/smoke_matched.json) must hold what cycles_render.py matches. Each
# renderer renders it at SPP (default 16) with seeds 1 and 2, and at 4 x SPP with seed 3. VOXLUX
# names another voxlux binary (a build of an earlier commit, say); build/voxlux by default.
set -eu
voxlux=${VOXLUX:-build/voxlux}
here=$(dirname "$0")
scene=${1:-$here/smoke_matched.json}
spp=${2:-16}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for bounces in 1 16; do
    for run in "1 $spp" "2 $spp" "3 $((4 * spp))"; do
        set -- $run
        seconds=$("$voxlux" render "$scene" -o "$out/voxlux_${bounces}_$1.exr" --set render.reference.seed=$1 \
            --set render.reference.spp=$2 --set render.reference.max_bounces=$bounces 2>&1 |
            sed -n 's/.* march \([0-9.]*\) s.*/\1/p')
        [ -n "$seconds" ] || { echo "compare_cycles.sh: $voxlux failed to render $scene" >&2; exit 1; }
        echo "voxlux $bounces $1 $2 $seconds" >> "$out/times"
        seconds=$(blender -b --factory-startup -P "$here/cycles_render.py" -- "$scene" "$out/cycles_${bounces}_$1.exr" \
            $2 $1 $bounces 2>&1 | sed -n 's/^cycles_seconds //p')
        [ -n "$seconds" ] || { echo "compare_cycles.sh: blender failed to render $scene" >&2; exit 1; }
        echo "cycles $bounces $1 $2 $seconds" >> "$out/times"
    done
done
blender -b --factory-startup -P "$here/noise_stats.py" -- "$out" 2>&1 | grep -v "^Blender\|^$\|^Read\|quit"

#!/bin/bash
# Frames per minute on the shared Blender fire (60 frames, 512x512, --quality draft), rendered
#   1. by one process for all frames (the render graph keeps what a frame change leaves valid);
#   2. by one process per frame (what a farm pays per task: start-up, scene and cache load);
#   3. through Slurm on a one-node localhost cluster (tests/farm/slurm_cluster.sh), in chunks of
#      CHUNK frames (default 10), submit to the last frame checked (farm submit --wait);
#   4. by one process with a deep EXR beside each frame (--deep, 16 samples a pixel);
#   5. by one process with velocity motion blur (8 rays a pixel, velocity_scale 0.5).
# Every way renders the same scene file (the camera framed once on all 60 frames), so the frames
# are the same. Needs the shared data beside the clone; the Slurm row needs root, slurm-wlm and
# munge, and is left out when the cluster cannot start. Run from the repository's root:
#   bench/farm/frames_per_minute.sh [FRAMES] [CHUNK]
# FRAMES (default 1-60) picks fewer frames for a quick look. VOXLUX names another binary.
set -eu
voxlux=$(realpath "${VOXLUX:-build/voxlux}")
frames=${1:-1-60}
chunk=${2:-10}
fire=$(realpath ../shared/data/blender/fire)/fluid_data_####.vdb
out=$(mktemp -d /tmp/vxfarm.XXXXXX)
trap 'tests/farm/slurm_cluster.sh stop "$out/cluster" >/dev/null 2>&1; rm -rf "$out"' EXIT
count=$(python3 -c "
import sys; n=0
for part in sys.argv[1].split(','):
    a, _, rest = part.partition('-'); b, _, s = rest.partition('x')
    n += (int(b or a) - int(a)) // int(s or 1) + 1
print(n)" "$frames")
"$voxlux" scene "$fire" --frames "$frames" --blackbody-grid temperature --quality draft --res 512x512 \
    --image "$out/frames/fire.####.exr" -o "$out/shot.json" 2>/dev/null >/dev/null

now() { date +%s.%N; }
report() {   # NAME START END
    python3 -c "import sys; s=float(sys.argv[3])-float(sys.argv[2]); print(f'{sys.argv[1]:<34} {s:7.1f} s  {60*int(sys.argv[4])/s:6.1f} frames/min')" \
        "$1" "$2" "$3" "$count"
}
echo "$count frames of the Blender fire, 512x512, --quality draft, $(nproc) cores; $voxlux"

start=$(now)
"$voxlux" render "$out/shot.json" -o "$out/one/fire.####.exr" >/dev/null
report "one process, all frames" "$start" "$(now)"

start=$(now)
"$voxlux" render "$out/shot.json" -o "$out/deep/fire.####.exr" --deep >/dev/null
report "one process, all frames, --deep" "$start" "$(now)"
echo "  deep files: $(du -sh "$out/deep" | cut -f1) with the images (images alone: $(du -sh "$out/one" | cut -f1))"

start=$(now)
"$voxlux" render "$out/shot.json" -o "$out/blur/fire.####.exr" --set 'render.motion_blur={"velocity_scale":0.5}' >/dev/null
report "one process, all frames, motion blur" "$start" "$(now)"

start=$(now)
python3 - "$voxlux" "$out/shot.json" "$frames" "$out/each" <<'PY'
import subprocess, sys
voxlux, scene, spec, folder = sys.argv[1:]
for part in spec.split(','):
    a, _, rest = part.partition('-'); b, _, s = rest.partition('x')
    for f in range(int(a), int(b or a) + 1, int(s or 1)):
        subprocess.run([voxlux, "render", scene, "--frames", str(f), "-o", f"{folder}/fire.####.exr"],
                       check=True, stdout=subprocess.DEVNULL)
PY
report "one process per frame" "$start" "$(now)"

if conf=$(tests/farm/slurm_cluster.sh start "$out/cluster" 2>"$out/cluster.err"); then
    export "$conf"
    start=$(now)
    "$voxlux" farm submit "$out/shot.json" --chunk "$chunk" --job-dir "$out/job" -o "$out/slurm/fire.####.exr" --wait >/dev/null
    report "Slurm on localhost, chunks of $chunk" "$start" "$(now)"
else
    echo "Slurm on localhost: left out ($(cat "$out/cluster.err"))"
fi

# Reads the renders bench/cycles/compare_cycles.sh wrote into DIR and prints, per renderer and
# bounce count: the image mean (luminance, Rec.709 weights), the noise at N samples per pixel (the
# RMS luminance difference of two seeds over sqrt 2), the seconds per sample per pixel (the slope
# between N and 4N spp, which leaves out loading and set-up), and the seconds each needs for a noise
# of 1% of the image mean. Run by Blender's Python for its EXR reader:
#   blender -b --factory-startup -P noise_stats.py -- DIR
import math
import os
import sys

import bpy

folder = sys.argv[sys.argv.index("--") + 1]


def luminance(path):
    image = bpy.data.images.load(path)
    px = image.pixels[:]
    return [0.2126 * px[i] + 0.7152 * px[i + 1] + 0.0722 * px[i + 2] for i in range(0, len(px), 4)]


runs = {}
with open(os.path.join(folder, "times")) as f:
    for line in f:
        renderer, bounces, seed, spp, seconds = line.split()
        runs[(renderer, int(bounces), int(seed))] = (int(spp), float(seconds))

cost = {}
print("%-7s %7s %10s %12s %12s %14s" % ("", "bounces", "mean", "noise at N", "s per spp", "s for 1% noise"))
for bounces in sorted({key[1] for key in runs}):
    for renderer in ("voxlux", "cycles"):
        name = lambda seed: os.path.join(folder, "%s_%d_%d.exr" % (renderer, bounces, seed))
        a, b, fine = luminance(name(1)), luminance(name(2)), luminance(name(3))
        n, t1 = runs[(renderer, bounces, 1)]
        n4, t3 = runs[(renderer, bounces, 3)]
        mean = sum(fine) / len(fine)
        noise = math.sqrt(sum((x - y) ** 2 for x, y in zip(a, b)) / len(a) / 2.0)
        per_spp = max(t3 - t1, 1e-9) / (n4 - n)
        # Noise falls as 1/sqrt(spp): the samples for a noise of 1% of the mean, times their cost.
        seconds = per_spp * n * (noise / (0.01 * mean)) ** 2
        cost[(renderer, bounces)] = seconds
        print("%-7s %7d %10.5f %12.5f %12.5f %14.2f" % (renderer, bounces, mean, noise, per_spp, seconds))
    print("bounces %d: voxlux's mean is %.3f of Cycles'; it needs %.2fx Cycles' seconds for equal noise" % (
        bounces, sum(luminance(os.path.join(folder, "voxlux_%d_3.exr" % bounces))) /
        sum(luminance(os.path.join(folder, "cycles_%d_3.exr" % bounces))),
        cost[("voxlux", bounces)] / cost[("cycles", bounces)]))

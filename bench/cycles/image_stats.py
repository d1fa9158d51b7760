# Prints, for each image after the first two, its mean luminance over the first's (Rec.709 weights)
# and its RGB RMSE against the first and against the second, for bench/cycles/compare_presets.sh.
# Run by Blender's Python for its EXR reader:
#   blender -b --factory-startup -P image_stats.py -- CYCLES.exr REFERENCE.exr NAME=IMAGE.exr ...
import math
import sys

import bpy

args = sys.argv[sys.argv.index("--") + 1:]


def pixels(path):
    image = bpy.data.images.load(path)
    return image.pixels[:]  # RGBA, float


def mean_luminance(px):
    return sum(0.2126 * px[i] + 0.7152 * px[i + 1] + 0.0722 * px[i + 2] for i in range(0, len(px), 4)) / (len(px) // 4)


def rmse(a, b):
    channels = [i for i in range(len(a)) if i % 4 != 3]
    return math.sqrt(sum((a[i] - b[i]) ** 2 for i in channels) / len(channels))


cycles, reference = pixels(args[0]), pixels(args[1])
cycles_mean = mean_luminance(cycles)
print("%-10s %14s %16s %20s" % ("render", "mean / Cycles", "RMSE vs Cycles", "RMSE vs reference"))
for named in args[2:]:
    name, path = named.split("=", 1)
    px = pixels(path)
    print("%-10s %14.4f %16.5f %20.5f" % (name, mean_luminance(px) / cycles_mean, rmse(px, cycles), rmse(px, reference)))

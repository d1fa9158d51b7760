# Renders a voxlux scene .json (one volume, directional, ambient and environment lights, isotropic
# or HG scattering, constant albedo) with Blender's Cycles, for bench/cycles/compare_cycles.sh and
# compare_presets.sh:
#   blender -b --factory-startup -P cycles_render.py -- SCENE.json OUT.exr SPP SEED BOUNCES
# BOUNCES counts scattering events as voxlux's render.reference.max_bounces does (1 = single
# scattering: Cycles' volume bounces 0). Prints "cycles_seconds S", the time of the render alone.
# What differs, and stays: Cycles 3.x ray-marches heterogeneous volumes (render step rate 1, a
# voxel), where voxlux's reference tracks them without bias; Blender puts voxel centres half a
# voxel from OpenVDB's convention, so images are compared by their means and noise, not per pixel.
import json
import math
import os
import sys
import time

import bpy
from mathutils import Matrix, Vector

scene_path, out_path, spp, seed, bounces = sys.argv[sys.argv.index("--") + 1:]
spp, seed, bounces = int(spp), int(seed), int(bounces)
with open(scene_path) as f:
    vx = json.load(f)
here = os.path.dirname(os.path.abspath(scene_path))

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
scene.render.engine = "CYCLES"
cycles = scene.cycles
cycles.device = "CPU"
cycles.samples = spp
cycles.seed = seed
cycles.use_adaptive_sampling = False
cycles.use_denoising = False
cycles.sample_clamp_direct = 0.0
cycles.sample_clamp_indirect = 0.0
cycles.light_sampling_threshold = 0.0
cycles.max_bounces = bounces
cycles.volume_bounces = bounces - 1
cycles.transparent_max_bounces = 64  # volume bounds are transparent surfaces to shadow rays
cycles.filter_width = 0.01  # voxlux's reference samples pixel centres
scene.render.threads_mode = "FIXED"
scene.render.threads = os.cpu_count()
width, height = vx["render"]["resolution"]
scene.render.resolution_x, scene.render.resolution_y = width, height
scene.render.resolution_percentage = 100
scene.render.film_transparent = True  # the reference's camera sees no ambient background
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"
scene.render.image_settings.color_mode = "RGBA"
scene.view_settings.view_transform = "Standard"

# The volume, its density through the material: sigma_s = albedo * sigma_t by Volume Scatter
# (weight = density), sigma_a = (1 - albedo) * sigma_t by Volume Absorption with a black colour.
volume = bpy.data.volumes.new("volume")
volume.filepath = os.path.normpath(os.path.join(here, vx["volume"]["path"]))
obj = bpy.data.objects.new("volume", volume)
scene.collection.objects.link(obj)
material = bpy.data.materials.new("medium")
material.use_nodes = True
nodes, links = material.node_tree.nodes, material.node_tree.links
nodes.clear()
grid = nodes.new("ShaderNodeAttribute")
grid.attribute_name = vx["volume"].get("density", "density")
sigma_t = nodes.new("ShaderNodeMath")
sigma_t.operation = "MULTIPLY"
sigma_t.inputs[1].default_value = vx["material"].get("density_scale", 1.0)
links.new(grid.outputs["Fac"], sigma_t.inputs[0])
albedo = vx["material"].get("albedo", [1.0, 1.0, 1.0])
if max(albedo) - min(albedo) > 1e-6:
    sys.exit("cycles_render.py: a grey albedo only (one scattering coefficient per channel differs)")
scatter_density = nodes.new("ShaderNodeMath")
scatter_density.operation = "MULTIPLY"
scatter_density.inputs[1].default_value = albedo[0]
links.new(sigma_t.outputs[0], scatter_density.inputs[0])
absorb_density = nodes.new("ShaderNodeMath")
absorb_density.operation = "MULTIPLY"
absorb_density.inputs[1].default_value = 1.0 - albedo[0]
links.new(sigma_t.outputs[0], absorb_density.inputs[0])
scatter = nodes.new("ShaderNodeVolumeScatter")
scatter.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
scatter.inputs["Anisotropy"].default_value = vx["material"].get("anisotropy", 0.0)
links.new(scatter_density.outputs[0], scatter.inputs["Density"])
absorb = nodes.new("ShaderNodeVolumeAbsorption")
absorb.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
links.new(absorb_density.outputs[0], absorb.inputs["Density"])
add = nodes.new("ShaderNodeAddShader")
links.new(scatter.outputs[0], add.inputs[0])
links.new(absorb.outputs[0], add.inputs[1])
output = nodes.new("ShaderNodeOutputMaterial")
links.new(add.outputs[0], output.inputs["Volume"])
volume.materials.append(material)


def environment_world(light):
    """An environment light as the world: its map through a Mapping node that takes Cycles' world
    direction into the map's own frame (voxlux's is Blender's equirectangular mapping about `up`,
    turned by `rotation`: docs/environment.md), read by the nearest pixel as voxlux's lighting reads
    it, times the light's colour and intensity."""
    if "up" not in light:
        sys.exit("cycles_render.py: an environment light needs its `up` (voxlux's default reads the volume's file)")
    up = light["up"]
    up = Vector({"x": (1, 0, 0), "y": (0, 1, 0), "z": (0, 0, 1)}[up] if isinstance(up, str) else up).normalized()
    x = Vector((0, 1, 0)) if abs(up.x) > 0.9 else Vector((1, 0, 0))  # as environmentFrame
    x = (x - up * x.dot(up)).normalized()
    x.rotate(Matrix.Rotation(math.radians(light.get("rotation", 0.0)), 3, up))
    y = up.cross(x)
    to_map = Matrix((x, y, up))  # rows: a world direction's coordinates in the map's frame
    nodes, links = world.node_tree.nodes, world.node_tree.links
    coordinates = nodes.new("ShaderNodeTexCoord")
    mapping = nodes.new("ShaderNodeMapping")
    mapping.vector_type = "VECTOR"
    mapping.inputs["Rotation"].default_value = to_map.to_euler("XYZ")
    links.new(coordinates.outputs["Generated"], mapping.inputs["Vector"])
    texture = nodes.new("ShaderNodeTexEnvironment")
    texture.image = bpy.data.images.load(os.path.normpath(os.path.join(here, light["map"])))
    texture.interpolation = "Closest"
    links.new(mapping.outputs["Vector"], texture.inputs["Vector"])
    tint = nodes.new("ShaderNodeMixRGB")
    tint.blend_type = "MULTIPLY"
    tint.inputs["Fac"].default_value = 1.0
    tint.inputs["Color2"].default_value = (*light.get("color", [1.0, 1.0, 1.0]), 1.0)
    links.new(texture.outputs["Color"], tint.inputs["Color1"])
    links.new(tint.outputs["Color"], background.inputs["Color"])
    background.inputs["Strength"].default_value = light.get("intensity", 1.0)
    world.cycles.sampling_method = "MANUAL"
    world.cycles.sample_map_resolution = max(texture.image.size)


# The lights: a directional light is a sun of angle 0 whose strength is its irradiance; ambient
# light is the world's uniform background radiance, an environment light its map.
world = bpy.data.worlds.new("world")
world.use_nodes = True
background = world.node_tree.nodes["Background"]
background.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
scene.world = world
for light in vx["lights"]:
    color = [c * light.get("intensity", 1.0) for c in light.get("color", [1.0, 1.0, 1.0])]
    if light["type"] == "ambient":
        background.inputs["Color"].default_value = (*color, 1.0)
        background.inputs["Strength"].default_value = 1.0
    elif light["type"] == "environment":
        if light.get("map_colorspace") != "Linear Rec.709 (sRGB)":
            sys.exit("cycles_render.py: an environment map in \"Linear Rec.709 (sRGB)\" only (what Blender reads an EXR as)")
        environment_world(light)
    elif light["type"] == "directional":
        peak = max(color)
        sun = bpy.data.lights.new("sun", "SUN")
        sun.color = [c / peak for c in color]
        sun.energy = peak
        sun.angle = math.radians(0.01)
        sun_obj = bpy.data.objects.new("sun", sun)
        sun_obj.rotation_euler = Vector(light["direction"]).to_track_quat("-Z", "Y").to_euler()
        scene.collection.objects.link(sun_obj)
    else:
        sys.exit("cycles_render.py: light type %s is not matched" % light["type"])

# The camera: voxlux's look-at frame and vertical field of view.
cam = vx["camera"]
position, forward = Vector(cam["position"]), (Vector(cam["look_at"]) - Vector(cam["position"])).normalized()
right = forward.cross(Vector(cam.get("up", [0, 1, 0]))).normalized()
up = right.cross(forward)
camera = bpy.data.cameras.new("camera")
camera.sensor_fit = "VERTICAL"
camera.angle_y = math.radians(cam["fov"])
camera.clip_end = 1e5
camera_obj = bpy.data.objects.new("camera", camera)
camera_obj.matrix_world = Matrix((
    (right.x, up.x, -forward.x, position.x),
    (right.y, up.y, -forward.y, position.y),
    (right.z, up.z, -forward.z, position.z),
    (0.0, 0.0, 0.0, 1.0)))
scene.collection.objects.link(camera_obj)
scene.camera = camera_obj

scene.render.filepath = out_path
start = time.perf_counter()
bpy.ops.render.render(write_still=True)
print("cycles_seconds %.3f" % (time.perf_counter() - start))

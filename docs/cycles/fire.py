# Renders a Mantaflow fire cache in Cycles as Blender 3.4's defaults show it, through the camera and
# key light of a voxlux scene, for the side-by-side picture in docs/cli.md:
#   blender -b --factory-startup --python docs/cycles/fire.py -- CACHE.vdb SCENE.json OUT.png
# The material is a Principled Volume reading `density`, and `temperature` as Blackbody at
# intensity 1 (Blender's Quick Smoke with fire); its density is voxlux's density_scale per world
# unit, so both see the same optical depth. Blender's default view transform (Filmic) stays.
import json
import math
import sys

import bpy
from mathutils import Vector

cache, scene_file, out = sys.argv[sys.argv.index("--") + 1:][:3]
with open(scene_file) as f:
    vx = json.load(f)

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = 256
scene.cycles.volume_bounces = 2
scene.cycles.use_denoising = False   # Debian builds Cycles without OpenImageDenoise
scene.render.resolution_x, scene.render.resolution_y = vx["render"]["resolution"]
scene.render.film_transparent = False
scene.world = bpy.data.worlds.new("black")   # no light but the key, as in the voxlux scene
scene.world.color = (0.0, 0.0, 0.0)

bpy.ops.object.volume_import(filepath=cache)
volume = bpy.context.active_object
volume.data.grids.load()
voxel = min(volume.data.grids["density"].matrix_object.to_scale())   # the smallest voxel edge, as voxlux's voxel units
material = bpy.data.materials.new("fire")
material.use_nodes = True
nodes = material.node_tree.nodes
nodes.clear()
shader = nodes.new("ShaderNodeVolumePrincipled")
shader.inputs["Density"].default_value = vx["material"]["density_scale"] / voxel   # voxlux's per voxel, per unit here
shader.inputs["Density Attribute"].default_value = "density"
shader.inputs["Blackbody Intensity"].default_value = 1.0
shader.inputs["Temperature Attribute"].default_value = "temperature"
output = nodes.new("ShaderNodeOutputMaterial")
material.node_tree.links.new(shader.outputs["Volume"], output.inputs["Volume"])
volume.data.materials.append(material)

cam = vx["camera"]
camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
scene.collection.objects.link(camera)
scene.camera = camera
camera.data.sensor_fit = "VERTICAL"
camera.data.angle_y = math.radians(cam["fov"])
camera.location = Vector(cam["position"])
camera.rotation_euler = (Vector(cam["look_at"]) - camera.location).to_track_quat("-Z", "Y").to_euler()

key = next(l for l in vx["lights"] if l["type"] == "directional")
sun = bpy.data.objects.new("key", bpy.data.lights.new("key", "SUN"))
scene.collection.objects.link(sun)
sun.data.energy = 3.0
sun.rotation_euler = Vector(key["direction"]).to_track_quat("-Z", "Z").to_euler()

scene.render.filepath = out
bpy.ops.render.render(write_still=True)

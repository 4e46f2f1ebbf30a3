# Runs inside Blender with the add-on enabled (blender -b --factory-startup --addons veach --python
# blender_passes_scene.py -- OUT.blend): a floor whose Principled BSDF has subsurface scattering
# and a ball coloured by a Noise Texture (two kinds the add-on drops with a warning each), under a
# sun and two area lights with a spread of 90 degrees (warned once), with every pass the engine offers switched on; saved to OUT.blend for check_blender_passes.py.
import sys

import bpy

out = sys.argv[sys.argv.index("--") + 1]
scene = bpy.context.scene
for obj in list(scene.objects):
    bpy.data.objects.remove(obj)
scene.world = None

floor_material = bpy.data.materials.new("skin")
floor_material.use_nodes = True
bsdf = floor_material.node_tree.nodes["Principled BSDF"]
bsdf.inputs["Base Color"].default_value = (0.8, 0.5, 0.3, 1.0)
bsdf.inputs["Subsurface"].default_value = 0.5
bsdf.inputs["Specular"].default_value = 0.0
bsdf.inputs["Roughness"].default_value = 1.0
bpy.ops.mesh.primitive_plane_add(size=20)
bpy.context.object.data.materials.append(floor_material)

ball_material = bpy.data.materials.new("noisy")
ball_material.use_nodes = True
tree = ball_material.node_tree
noise = tree.nodes.new("ShaderNodeTexNoise")
tree.links.new(noise.outputs["Color"], tree.nodes["Principled BSDF"].inputs["Base Color"])
bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, location=(0, 0, 0.5))
bpy.context.object.data.materials.append(ball_material)

# The ball once more, as a collection instance (the export shares the ball's mesh between the two).
ball = bpy.context.object
ball.name = "ball"
group = bpy.data.collections.new("ball group")
group.objects.link(ball)
instance = bpy.data.objects.new("ball instance", None)
instance.instance_type = 'COLLECTION'
instance.instance_collection = group
instance.location = (1.5, 1.0, 0.0)
scene.collection.objects.link(instance)

# Two area lights whose spread the renderer does not have (90 degrees, rendered as 180): one
# warning for both. Dim, so the floor's checks below hold either way.
for k in range(2):
    area = bpy.data.objects.new(f"area{k}", bpy.data.lights.new(f"area{k}", "AREA"))
    area.data.energy = 1.0
    area.data.spread = 1.5708
    area.location = (k - 0.5, 0.0, 3.0)
    scene.collection.objects.link(area)

sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
sun.data.energy = 3.0
sun.rotation_euler = (0.4, 0.2, 0.0)
scene.collection.objects.link(sun)
camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
camera.location = (0.0, -4.0, 2.0)
camera.rotation_euler = (1.15, 0.0, 0.0)
scene.collection.objects.link(camera)
scene.camera = camera

scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 48, 32, 100
scene.cycles.samples = 16
scene.cycles.use_adaptive_sampling = False
layer = scene.view_layers[0]
layer.use_pass_z = True
layer.use_pass_normal = True
layer.veach.use_pass_denoising_data = True
layer.veach.use_pass_variance = True
layer.veach.use_pass_sample_count = True
bpy.ops.wm.save_as_mainfile(filepath=out)

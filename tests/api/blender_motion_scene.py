# Runs inside Blender (blender -b --factory-startup --python blender_motion_scene.py -- OUT_DIR
# ADDONS_DIR):
# saves OUT_DIR/motion.blend (Motion Blur on, Blender's default shutter 0.5 centred on the frame)
# and OUT_DIR/still.blend (the same scene, Motion Blur off) for check_blender_motion_blur.py.
# The scene: an orthographic camera at z = 2 looking down over x in [-2, 2], y in [-1, 1]
# (128 x 64 pixels, 32 per unit), a uniform white World (radiance 1), and a black mirror square
# (metallic, roughness 0: it reflects nothing of the World straight up) x, y in [-0.5, 0.5] at
# z = 0.5 keyed LINEAR from x = -1.5 at frame 1 to 1.5 at frame 13: 0.25 units per frame, centred
# on x = 0 at frame 7; and a spinning bar (below) beside it.
import math
import os
import sys

import bpy

out_dir, addons_dir = sys.argv[sys.argv.index("--") + 1:][:2]
sys.path.insert(0, addons_dir)
import veach  # noqa: E402 (the add-on, linked into addons_dir by check_blender_motion_blur.py)

veach.register()
scene = bpy.context.scene
for obj in list(scene.objects):
    bpy.data.objects.remove(obj, do_unlink=True)

bpy.ops.mesh.primitive_plane_add(size=1, location=(-1.5, 0, 0.5))
square = bpy.context.active_object
square.name = "Square"
material = bpy.data.materials.new("BlackMirror")
material.use_nodes = True
bsdf = material.node_tree.nodes["Principled BSDF"]
bsdf.inputs["Base Color"].default_value = (0, 0, 0, 1)
bsdf.inputs["Metallic"].default_value = 1.0
bsdf.inputs["Roughness"].default_value = 0.0
square.data.materials.append(material)
square.keyframe_insert("location", frame=1)
square.location.x = 1.5
square.keyframe_insert("location", frame=13)
for curve in square.animation_data.action.fcurves:
    for key in curve.keyframe_points:
        key.interpolation = "LINEAR"

# A spinner out of the square's rows: a 0.6 x 0.2 bar at (1.4, 0.75) turning about Z from 0 at
# frame 5 to 90 degrees at frame 9 (45 at frame 7, 22.5 per frame), for the export's rotation keys.
bpy.ops.mesh.primitive_plane_add(size=0.2, location=(1.4, 0.75, 0.5))
spinner = bpy.context.active_object
spinner.name = "Spinner"
spinner.scale = (3, 1, 1)
spinner.data.materials.append(material)
spinner.keyframe_insert("rotation_euler", frame=5)
spinner.rotation_euler.z = math.radians(90)
spinner.keyframe_insert("rotation_euler", frame=9)
for curve in spinner.animation_data.action.fcurves:
    for key in curve.keyframe_points:
        key.interpolation = "LINEAR"

# A shape key sliding a strip: x in [-1.5, -0.5], y in [-0.95, -0.55] at z = 0.5, its key "Slide"
# moving every vertex +1 along X, the key's value 0 at frame 5 and 1 at frame 9 (LINEAR): 0.25
# units per frame, the strip at x in [-1, 0] at frame 7. The object stands still: only its
# shape moves.
bpy.ops.mesh.primitive_plane_add(size=1, location=(-1.0, -0.75, 0.5))
strip = bpy.context.active_object
strip.name = "Strip"
strip.scale = (1, 0.4, 1)
bpy.ops.object.transform_apply(location=False, rotation=False, scale=True)
strip.data.materials.append(material)
strip.shape_key_add(name="Basis")
slide = strip.shape_key_add(name="Slide")
for point in slide.data:
    point.co.x += 1.0
slide.value = 0.0
slide.keyframe_insert("value", frame=5)
slide.value = 1.0
slide.keyframe_insert("value", frame=9)
for curve in strip.data.shape_keys.animation_data.action.fcurves:
    for key in curve.keyframe_points:
        key.interpolation = "LINEAR"

camera_data = bpy.data.cameras.new("Camera")
camera_data.type = "ORTHO"
camera_data.ortho_scale = 4.0
camera = bpy.data.objects.new("Camera", camera_data)
camera.location = (0, 0, 2)
scene.collection.objects.link(camera)
scene.camera = camera

world = scene.world or bpy.data.worlds.new("World")
scene.world = world
world.use_nodes = True
background = world.node_tree.nodes["Background"]
background.inputs["Color"].default_value = (1, 1, 1, 1)
background.inputs["Strength"].default_value = 1.0

scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 128, 64, 100
scene.render.fps, scene.render.fps_base = 24, 1.0
scene.frame_start, scene.frame_end = 1, 13
scene.veach.use_cycles_settings = False
scene.veach.samples = 256
scene.veach.integrator = "pt"
scene.veach.filter_type = "box"
scene.render.filter_size = 1.0
scene.render.motion_blur_shutter = 0.5
scene.render.use_motion_blur = True
bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out_dir, "motion.blend"))
scene.render.use_motion_blur = False
bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out_dir, "still.blend"))

# Runs inside Blender (blender -b --factory-startup --python blender_scene.py -- OUT_DIR ADDONS_DIR):
# builds a small scene, exports it to OUT_DIR/scene.gltf exactly as the add-on does, renders it with
# the VEACH engine to OUT_DIR/blender.exr (multilayer: Combined and Depth), then renders again with
# a huge sample count and a simulated Esc after 0.5 s to check that cancel stops the render.
# Writes what it saw to OUT_DIR/blender.json for check_blender.py.
import json
import os
import sys
import time

import bpy

out_dir, addons_dir = sys.argv[sys.argv.index("--") + 1:][:2]
sys.path.insert(0, addons_dir)
import veach  # noqa: E402 (the add-on, linked into addons_dir by check_blender.py)

veach.register()

scene = bpy.context.scene
# The factory scene (a cube, a 1000 W point light, a camera) plus a floor and a sun, so light
# units of two light types and interreflection all take part.
bpy.ops.mesh.primitive_plane_add(size=20, location=(0, 0, -1))
# A red-orange cube, so that the channels differ and an RGB order mistake shows.
material = bpy.data.materials.new("Orange")
material.use_nodes = True
material.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.8, 0.3, 0.05, 1.0)
bpy.data.objects["Cube"].data.materials[0] = material
sun = bpy.data.lights.new("Sun", type="SUN")
sun.energy = 2.0
sun_object = bpy.data.objects.new("Sun", sun)
sun_object.rotation_euler = (0.6, 0.2, 0.3)
scene.collection.objects.link(sun_object)

scene.render.engine = "VEACH"
scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 64, 48, 100
scene.render.filter_size = 1.5
scene.veach.use_cycles_settings = False  # the Veach panel's own settings, as the CLI gets them
scene.veach.samples = 32
scene.veach.integrator = "pt"
scene.veach.seed = 3
scene.veach.filter_type = "blackman-harris"
bpy.context.view_layer.use_pass_z = True

# The factory World's grey would light the add-on's render but not the CLI's (glTF has no World).
scene.world = None
veach.gltf_export.export_frame_gltf(bpy.context.evaluated_depsgraph_get(), os.path.join(out_dir, "scene.gltf"))

scene.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
scene.render.image_settings.color_depth = "32"
scene.render.filepath = os.path.join(out_dir, "blender.exr")
t0 = time.monotonic()
bpy.ops.render.render(write_still=True)
report = {"render_status": veach.engine.last_status, "render_seconds": time.monotonic() - t0}

# Cancel half a second into the render (Esc's test_break() cannot be simulated from Python; the
# add-on's external_cancel hook takes the same path).
scene.veach.samples = int(os.environ.get("VEACH_TEST_CANCEL_SPP", 1 << 20))
deadline = [0.0]
veach.engine.external_cancel = lambda: time.monotonic() > deadline[0]
scene.render.filepath = os.path.join(out_dir, "cancelled.exr")
t0 = time.monotonic()
deadline[0] = t0 + 0.5
bpy.ops.render.render(write_still=False)
report["cancel_status"] = veach.engine.last_status
report["cancel_seconds"] = time.monotonic() - t0

# The panels a user expects show for the engine (Blender's own, registered as other engines do).
report["panels_missing"] = [name for name in (
    "RENDER_PT_format", "RENDER_PT_output", "RENDER_PT_frame_range", "RENDER_PT_color_management",
    "DATA_PT_lens", "DATA_PT_camera", "EEVEE_MATERIAL_PT_surface", "EEVEE_WORLD_PT_surface",
    "DATA_PT_EEVEE_light", "VEACH_PT_passes", "VEACH_PT_settings")
    if "VEACH" not in getattr(bpy.types, name).COMPAT_ENGINES]

# The stats line before any pass is done, and after.
report["progress_lines"] = [veach.engine.progress_line("pt", 0.0, 0.0), veach.engine.progress_line("pt", 0.5, 3.2)]

with open(os.path.join(out_dir, "blender.json"), "w") as f:
    json.dump(report, f)

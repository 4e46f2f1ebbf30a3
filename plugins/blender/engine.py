# The render engine: F12, Render Animation, `blender -b file.blend -E VEACH -f 1` and `-a`.
#
# Blender hands render() the depsgraph of one frame, evaluated for rendering. gltf_export walks
# it into a glTF file in a temporary folder (every object instance as it is at that frame:
# modifiers, poses, shape keys, instances; the scene camera; Blender's lights) and world.py turns
# the World into the library's environment options; libveach loads both and renders on its own
# thread (veachRenderAsync) while this thread reports progress and passes Esc (test_break) on as
# a cancel. Pixels come back scene-linear and go into the RenderResult untouched: Blender's
# colour management then applies the user's view transform. What the export could not carry, and
# the library's own scene warnings, are reported through self.report, one WARNING per kind.
import os
import tempfile
import time

import bpy
import numpy as np

from . import gltf_export, library, world
from .properties import VeachSceneSettings  # noqa: F401 (scene.veach's type)

# The outcome of the last render in this Blender session ("done", "cancelled", "failed: ..."),
# for scripts and tests: Blender's render operator does not report an engine's cancel.
last_status = ""

# Besides Esc: a callable returning True to cancel the running render, for scripts and farm
# managers (a deadline, a job kill). Blender's own test_break() cannot be overridden from Python.
external_cancel = None


def addon_preferences(context):
    addon = context.preferences.addons.get(__package__)
    return addon.preferences if addon else None


def render_size(scene):
    scale = scene.render.resolution_percentage / 100.0
    return max(1, int(scene.render.resolution_x * scale)), max(1, int(scene.render.resolution_y * scale))


class VeachRenderEngine(bpy.types.RenderEngine):
    bl_idname = "VEACH"
    bl_label = "Veach"
    bl_use_preview = False
    bl_use_postprocess = True

    def update_render_passes(self, scene=None, renderlayer=None):
        self.register_pass(scene, renderlayer, "Combined", 4, "RGBA", "COLOR")
        if renderlayer.use_pass_z:
            self.register_pass(scene, renderlayer, "Depth", 1, "Z", "VALUE")

    def render(self, depsgraph):
        global last_status
        scene = depsgraph.scene_eval
        width, height = render_size(scene)
        try:
            with tempfile.TemporaryDirectory(prefix="veach_blender_") as tmp:
                self.update_stats("", "Veach | Exporting the scene")
                path = os.path.join(tmp, "frame.gltf")
                export = gltf_export.export_frame_gltf(depsgraph, path, width, height)
                options = {"spot_falloff": "blender", "allow_external_files": 1}
                options.update(world.environment_options(scene.world, export, tmp))
                for message in export.warnings.values():
                    self.report({"WARNING"}, f"Veach: {message}")
                if os.environ.get("VEACH_BLENDER_KEEP_EXPORT"):  # for debugging an export
                    import shutil
                    shutil.copytree(tmp, os.environ["VEACH_BLENDER_KEEP_EXPORT"], dirs_exist_ok=True)
                last_status = self.render_scene(scene, depsgraph.view_layer, path, options, export, width, height)
        except Exception as e:  # a failed render must not take Blender down: report it
            last_status = f"failed: {e}"
            self.report({"ERROR"}, f"Veach: {e}")

    def render_scene(self, scene, view_layer, path, scene_options, export, width, height):
        prefs = addon_preferences(bpy.context)
        lib = library.load(prefs.library_path if prefs else "")
        job = library.Render(lib, path, scene_options)
        try:
            for line in job.scene_string("warnings").splitlines():
                if line.strip():
                    self.report({"WARNING"}, f"Veach: {line.strip()}")
            settings = scene.veach
            job.set("width", width)
            job.set("height", height)
            job.set("spp", settings.samples)
            job.set("time_limit", float(settings.time_limit))
            job.set("integrator", settings.integrator)
            job.set("max_depth", settings.max_depth)
            job.set("seed", settings.seed)
            job.set("threads", render_threads(scene))
            job.set("filter", settings.filter_type)
            job.set("filter_width", float(scene.render.filter_size))
            if export.camera_name and export.camera_name in job.camera_names():
                job.set("camera", export.camera_name)
            want_depth = bool(view_layer.use_pass_z)
            job.set("aovs", 1 if want_depth else 0)

            job.start()
            cancelled = False
            started = time.monotonic()
            while job.wait(100) == library.STATUS_RUNNING:
                if not cancelled and (self.test_break() or (external_cancel and external_cancel())):
                    job.cancel()
                    cancelled = True
                fraction = job.get_float("progress")
                eta = job.get_float("eta_seconds")
                self.update_progress(fraction)
                self.update_stats("", f"Veach | {settings.integrator} | {int(fraction * 100)}% | "
                                      f"{time.monotonic() - started:.1f} s, ETA {eta:.1f} s")
            status = job.wait(0)
            if status == library.STATUS_CANCELLED:
                # Esc: Blender discards the result; a cancel from elsewhere keeps the partial image.
                if self.test_break():
                    return "cancelled"
            self.write_result(job, view_layer.name, width, height, want_depth)
            return "cancelled" if status == library.STATUS_CANCELLED else "done"
        finally:
            job.close()

    def write_result(self, job, layer_name, width, height, want_depth):
        w, h = job.get_int("result_width"), job.get_int("result_height")
        # Blender calls render() once per view layer: fill that one.
        result = self.begin_result(0, 0, width, height, layer=layer_name)
        layer = result.layers[0]
        if (w, h) == (width, height):
            layer.passes["Combined"].rect = read_pass(job, "combined", w, h)
            if want_depth and "Depth" in layer.passes:
                layer.passes["Depth"].rect = read_pass(job, "depth", w, h)[:, :1]
        self.end_result(result)


def read_pass(job, name, width, height):
    """The pass as Blender wants it: (pixels, 4) float32, rows from the bottom up."""
    pixels = np.empty((height, width, 4), dtype=np.float32)
    job.get_pass(name, pixels.ctypes.data)
    return np.ascontiguousarray(pixels[::-1]).reshape(-1, 4)


def render_threads(scene):
    if scene.veach.threads > 0:
        return scene.veach.threads
    if scene.render.threads_mode == "FIXED":
        return scene.render.threads
    return 0


def get_panels():
    """Blender's own panels that make sense for this engine (output, dimensions, colour
    management, film filter size)."""
    keep = {"RENDER_PT_format", "RENDER_PT_frame_range", "RENDER_PT_output", "RENDER_PT_color_management",
            "RENDER_PT_color_management_curves", "VIEWLAYER_PT_layer_passes", "RENDER_PT_post_processing"}
    return [p for p in bpy.types.Panel.__subclasses__()
            if getattr(p, "COMPAT_ENGINES", None) is not None and p.__name__ in keep]


class VEACH_PT_settings(bpy.types.Panel):
    bl_label = "Veach"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    COMPAT_ENGINES = {"VEACH"}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        settings = context.scene.veach
        layout.prop(settings, "integrator")
        layout.prop(settings, "samples")
        layout.prop(settings, "time_limit")
        layout.prop(settings, "max_depth")
        layout.prop(settings, "seed")
        layout.prop(settings, "threads")
        layout.prop(settings, "filter_type")
        layout.prop(context.scene.render, "filter_size")


def register():
    bpy.utils.register_class(VeachRenderEngine)
    bpy.utils.register_class(VEACH_PT_settings)
    for panel in get_panels():
        panel.COMPAT_ENGINES.add("VEACH")


def unregister():
    for panel in get_panels():
        panel.COMPAT_ENGINES.discard("VEACH")
    bpy.utils.unregister_class(VEACH_PT_settings)
    bpy.utils.unregister_class(VeachRenderEngine)

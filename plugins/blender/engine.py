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
import math
import os
import tempfile
import time

import bpy
import numpy as np

from . import gltf_export, library, render_settings, world
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


# Blender's passes: (name, channels, channel ids, type, libveach pass, enabled for a view layer).
PASSES = [
    ("Combined", 4, "RGBA", "COLOR", "combined", lambda layer: True),
    ("Depth", 1, "Z", "VALUE", "depth", lambda layer: layer.use_pass_z),
    ("Normal", 3, "XYZ", "VECTOR", "normal", lambda layer: layer.use_pass_normal),
    ("Denoising Albedo", 3, "RGB", "COLOR", "albedo", lambda layer: layer.veach.use_pass_denoising_data),
    ("Denoising Normal", 3, "XYZ", "VECTOR", "normal", lambda layer: layer.veach.use_pass_denoising_data),
    ("Variance", 3, "RGB", "COLOR", "variance", lambda layer: layer.veach.use_pass_variance),
    ("Sample Count", 1, "X", "VALUE", "samples", lambda layer: layer.veach.use_pass_sample_count),
]
AOV_PASSES = {"depth", "normal", "albedo"}  # the library records these only with aovs = 1
# When denoising, Denoising Data is the denoiser's own guides (of the first surface seen, through
# mirrors and smooth glass), with Cycles' Denoising Depth and Noisy Image beside them.
DENOISING_SOURCES = {"Denoising Albedo": "denoising_albedo", "Denoising Normal": "denoising_normal"}
DENOISING_EXTRA = [
    ("Noisy Image", 4, "RGBA", "COLOR", "noisy", lambda layer: layer.veach.use_pass_denoising_data),
    ("Denoising Depth", 1, "Z", "VALUE", "denoising_depth", lambda layer: layer.veach.use_pass_denoising_data),
]
NORMAL_PASSES = {"normal", "denoising_normal"}  # glTF's Y up, turned back to Blender's Z up

# The library's scene warnings that repeat, once per light, what the export reported once for the
# kind: (export warning kind, text of the library's line).
REPORTED_BY_EXPORT = [("area light spread", "area light spread of")]


def library_warnings(text, export):
    """The library's scene warnings worth showing: one per line, none the export already gave."""
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    return [line for line in lines
            if not any(kind in export.warnings and words in line for kind, words in REPORTED_BY_EXPORT)]


def enabled_passes(view_layer, denoise=False):
    passes = PASSES
    if denoise:
        passes = [(p[0], p[1], p[2], p[3], DENOISING_SOURCES.get(p[0], p[4]), p[5]) for p in PASSES] + DENOISING_EXTRA
    return [p for p in passes if p[5](view_layer)]


def progress_line(integrator, fraction, eta):
    """The stats line: it changes only when the whole percent or the whole second of the ETA does,
    and the ETA is unknown until the library has finished a pass of samples."""
    eta_text = "unknown" if fraction <= 0 or eta < 0 or eta != eta else f"{eta:.0f} s"
    return f"Veach | {integrator} | {int(fraction * 100)}% | ETA {eta_text}"


class VeachRenderEngine(bpy.types.RenderEngine):
    bl_idname = "VEACH"
    bl_label = "Veach"
    bl_use_preview = False
    bl_use_postprocess = True

    def update_render_passes(self, scene=None, renderlayer=None):
        for name, channels, ids, kind, _, _ in enabled_passes(renderlayer, render_settings.denoising(scene)):
            self.register_pass(scene, renderlayer, name, channels, ids, kind)

    def render(self, depsgraph):
        global last_status
        scene = depsgraph.scene_eval
        width, height = render_settings.full_size(scene)
        try:
            with tempfile.TemporaryDirectory(prefix="veach_blender_") as tmp:
                self.update_stats("", "Veach | Exporting the scene")
                path = os.path.join(tmp, "frame.gltf")
                motion = self.motion_steps(depsgraph, scene) if scene.render.use_motion_blur else None
                export = gltf_export.export_frame_gltf(depsgraph, path, width, height, motion)
                options = {"spot_falloff": "blender", "default_material": "blender", "allow_external_files": 1}
                if export.motion:
                    # The exported frame is time 0 of its motion animation; the shutter in seconds.
                    options["time"] = 0.0
                    options["shutter"] = "%r,%r" % (motion[0][0], motion[0][-1])
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

    def motion_steps(self, depsgraph, scene):
        """Motion blur's steps: the depsgraph evaluated at the shutter's open, middle and close
        (Blender's Motion Blur shutter, in frames, placed by Cycles' Position), each step's world
        matrices of meshes and the camera and each object's evaluated shape
        (gltf_export.world_matrices), and the times in seconds from the frame; the depsgraph is
        left at the frame."""
        shutter = scene.render.motion_blur_shutter
        position = getattr(getattr(scene, "cycles", None), "motion_blur_position", "CENTER")
        open_, close = {"START": (0.0, shutter), "END": (-shutter, 0.0)}.get(position, (-shutter / 2, shutter / 2))
        frame, subframe = scene.frame_current, scene.frame_subframe
        seconds_per_frame = scene.render.fps_base / scene.render.fps
        times, steps, shapes = [], [], []
        for k in range(3):
            offset = open_ + (close - open_) * k / 2
            at = frame + subframe + offset
            whole = math.floor(at)
            self.frame_set(int(whole), at - whole)
            shapes.append({})
            steps.append(gltf_export.world_matrices(depsgraph, shapes[-1]))
            times.append(offset * seconds_per_frame)
        self.frame_set(frame, subframe)
        return times, steps, shapes

    def render_scene(self, scene, view_layer, path, scene_options, export, width, height):
        prefs = addon_preferences(bpy.context)
        veach = library.module(prefs.library_path if prefs else "")
        with veach.Scene(path, **scene_options) as loaded, veach.Render(loaded) as job:
            for line in library_warnings(loaded.get("warnings"), export):
                self.report({"WARNING"}, f"Veach: {line}")
            options = render_settings.render_options(scene)
            job.set("width", width)
            job.set("height", height)
            for name, value in options.items():
                job.set(name, value)
            job.set("threads", render_threads(scene))
            if export.camera_name and export.camera_name in loaded.cameras:
                job.set("camera", export.camera_name)
            passes = enabled_passes(view_layer, bool(options["denoise"]))
            job.set("aovs", 1 if any(p[4] in AOV_PASSES for p in passes) else 0)

            job.set("snapshots", 1)  # the film so far at every pass, shown while rendering
            job.start()
            cancelled = False
            shown = None
            last_preview = time.monotonic()
            while job.wait(0.1) == veach.RUNNING:
                if time.monotonic() - last_preview >= 1.0:
                    self.show_progress(job, veach, view_layer.name, render_settings.region(scene), width, height)
                    last_preview = time.monotonic()
                if not cancelled and (self.test_break() or (external_cancel and external_cancel())):
                    job.cancel()
                    cancelled = True
                fraction = job.get("progress")
                line = progress_line(options["integrator"], fraction, job.get("eta_seconds"))
                if line != shown:
                    self.update_progress(fraction)
                    self.update_stats("", line)
                    shown = line
            status = job.wait(0)
            if status == veach.CANCELLED:
                # Esc: Blender discards the result; a cancel from elsewhere keeps the partial image.
                if self.test_break():
                    return "cancelled"
            for line in job.get("result_warnings").splitlines():
                if line.strip():
                    self.report({"WARNING"}, f"Veach: {line.strip()}")
            self.write_result(job, view_layer.name, passes, render_settings.region(scene), width, height)
            return "cancelled" if status == veach.CANCELLED else "done"

    def show_progress(self, job, veach, layer_name, region, width, height):
        """The Combined pass so far into the render result (Blender redraws it): the library keeps
        the film at each pass boundary while the render runs; none before the first pass."""
        try:
            pixels = job.get_pass("combined")
        except veach.InvalidOperation:
            return
        h, w = pixels.shape[:2]
        if (w, h) != (width, height):
            return
        x, y, rw, rh = region or (0, 0, width, height)
        result = self.begin_result(0, 0, rw, rh, layer=layer_name)
        rows = np.ascontiguousarray(pixels[y:y + rh, x:x + rw][::-1]).reshape(-1, 4)
        combined = result.layers[0].passes.get("Combined")
        if combined is not None:
            combined.rect = rows
        self.end_result(result)

    def write_result(self, job, layer_name, passes, region, width, height):
        w, h = job.get("result_width"), job.get("result_height")
        x, y, rw, rh = region or (0, 0, width, height)
        # Blender calls render() once per view layer: fill that one. A border render's result is
        # the region's size.
        result = self.begin_result(0, 0, rw, rh, layer=layer_name)
        layer = result.layers[0]
        if (w, h) == (width, height):
            for name, channels, _, _, source, _ in passes:
                if name in layer.passes:
                    pixels = job.get_pass(source)[y:y + rh, x:x + rw]  # (h, w, 4) float32, top row first
                    if source in NORMAL_PASSES:  # the library's world is glTF's (Y up), Blender's is Z up
                        pixels = np.stack([pixels[..., 0], -pixels[..., 2], pixels[..., 1], pixels[..., 3]], axis=-1)
                    rows = np.ascontiguousarray(pixels[::-1]).reshape(-1, 4)
                    layer.passes[name].rect = rows[:, :channels]
        self.end_result(result)


def render_threads(scene):
    if scene.veach.threads > 0:
        return scene.veach.threads
    if scene.render.threads_mode == "FIXED":
        return scene.render.threads
    return 0


# Blender's own panels that apply to this engine as they are: the documented RenderEngine way
# (every panel Blender's internal engines share), plus EEVEE's node-based material, world and light
# panels, which show the shader nodes the add-on converts (as Cycles' own panels would).
SHARED_PANELS = {
    "EEVEE_MATERIAL_PT_context_material", "EEVEE_MATERIAL_PT_surface", "EEVEE_MATERIAL_PT_volume",
    "EEVEE_WORLD_PT_surface", "DATA_PT_EEVEE_light", "DATA_PT_spot", "DATA_PT_camera_dof",
    "RENDER_PT_format", "RENDER_PT_frame_range", "RENDER_PT_output", "RENDER_PT_color_management",
    "RENDER_PT_color_management_curves", "RENDER_PT_post_processing", "RENDER_PT_stamp",
    "VIEWLAYER_PT_layer", "RENDER_PT_encoding", "RENDER_PT_format_presets",
}
EXCLUDED_PANELS = {"VIEWLAYER_PT_filter", "VIEWLAYER_PT_layer_passes"}  # Veach draws its own passes


def get_panels():
    panels = []
    for panel in bpy.types.Panel.__subclasses__():
        engines = getattr(panel, "COMPAT_ENGINES", None)
        if engines is None or panel.__name__ in EXCLUDED_PANELS:
            continue
        if "BLENDER_RENDER" in engines or panel.__name__ in SHARED_PANELS:
            panels.append(panel)
    return panels


class VeachPanel:
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    COMPAT_ENGINES = {"VEACH"}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES


class VEACH_PT_settings(VeachPanel, bpy.types.Panel):
    bl_label = "Veach"
    bl_context = "render"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        settings = context.scene.veach
        layout.prop(settings, "integrator")
        layout.prop(settings, "threads")
        layout.prop(settings, "use_cycles_settings")
        column = layout.column()
        column.active = not render_settings.uses_cycles(context.scene)
        for name in ("samples", "time_limit", "noise_threshold", "use_denoising", "max_depth", "seed",
                     "use_animated_seed", "filter_type"):
            column.prop(settings, name)
        if render_settings.uses_cycles(context.scene):
            # Cycles' own Render > Sampling > Denoise switch, which its settings bring along.
            layout.prop(context.scene.cycles, "use_denoising", text="Denoise")
        column.prop(context.scene.render, "filter_size")
        layout.prop(context.scene.render, "film_transparent")


class VEACH_PT_passes(VeachPanel, bpy.types.Panel):
    bl_label = "Passes"
    bl_context = "view_layer"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        view_layer = context.view_layer
        layout.prop(view_layer, "use_pass_combined")
        layout.prop(view_layer, "use_pass_z")
        layout.prop(view_layer, "use_pass_normal")
        for name in ("use_pass_denoising_data", "use_pass_variance", "use_pass_sample_count"):
            layout.prop(view_layer.veach, name)


classes = (VeachRenderEngine, VEACH_PT_settings, VEACH_PT_passes)


def register():
    for c in classes:
        bpy.utils.register_class(c)
    for panel in get_panels():
        panel.COMPAT_ENGINES.add("VEACH")


def unregister():
    for panel in get_panels():
        panel.COMPAT_ENGINES.discard("VEACH")
    for c in reversed(classes):
        bpy.utils.unregister_class(c)

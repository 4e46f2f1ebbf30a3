# The settings scripts and farm jobs set: scene.veach.samples etc., and the add-on preference
# that says where libveach is.
import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty

INTEGRATORS = [
    ("auto", "Automatic", "Bidirectional path tracing with the strategies this scene needs, chosen per render"),
    ("bdpt", "Bidirectional", "Bidirectional path tracing: every strategy, MIS-weighted"),
    ("pt", "Path Tracing", "Unidirectional path tracing with next-event estimation and MIS"),
    ("lt", "Light Tracing", "Paths from the lights, splatted onto the film"),
]

FILTERS = [
    ("blackman-harris", "Blackman-Harris", "Cycles' default pixel filter"),
    ("gaussian", "Gaussian", "Gaussian pixel filter"),
    ("box", "Box", "Box pixel filter"),
]


class VeachSceneSettings(bpy.types.PropertyGroup):
    use_cycles_settings: BoolProperty(
        name="Use Cycles Settings", default=True,
        description="Take samples, time limit, noise threshold, denoise, seed (and animated seed), max bounces and "
                    "pixel filter from the scene's Cycles settings, so that a .blend set up for Cycles renders "
                    "with what it asks for; off: the Veach settings below")
    samples: IntProperty(name="Samples", description="Samples per pixel", default=64, min=1, soft_max=4096)
    time_limit: FloatProperty(name="Time Limit", description="Stop after this many seconds (0: no limit)",
                              default=0.0, min=0.0, subtype="TIME_ABSOLUTE", unit="TIME_ABSOLUTE")
    noise_threshold: FloatProperty(
        name="Noise Threshold", default=0.0, min=0.0, soft_max=0.1, precision=4,
        description="Adaptive sampling: a pixel stops once its estimated relative error is below this (0: off, "
                    "every pixel gets the samples)")
    use_denoising: BoolProperty(
        name="Denoise", default=False,
        description="Denoise the render with Veach's own denoiser (feature-guided regression; biased, its "
                    "error vanishing as samples grow); the noisy image is the Noisy Image pass of Denoising Data")
    integrator: EnumProperty(name="Integrator", items=INTEGRATORS, default="auto")
    max_depth: IntProperty(name="Max Bounces", description="Maximum scattering events on a path",
                           default=64, min=0, soft_max=256)
    threads: IntProperty(name="Threads",
                         description="Render threads (0: Blender's Threads setting when fixed, else all cores)",
                         default=0, min=0, soft_max=256)
    seed: IntProperty(name="Seed", description="Random seed (the image is identical for any thread count)",
                      default=0, min=0)
    use_animated_seed: BoolProperty(name="Animated Seed", default=False,
                                    description="A different seed on every frame (Cycles' option of the name)")
    filter_type: EnumProperty(name="Pixel Filter", items=FILTERS, default="blackman-harris",
                              description="Reconstruction filter; its width is Blender's Film > Filter Size")


class VeachViewLayerSettings(bpy.types.PropertyGroup):
    """Passes beyond Blender's own Depth (Z) and Normal switches of the view layer."""
    use_pass_denoising_data: BoolProperty(name="Denoising Data", default=False,
                                          description="Denoising Albedo and Denoising Normal (first-hit albedo "
                                                      "and normal, for the compositor's Denoise node); when "
                                                      "denoising, the denoiser's own (seen through mirrors and "
                                                      "smooth glass), Denoising Depth and the Noisy Image")
    use_pass_variance: BoolProperty(name="Variance", default=False,
                                    description="Variance of each pixel's mean, per channel")
    use_pass_sample_count: BoolProperty(name="Sample Count", default=False,
                                        description="The samples averaged into each pixel (fewer where adaptive "
                                                    "sampling stopped it)")


class VeachPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__
    library_path: StringProperty(name="libveach", subtype="FILE_PATH",
                                 description="Path to libveach.so (the VEACH_LIBRARY environment variable wins)")

    def draw(self, context):
        self.layout.prop(self, "library_path")


classes = (VeachSceneSettings, VeachViewLayerSettings, VeachPreferences)


def register():
    for c in classes:
        bpy.utils.register_class(c)
    bpy.types.Scene.veach = PointerProperty(type=VeachSceneSettings)
    bpy.types.ViewLayer.veach = PointerProperty(type=VeachViewLayerSettings)


def unregister():
    del bpy.types.ViewLayer.veach
    del bpy.types.Scene.veach
    for c in reversed(classes):
        bpy.utils.unregister_class(c)

# The settings scripts and farm jobs set: scene.veach.samples etc., and the add-on preference
# that says where libveach is.
import bpy
from bpy.props import EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty

INTEGRATORS = [
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
    samples: IntProperty(name="Samples", description="Samples per pixel", default=64, min=1, soft_max=4096)
    time_limit: FloatProperty(name="Time Limit", description="Stop after this many seconds (0: no limit)",
                              default=0.0, min=0.0, subtype="TIME_ABSOLUTE", unit="TIME_ABSOLUTE")
    integrator: EnumProperty(name="Integrator", items=INTEGRATORS, default="bdpt")
    max_depth: IntProperty(name="Max Bounces", description="Maximum scattering events on a path",
                           default=64, min=0, soft_max=256)
    threads: IntProperty(name="Threads",
                         description="Render threads (0: Blender's Threads setting when fixed, else all cores)",
                         default=0, min=0, soft_max=256)
    seed: IntProperty(name="Seed", description="Random seed (the image is identical for any thread count)",
                      default=0, min=0)
    filter_type: EnumProperty(name="Pixel Filter", items=FILTERS, default="blackman-harris",
                              description="Reconstruction filter; its width is Blender's Film > Filter Size")


class VeachPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__
    library_path: StringProperty(name="libveach", subtype="FILE_PATH",
                                 description="Path to libveach.so (the VEACH_LIBRARY environment variable wins)")

    def draw(self, context):
        self.layout.prop(self, "library_path")


classes = (VeachSceneSettings, VeachPreferences)


def register():
    for c in classes:
        bpy.utils.register_class(c)
    bpy.types.Scene.veach = PointerProperty(type=VeachSceneSettings)


def unregister():
    del bpy.types.Scene.veach
    for c in reversed(classes):
        bpy.utils.unregister_class(c)

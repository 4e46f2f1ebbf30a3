# Veach for Blender: a RenderEngine that exports the evaluated scene with Blender's own glTF
# exporter and renders it through libveach (the C API, by ctypes). Install: copy or link this
# folder as `veach` into Blender's add-ons folder (see README.md "Blender add-on").
bl_info = {
    "name": "Veach",
    "author": "Veach developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Render Properties > Render Engine > Veach",
    "description": "Physically based path tracing through libveach",
    "category": "Render",
}

if "bpy" in locals():
    import importlib
    importlib.reload(properties)  # noqa: F821 (re-registration while developing)
    importlib.reload(library)  # noqa: F821
    importlib.reload(engine)  # noqa: F821
else:
    from . import properties, library, engine

import bpy


def register():
    properties.register()
    engine.register()


def unregister():
    engine.unregister()
    properties.unregister()

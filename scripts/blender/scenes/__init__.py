"""Scene definitions for make_scene.py: one module per scene, named as the scene.

A scene module has a docstring saying what the scene exercises and:
  build()       makes the scene in the current (empty) Blender file with scene_kit's helpers;
                the render resolution is already set, so the camera's aspect follows it
  RESOLUTION    (width, height) of its references, which is what the tests render at
  SPP           samples per pixel of its Cycles reference
  FRAMES        optional (first, last): an animated scene's frame range, every frame of which
                its references are rendered at by default
  REFERENCE_FRAMES optional tuple of frames within FRAMES: the only frames rendered by default
  BLEND_SAMPLES optional: the .blend is saved with the reference's Cycles settings at this many
                samples (what the Blender add-on, following Cycles' settings, renders it with)
  VEACH_ARGS    optional list of `veach render` arguments needed to see what Cycles sees (the
                World, which glTF does not carry: ["--env", "sky.hdr"], paths relative to the
                scene's folder); written to NAME.cycles.json
"""
import importlib
import os
import pkgutil


def names():
    folder = os.path.dirname(os.path.abspath(__file__))
    return sorted(m.name for m in pkgutil.iter_modules([folder]) if not m.name.startswith("_"))


def load(name):
    if name not in names():
        raise KeyError("unknown scene '%s' (scenes: %s)" % (name, ", ".join(names())))
    return importlib.import_module("scenes." + name)

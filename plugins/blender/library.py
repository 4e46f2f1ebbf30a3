# libveach for the add-on: the Python module `veach` (plugins/python, installed in the prefix's
# Python site folder), loaded by path under a name of its own, since the add-on's own package is
# also called `veach`. Where it is looked for, in order: $VEACH_PYTHON (a folder holding veach/),
# the prefix the add-on is installed in (PREFIX/share/veach/blender/veach -> PREFIX/lib/python3.X/
# dist-packages), the prefix of the library named by the add-on's "libveach" preference (an add-on
# installed from a zip lives in Blender's add-ons folder, away from any prefix: PREFIX/lib/
# libveach.so.0 -> PREFIX/lib/python3.X/dist-packages), the repository the add-on folder belongs to
# (plugins/blender -> plugins/python), then Python's own path.
import glob
import importlib.util
import os
import sys

_NAME = "veach_python_module"


def _candidates(preference_path=""):
    here = os.path.dirname(os.path.realpath(__file__))
    folders = []
    if os.environ.get("VEACH_PYTHON"):
        folders.append(os.environ["VEACH_PYTHON"])
    prefix = os.path.normpath(os.path.join(here, "..", "..", "..", ".."))
    folders += sorted(glob.glob(os.path.join(prefix, "lib", "python3*", "dist-packages")))
    if preference_path:
        lib = os.path.dirname(os.path.realpath(_abspath(preference_path)))
        folders += sorted(glob.glob(os.path.join(lib, "python3*", "dist-packages")))
    folders.append(os.path.normpath(os.path.join(here, "..", "python")))
    folders += [p for p in sys.path if p]
    return [os.path.join(f, "veach", "__init__.py") for f in folders]


def module(preference_path=""):
    """The module, loaded once; libveach from VEACH_LIBRARY, the add-on preference "libveach", a
    libveach.so* beside the add-on, the prefix, then the system (the module's own search)."""
    if _NAME in sys.modules:
        return sys.modules[_NAME]
    for path in _candidates(preference_path):
        if not os.path.isfile(path) or os.path.dirname(path) == os.path.dirname(os.path.realpath(__file__)):
            continue
        spec = importlib.util.spec_from_file_location(_NAME, path)
        mod = importlib.util.module_from_spec(spec)
        sys.modules[_NAME] = mod
        try:
            spec.loader.exec_module(mod)
        except Exception:
            del sys.modules[_NAME]
            raise
        library = None
        if not os.environ.get("VEACH_LIBRARY"):  # which the module takes first
            here = os.path.dirname(os.path.realpath(__file__))
            beside = sorted(glob.glob(os.path.join(here, "libveach.so*")))
            library = (preference_path and _abspath(preference_path)) or (beside[0] if beside else None)
        mod.load_library(library)
        return mod
    raise RuntimeError("the Python module veach was not found; install Veach (make install) or set VEACH_PYTHON")


def _abspath(path):
    try:
        import bpy
        return bpy.path.abspath(path)
    except ImportError:
        return path

"""veach: the Veach renderer from Python, through libveach's C API (ctypes over veach.h).

    import veach
    image = veach.render("cornell.gltf", width=256, height=256, spp=64, seed=0, integrator="pt")
    image.shape, image.dtype            # (256, 256, 4) float32: the Combined pass, scene-linear

The same in steps, with options, progress, cancel and every pass:

    with veach.Scene("scene.glb", env_strength=0.5) as scene, veach.Render(scene, spp=256) as r:
        r.start(progress=lambda fraction, eta: print(f"{fraction:.0%}"))
        while r.wait(0.1) == veach.RUNNING:
            preview = r.get_pass("combined")   # the film so far
        depth = r.get_pass("depth")            # with aovs=1
        r.write("out.exr")

Options are the library's options table (Device.options(), veach.h): each name's type decides the
setter, so `spp=64` and `noise=0.01` go where they belong. Errors are exceptions carrying the
library's one-line message: InvalidArgument (also a ValueError), BadInput, OutputError,
Cancelled, InvalidOperation. Passes come back as H x W x 4 float32 numpy arrays written by the
library straight into the array's memory.
"""
import ctypes
import ctypes.util
import glob
import json
import os
import threading

import numpy as np

ABI_MAJOR = 0
ABI_MIN_MINOR = 8  # the options table (device query "options")

IDLE, RUNNING, DONE, CANCELLED, FAILED = 0, 1, 2, 3, 4


class VeachError(RuntimeError):
    """A failed call: `code` is veach.h's VeachError, the message the library's last error."""

    def __init__(self, code, message):
        super().__init__(message)
        self.code = code


class InvalidArgument(VeachError, ValueError):
    pass


class InvalidOperation(VeachError):
    pass


class BadInput(VeachError):
    pass


class OutputError(VeachError):
    pass


class Cancelled(VeachError):
    pass


_ERRORS = {1: InvalidArgument, 2: InvalidOperation, 3: BadInput, 4: OutputError, 5: Cancelled}

_lock = threading.Lock()
_lib = None


def _candidates(path=None):
    """Where libveach is looked for, in order: `path`, $VEACH_LIBRARY, the prefix this module is
    installed in (PREFIX/lib/python3.X/dist-packages/veach -> PREFIX/lib), the system."""
    here = os.path.dirname(os.path.realpath(__file__))
    paths = [p for p in (path, os.environ.get("VEACH_LIBRARY")) if p]
    prefix = os.path.normpath(os.path.join(here, "..", "..", "..", ".."))
    for libdir in ("lib", "lib64", "lib/*-linux-gnu"):
        paths += sorted(glob.glob(os.path.join(prefix, libdir, f"libveach.so.{ABI_MAJOR}")))
    found = ctypes.util.find_library("veach")
    paths.append(found or f"libveach.so.{ABI_MAJOR}")
    return paths


def _declare(lib):
    c = ctypes
    P = c.c_void_p
    S = c.POINTER(c.c_size_t)
    sigs = {
        "veachGetVersion": (c.c_int, []),
        "veachGetVersionString": (c.c_char_p, []),
        "veachGetLastError": (c.c_char_p, []),
        "veachGetLastErrorCode": (c.c_int, []),
        "veachNewDevice": (P, []),
        "veachReleaseDevice": (None, [P]),
        "veachGetDeviceInt": (c.c_int, [P, c.c_char_p, c.POINTER(c.c_longlong)]),
        "veachGetDeviceString": (c.c_int, [P, c.c_char_p, c.c_char_p, c.c_size_t, S]),
        "veachNewScene": (P, [P]),
        "veachReleaseScene": (None, [P]),
        "veachSetSceneInt": (c.c_int, [P, c.c_char_p, c.c_longlong]),
        "veachSetSceneFloat": (c.c_int, [P, c.c_char_p, c.c_double]),
        "veachSetSceneString": (c.c_int, [P, c.c_char_p, c.c_char_p]),
        "veachGetSceneInt": (c.c_int, [P, c.c_char_p, c.POINTER(c.c_longlong)]),
        "veachGetSceneFloat": (c.c_int, [P, c.c_char_p, c.POINTER(c.c_double)]),
        "veachGetSceneString": (c.c_int, [P, c.c_char_p, c.c_char_p, c.c_size_t, S]),
        "veachLoadSceneFile": (c.c_int, [P, c.c_char_p]),
        "veachLoadSceneMemory": (c.c_int, [P, c.c_void_p, c.c_size_t, c.c_char_p, c.c_char_p]),
        "veachGetSceneCameraCount": (c.c_int, [P]),
        "veachGetSceneCameraName": (c.c_char_p, [P, c.c_int]),
        "veachNewRender": (P, [P]),
        "veachReleaseRender": (None, [P]),
        "veachSetInt": (c.c_int, [P, c.c_char_p, c.c_longlong]),
        "veachSetFloat": (c.c_int, [P, c.c_char_p, c.c_double]),
        "veachSetString": (c.c_int, [P, c.c_char_p, c.c_char_p]),
        "veachGetInt": (c.c_int, [P, c.c_char_p, c.POINTER(c.c_longlong)]),
        "veachGetFloat": (c.c_int, [P, c.c_char_p, c.POINTER(c.c_double)]),
        "veachGetString": (c.c_int, [P, c.c_char_p, c.c_char_p, c.c_size_t, S]),
        "veachSetProgressFunction": (None, [P, c.c_void_p, c.c_void_p]),
        "veachRender": (c.c_int, [P]),
        "veachRenderAsync": (c.c_int, [P]),
        "veachWaitRender": (c.c_int, [P, c.c_int]),
        "veachGetRenderStatus": (c.c_int, [P]),
        "veachCancelRender": (None, [P]),
        "veachGetPass": (c.c_int, [P, c.c_char_p, c.c_void_p, c.c_size_t, c.c_size_t]),
        "veachWriteImage": (c.c_int, [P, c.c_char_p]),
    }
    for name, (res, args) in sigs.items():
        f = getattr(lib, name)
        f.restype = res
        f.argtypes = args


def load_library(path=None):
    """libveach, loaded once per process (from `path` if given the first time). Raises VeachError
    listing what was tried when none opens or none is recent enough."""
    global _lib
    with _lock:
        if _lib is not None:
            return _lib
        tried = []
        for candidate in _candidates(path):
            try:
                lib = ctypes.CDLL(candidate)
            except OSError as e:
                tried.append(f"{candidate} ({e})")
                continue
            lib.veachGetVersion.restype = ctypes.c_int
            version = lib.veachGetVersion()
            if version // 10000 != ABI_MAJOR or version // 100 % 100 < ABI_MIN_MINOR:
                tried.append(f"{candidate} (version {version // 10000}.{version // 100 % 100}, need "
                             f"{ABI_MAJOR}.{ABI_MIN_MINOR} or a later {ABI_MAJOR}.x)")
                continue
            _declare(lib)
            _lib = lib
            return lib
        raise VeachError(-1, "libveach not found; set VEACH_LIBRARY. Tried: " + "; ".join(tried))


def version():
    return load_library().veachGetVersionString().decode()


def _fail(lib):
    code = lib.veachGetLastErrorCode()
    message = (lib.veachGetLastError() or b"").decode(errors="replace")
    return _ERRORS.get(code, VeachError)(code, message)


def _check(lib, code):
    if code != 0:
        raise _fail(lib)


def _string(lib, getter, handle, name):
    length = ctypes.c_size_t(0)
    _check(lib, getter(handle, name.encode(), None, 0, ctypes.byref(length)))
    buffer = ctypes.create_string_buffer(length.value + 1)
    _check(lib, getter(handle, name.encode(), buffer, length.value + 1, None))
    return buffer.raw[:length.value].decode(errors="replace")


class Device:
    """The library's device: shared defaults, queries, and the options table."""

    def __init__(self, library=None):
        self.lib = load_library(library)
        self.handle = self.lib.veachNewDevice()
        if not self.handle:
            raise _fail(self.lib)
        self._options = None

    def string(self, name):
        return _string(self.lib, self.lib.veachGetDeviceString, self.handle, name)

    def options(self):
        """The options table: {(object, name): row} with type, default, min, max, choices, help,
        identity (shapes the image) and flag (the command's)."""
        if self._options is None:
            self._options = {(row["object"], row["name"]): row for row in json.loads(self.string("options"))}
        return self._options

    def option_type(self, obj, name):
        row = self.options().get((obj, name))
        return row["type"] if row else None

    def close(self):
        if getattr(self, "handle", None):
            self.lib.veachReleaseDevice(self.handle)
            self.handle = None

    def __del__(self):
        self.close()


_default_device = None


def default_device():
    global _default_device
    with _lock:
        if _default_device is None:
            _default_device = Device.__new__(Device)
    if not getattr(_default_device, "handle", None):
        _default_device.__init__()
    return _default_device


def _get(lib, getters, handle, kind, name):
    """One option or result through the getter its type calls for."""
    get_int, get_float, get_string = getters
    if kind == "string":
        return _string(lib, get_string, handle, name)
    v = ctypes.c_double() if kind == "float" else ctypes.c_longlong()
    _check(lib, (get_float if kind == "float" else get_int)(handle, name.encode(), ctypes.byref(v)))
    return v.value


def _set(lib, setters, handle, kind, name, value):
    """One option through the setter its type calls for (a result name or an unknown name falls to
    the value's own type, and the library says what is wrong)."""
    set_int, set_float, set_string = setters
    if kind is None:
        kind = "string" if isinstance(value, str) else "float" if isinstance(value, float) else "int"
    key = name.encode()
    if kind == "string":
        _check(lib, set_string(handle, key, str(value).encode()))
    elif kind == "float":
        _check(lib, set_float(handle, key, float(value)))
    else:
        if isinstance(value, float) and not value.is_integer():
            raise InvalidArgument(1, f"{name} is an int, not {value!r}")
        _check(lib, set_int(handle, key, int(value)))


class Scene:
    """A scene loaded from a file (or from bytes: Scene(data=b'...', format='glb')), with the scene
    options given as keywords (env_map, env_color, env_strength, time, variant, ...)."""

    def __init__(self, path=None, data=None, format=None, base_dir=None, device=None, **options):
        self.device = device or default_device()
        self.lib = lib = self.device.lib
        self.handle = lib.veachNewScene(self.device.handle)
        if not self.handle:
            raise _fail(lib)
        try:
            for name, value in options.items():
                self.set(name, value)
            if path is not None:
                _check(lib, lib.veachLoadSceneFile(self.handle, os.fsencode(path)))
            elif data is not None:
                buf = bytes(data)
                _check(lib, lib.veachLoadSceneMemory(self.handle, buf, len(buf), (format or "glb").encode(),
                                                     base_dir.encode() if base_dir else None))
            else:
                raise InvalidArgument(1, "Scene: give a path or data")
        except BaseException:
            self.close()
            raise

    def set(self, name, value):
        """A scene option; `time` after the load poses the scene again (a sequence)."""
        lib = self.lib
        _set(lib, (lib.veachSetSceneInt, lib.veachSetSceneFloat, lib.veachSetSceneString), self.handle,
             self.device.option_type("scene", name), name, value)

    def get(self, name):
        """A scene option or what the load found (triangles, cameras, features, warnings, ...)."""
        lib = self.lib
        kind = self.device.option_type("scene", name)
        if kind is None:
            kind = "string" if name in ("source", "features", "warnings", "info") else "int"
        return _get(lib, (lib.veachGetSceneInt, lib.veachGetSceneFloat, lib.veachGetSceneString), self.handle,
                    kind, name)

    @property
    def cameras(self):
        n = self.lib.veachGetSceneCameraCount(self.handle)
        return [self.lib.veachGetSceneCameraName(self.handle, i).decode() for i in range(max(n, 0))]

    @property
    def features(self):
        return [f for f in self.get("features").split("\n") if f]

    def info(self):
        """What the scene holds (as `veach info --json`): the file's scenes, variants and
        animations, cameras, lights by kind, triangles, instances, textures with sizes, features."""
        return json.loads(self.get("info"))

    @property
    def warnings(self):
        return [w for w in self.get("warnings").split("\n") if w]

    def close(self):
        if getattr(self, "handle", None):
            self.lib.veachReleaseScene(self.handle)
            self.handle = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        self.close()


_PROGRESS = ctypes.CFUNCTYPE(ctypes.c_bool, ctypes.c_void_p, ctypes.c_double, ctypes.c_double)
_RESULT_STRINGS = ("result_camera", "result_integrator", "result_warnings")
_RESULT_FLOATS = ("progress", "eta_seconds", "render_seconds", "build_seconds", "denoise_seconds")


class Render:
    """A render of a loaded Scene, with render options as keywords (width, spp, integrator, ...)."""

    def __init__(self, scene, **options):
        self.scene = scene
        self.device = scene.device
        self.lib = lib = scene.lib
        self.handle = lib.veachNewRender(scene.handle)
        if not self.handle:
            raise _fail(lib)
        self._callback = None
        try:
            for name, value in options.items():
                self.set(name, value)
        except BaseException:
            self.close()
            raise

    def set(self, name, value):
        lib = self.lib
        _set(lib, (lib.veachSetInt, lib.veachSetFloat, lib.veachSetString), self.handle,
             self.device.option_type("render", name), name, value)

    def get(self, name):
        """An option, or a result (result_spp, result_complete, render_seconds, progress, ...)."""
        lib = self.lib
        kind = self.device.option_type("render", name)
        if kind is None:
            kind = "string" if name in _RESULT_STRINGS else "float" if name in _RESULT_FLOATS else "int"
        return _get(lib, (lib.veachGetInt, lib.veachGetFloat, lib.veachGetString), self.handle, kind, name)

    def _progress(self, progress):
        """progress(fraction, eta_seconds), called after each pass on the render's thread;
        returning False cancels."""
        if progress is None:
            self._callback = None
            self.lib.veachSetProgressFunction(self.handle, None, None)
            return

        def call(user, fraction, eta):
            try:
                return progress(fraction, eta) is not False
            except Exception:
                return False  # an exception in the callback stops the render
        self._callback = _PROGRESS(call)  # kept alive while the render may call it
        self.lib.veachSetProgressFunction(self.handle, ctypes.cast(self._callback, ctypes.c_void_p), None)

    def render(self, progress=None):
        """Renders on this thread (the library's workers do the work); raises Cancelled when
        stopped early (the partial image stays available)."""
        self._progress(progress)
        _check(self.lib, self.lib.veachRender(self.handle))
        return self

    def start(self, progress=None):
        """Starts rendering on the library's own thread and returns at once."""
        self._progress(progress)
        _check(self.lib, self.lib.veachRenderAsync(self.handle))
        return self

    def wait(self, timeout=None):
        """Waits up to `timeout` seconds (None: until done) and returns the status (RUNNING, DONE,
        CANCELLED); a failed render raises its error."""
        ms = -1 if timeout is None else max(0, int(timeout * 1000))
        status = self.lib.veachWaitRender(self.handle, ms)
        if status == FAILED:
            raise _fail(self.lib)
        return status

    @property
    def status(self):
        return self.lib.veachGetRenderStatus(self.handle)

    def cancel(self):
        self.lib.veachCancelRender(self.handle)

    def get_pass(self, name="combined", out=None):
        """A pass as an H x W x 4 float32 array (combined, depth, normal, albedo, variance,
        samples). The library writes it into the array's own memory: pass `out` (C-contiguous,
        float32, H x W x 4) to reuse one. During an asynchronous render: the film so far."""
        width, height = self.get("result_width"), self.get("result_height")
        if out is None:
            out = np.empty((height, width, 4), dtype=np.float32)
        elif out.dtype != np.float32 or not out.flags["C_CONTIGUOUS"] or out.shape != (height, width, 4):
            raise InvalidArgument(1, f"get_pass: out must be a C-contiguous float32 {height}x{width}x4 array")
        _check(self.lib, self.lib.veachGetPass(self.handle, name.encode(), out.ctypes.data_as(ctypes.c_void_p),
                                               out.nbytes, 0))
        return out

    def write(self, path):
        """Writes the image as the veach command does (format from the extension, metadata)."""
        _check(self.lib, self.lib.veachWriteImage(self.handle, os.fsencode(path)))

    def close(self):
        if getattr(self, "handle", None):
            self.lib.veachReleaseRender(self.handle)  # cancels and joins a running render
            self.handle = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        self.close()


def render(path, progress=None, scene_options=None, **options):
    """Renders the scene file at `path` and returns its Combined pass, H x W x 4 float32
    (scene-linear Rec.709, alpha 1 unless transparent=1): what `veach render` writes to an EXR
    with the same options, bit for bit. Keywords are render options (width, height, spp, seed,
    integrator, ...); scene options go in `scene_options` (a dict)."""
    with Scene(path, **(scene_options or {})) as scene, Render(scene, **options) as r:
        r.render(progress)
        return r.get_pass("combined")


__all__ = ["render", "Scene", "Render", "Device", "load_library", "version", "VeachError", "InvalidArgument",
           "InvalidOperation", "BadInput", "OutputError", "Cancelled", "IDLE", "RUNNING", "DONE", "CANCELLED",
           "FAILED"]

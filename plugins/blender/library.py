# libveach through ctypes: finding the library, declaring the C API's signatures (veach.h), and a
# small Render wrapper that turns error codes into exceptions carrying veachGetLastError().
import ctypes
import ctypes.util
import glob
import os

VEACH_ERROR_NONE = 0
VEACH_ERROR_CANCELLED = 5
STATUS_RUNNING, STATUS_DONE, STATUS_CANCELLED, STATUS_FAILED = 1, 2, 3, 4
ABI_MAJOR = 0  # the libveach.so.<major> this add-on speaks to
# The oldest minor it speaks to: 0.6's veachGetPass takes the destination's size, and ctypes
# binds the newest symbol version a library has, so an older library would take the wrong call.
ABI_MIN_MINOR = 6


class VeachError(RuntimeError):
    def __init__(self, code, message):
        super().__init__(message)
        self.code = code


def candidate_paths(preference_path=""):
    """Where to look, in order: VEACH_LIBRARY, the add-on preference, beside the add-on (or the
    lib folder of the prefix it is installed in: PREFIX/share/veach/blender/veach), the system."""
    here = os.path.dirname(os.path.abspath(__file__))
    paths = []
    if os.environ.get("VEACH_LIBRARY"):
        paths.append(os.environ["VEACH_LIBRARY"])
    if preference_path:
        paths.append(bpy_abspath(preference_path))
    paths += sorted(glob.glob(os.path.join(here, "libveach.so*")))
    prefix = os.path.normpath(os.path.join(here, "..", "..", "..", ".."))
    for libdir in ("lib", "lib64", "lib/x86_64-linux-gnu"):
        paths += sorted(glob.glob(os.path.join(prefix, libdir, f"libveach.so.{ABI_MAJOR}")))
    found = ctypes.util.find_library("veach")
    paths.append(found or f"libveach.so.{ABI_MAJOR}")
    return paths


def bpy_abspath(path):
    try:
        import bpy
        return bpy.path.abspath(path)
    except ImportError:
        return path


def load(preference_path=""):
    """Loads libveach from the first candidate that opens; raises VeachError listing the tries."""
    tried = []
    for path in candidate_paths(preference_path):
        try:
            lib = ctypes.CDLL(path)
        except OSError as e:
            tried.append(f"{path} ({e})")
            continue
        declare(lib)
        version = lib.veachGetVersion()
        if version // 10000 != ABI_MAJOR or version // 100 % 100 < ABI_MIN_MINOR:
            tried.append(f"{path} (version {lib.veachGetVersionString().decode()}, "
                         f"need {ABI_MAJOR}.{ABI_MIN_MINOR} or a later {ABI_MAJOR}.x)")
            continue
        return lib
    raise VeachError(-1, "libveach not found; set VEACH_LIBRARY or the add-on preference. Tried: " + "; ".join(tried))


def declare(lib):
    c = ctypes
    P = c.c_void_p
    sigs = {
        "veachGetVersion": (c.c_int, []),
        "veachGetVersionString": (c.c_char_p, []),
        "veachGetLastError": (c.c_char_p, []),
        "veachGetLastErrorCode": (c.c_int, []),
        "veachNewDevice": (P, []),
        "veachReleaseDevice": (None, [P]),
        "veachNewSceneFromFile": (P, [P, c.c_char_p]),
        "veachNewSceneFromMemory": (P, [P, c.c_void_p, c.c_size_t, c.c_char_p, c.c_char_p]),
        "veachReleaseScene": (None, [P]),
        "veachNewScene": (P, [P]),
        "veachSetSceneInt": (c.c_int, [P, c.c_char_p, c.c_longlong]),
        "veachSetSceneFloat": (c.c_int, [P, c.c_char_p, c.c_double]),
        "veachSetSceneString": (c.c_int, [P, c.c_char_p, c.c_char_p]),
        "veachLoadSceneFile": (c.c_int, [P, c.c_char_p]),
        "veachGetSceneString": (c.c_int, [P, c.c_char_p, c.c_char_p, c.c_size_t, c.POINTER(c.c_size_t)]),
        "veachGetSceneCameraCount": (c.c_int, [P]),
        "veachGetSceneCameraName": (c.c_char_p, [P, c.c_int]),
        "veachNewRender": (P, [P]),
        "veachReleaseRender": (None, [P]),
        "veachSetInt": (c.c_int, [P, c.c_char_p, c.c_longlong]),
        "veachSetFloat": (c.c_int, [P, c.c_char_p, c.c_double]),
        "veachSetString": (c.c_int, [P, c.c_char_p, c.c_char_p]),
        "veachGetInt": (c.c_int, [P, c.c_char_p, c.POINTER(c.c_longlong)]),
        "veachGetFloat": (c.c_int, [P, c.c_char_p, c.POINTER(c.c_double)]),
        "veachGetString": (c.c_int, [P, c.c_char_p, c.c_char_p, c.c_size_t, c.POINTER(c.c_size_t)]),
        "veachRenderAsync": (c.c_int, [P]),
        "veachWaitRender": (c.c_int, [P, c.c_int]),
        "veachCancelRender": (None, [P]),
        "veachGetPass": (c.c_int, [P, c.c_char_p, c.c_void_p, c.c_size_t, c.c_size_t]),
    }
    for name, (res, args) in sigs.items():
        f = getattr(lib, name)
        f.restype = res
        f.argtypes = args


class Render:
    """One scene and one render on it; the handles are released by close(). scene_options are
    the scene options set before the load (env_map, env_color, spot_falloff, ...)."""

    def __init__(self, lib, path, scene_options=None):
        self.lib = lib
        self.device = lib.veachNewDevice()
        self.scene = lib.veachNewScene(self.device)
        if not self.scene:
            self._raise()
        try:
            for name, value in (scene_options or {}).items():
                key = name.encode()
                if isinstance(value, str):
                    self._check(lib.veachSetSceneString(self.scene, key, value.encode()))
                elif isinstance(value, float):
                    self._check(lib.veachSetSceneFloat(self.scene, key, value))
                else:
                    self._check(lib.veachSetSceneInt(self.scene, key, int(value)))
            self._check(lib.veachLoadSceneFile(self.scene, path.encode()))
        except VeachError:
            self.close()
            raise
        self.render = lib.veachNewRender(self.scene)
        if not self.render:
            self._raise()

    def _raise(self):
        code = self.lib.veachGetLastErrorCode()
        message = (self.lib.veachGetLastError() or b"").decode(errors="replace")
        self.close()
        raise VeachError(code, message)

    def _check(self, code):
        if code != VEACH_ERROR_NONE:
            raise VeachError(code, (self.lib.veachGetLastError() or b"").decode(errors="replace"))

    def camera_names(self):
        n = self.lib.veachGetSceneCameraCount(self.scene)
        return [self.lib.veachGetSceneCameraName(self.scene, i).decode() for i in range(max(n, 0))]

    def scene_string(self, name):
        return self._string(self.lib.veachGetSceneString, self.scene, name)

    def get_string(self, name):
        return self._string(self.lib.veachGetString, self.render, name)

    def _string(self, getter, handle, name):
        length = ctypes.c_size_t(0)
        self._check(getter(handle, name.encode(), None, 0, ctypes.byref(length)))
        buffer = ctypes.create_string_buffer(length.value + 1)
        self._check(getter(handle, name.encode(), buffer, length.value + 1, None))
        return buffer.value.decode(errors="replace")

    def set(self, name, value):
        key = name.encode()
        if isinstance(value, str):
            self._check(self.lib.veachSetString(self.render, key, value.encode()))
        elif isinstance(value, float):
            self._check(self.lib.veachSetFloat(self.render, key, value))
        else:
            self._check(self.lib.veachSetInt(self.render, key, int(value)))

    def get_int(self, name):
        v = ctypes.c_longlong(0)
        self._check(self.lib.veachGetInt(self.render, name.encode(), ctypes.byref(v)))
        return v.value

    def get_float(self, name):
        v = ctypes.c_double(0)
        self._check(self.lib.veachGetFloat(self.render, name.encode(), ctypes.byref(v)))
        return v.value

    def start(self):
        self._check(self.lib.veachRenderAsync(self.render))

    def wait(self, timeout_ms):
        status = self.lib.veachWaitRender(self.render, timeout_ms)
        if status == STATUS_FAILED:
            self._check(self.lib.veachGetLastErrorCode() or -1)
        return status

    def cancel(self):
        self.lib.veachCancelRender(self.render)

    def get_pass(self, name, buffer_address, buffer_bytes, row_stride_bytes=0):
        self._check(self.lib.veachGetPass(self.render, name.encode(), buffer_address, buffer_bytes,
                                          row_stride_bytes))

    def close(self):
        if getattr(self, "render", None):
            self.lib.veachReleaseRender(self.render)  # cancels and joins a running render
            self.render = None
        if getattr(self, "scene", None):
            self.lib.veachReleaseScene(self.scene)
            self.scene = None
        if getattr(self, "device", None):
            self.lib.veachReleaseDevice(self.device)
            self.device = None

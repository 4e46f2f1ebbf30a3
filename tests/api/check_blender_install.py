#!/usr/bin/python3
"""The Blender add-on installed exactly as README's "Blender add-on" steps say, with nothing else
telling it where libveach is (no VEACH_LIBRARY, no LD_LIBRARY_PATH):

1. `cmake --install` into a prefix (here a temporary one; `make install PREFIX=...` runs the same);
2. a. the installed folder PREFIX/share/veach/blender/veach linked into the user's add-ons as
      `veach` (~/.config/blender/3.4/scripts/addons/veach, HOME being a temporary folder): the
      add-on finds PREFIX/lib/libveach.so.0 through the link;
   b. a zip of that folder (`python3 -m zipfile -c veach.zip veach`) installed with Edit >
      Preferences > Add-ons > Install... (the operator that button runs), the "libveach"
      preference set to PREFIX/lib/libveach.so.0 and saved;
3. Blender started with `--addons veach` (a) or with the saved preferences alone (b), Veach chosen
   as the render engine (`-E VEACH`), a frame rendered (`-f 1`) of the default scene.
Each must write a frame that is not black. Exit 0 pass, 1 fail.
Usage: check_blender_install.py --build BUILD_DIR
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_harness import find_blender, run_blender  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
from check_report import FAILURES, check, import_oiio  # noqa: E402

# A small, quick frame of the default scene (Cycles' settings are used by default: 4 samples).
SMALL = ("import bpy; s = bpy.context.scene; s.render.resolution_x = 64; s.render.resolution_y = 48; "
         "s.cycles.samples = 4")


def blender_version_folder(blender):
    out = subprocess.run([blender, "--version"], capture_output=True, text=True, timeout=120).stdout
    version = out.split()[1]  # "Blender 3.4.1"
    return ".".join(version.split(".")[:2])


def user_env(home):
    env = {k: v for k, v in os.environ.items() if k not in ("VEACH_LIBRARY", "LD_LIBRARY_PATH", "BLENDER_USER_SCRIPTS",
                                                           "BLENDER_USER_CONFIG")}
    env["HOME"] = home
    return env


def render_frame(blender, home, out_dir, extra, what):
    """Renders frame 1 of the default scene with the Veach engine; checks the PNG is not black."""
    os.makedirs(out_dir)
    command = [blender, "-b", *extra, "-E", "VEACH", "--python-expr", SMALL, "-o", os.path.join(out_dir, "frame_#"),
               "-F", "PNG", "-f", "1"]
    code, log = run_blender(command, out_dir, user_env(home))
    frame = os.path.join(out_dir, "frame_1.png")
    if not check(code == 0 and os.path.isfile(frame) and "Traceback" not in log and "not found" not in log,
                 f"{what}: exit {code}, frame written: {os.path.isfile(frame)}\n$ {' '.join(command)}\n{log[-3000:]}"):
        return
    oiio = import_oiio()
    stats = oiio.ImageBufAlgo.computePixelStats(oiio.ImageBuf(frame))
    check(sum(stats.avg[:3]) > 0.01, f"{what}: the frame is black ({stats.avg})")
    print(f"{what}: rendered, mean {sum(stats.avg[:3]) / 3:.3f}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", required=True)
    args = ap.parse_args()
    blender = find_blender()
    version = blender_version_folder(blender)
    tmp = tempfile.mkdtemp(prefix="veach_addon_install_")
    try:
        prefix = os.path.join(tmp, "prefix")
        p = subprocess.run(["cmake", "--install", args.build, "--prefix", prefix], capture_output=True, text=True)
        if p.returncode != 0:
            sys.exit(f"FAIL: cmake --install: {p.stderr}")
        addon = os.path.join(prefix, "share", "veach", "blender", "veach")
        libs = [os.path.join(d, f) for d, _, fs in os.walk(prefix) for f in fs if f == "libveach.so.0"]
        if not os.path.isfile(os.path.join(addon, "__init__.py")) or len(libs) != 1:
            sys.exit(f"FAIL: the add-on ({addon}) or libveach.so.0 ({libs}) is not installed")

        # a. The installed folder linked into the add-ons folder.
        home = os.path.join(tmp, "home_link")
        addons = os.path.join(home, ".config", "blender", version, "scripts", "addons")
        os.makedirs(addons)
        os.symlink(addon, os.path.join(addons, "veach"))
        render_frame(blender, home, os.path.join(tmp, "out_link"), ["--addons", "veach"], "linked add-on")

        # b. A zip installed from the preferences, the library named in the add-on's preference.
        home = os.path.join(tmp, "home_zip")
        os.makedirs(home)
        archive = os.path.join(tmp, "veach.zip")
        p = subprocess.run([sys.executable, "-m", "zipfile", "-c", archive, "veach"], cwd=os.path.dirname(addon),
                           capture_output=True, text=True)
        check(p.returncode == 0, f"python3 -m zipfile -c: {p.stderr}")
        setup = ("import bpy; bpy.ops.preferences.addon_install(filepath=%r); "
                 "bpy.ops.preferences.addon_enable(module='veach'); "
                 "bpy.context.preferences.addons['veach'].preferences.library_path = %r; "
                 "bpy.context.preferences.use_preferences_save = True; bpy.ops.wm.save_userpref()") % (archive, libs[0])
        code, log = run_blender([blender, "-b", "--python-expr", setup], tmp, user_env(home))
        check(code == 0 and "Traceback" not in log, f"installing the zip: exit {code}\n{log[-3000:]}")
        render_frame(blender, home, os.path.join(tmp, "out_zip"), [], "zip-installed add-on")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    if FAILURES:
        return 1
    print("the add-on works installed as README says: linked from the prefix, and from a zip with the preference")
    return 0


if __name__ == "__main__":
    sys.exit(main())

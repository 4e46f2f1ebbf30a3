"""What the add-on's headless tests (check_blender_frames.py, check_blender_scenes.py,
check_blender_passes.py) share: Blender found on PATH (its absence is a failure:
scripts/install-deps.sh installs it), the add-on installed as a user installs it (a folder
`veach` in the user's add-ons: here a temporary BLENDER_USER_SCRIPTS), libveach named by
VEACH_LIBRARY, and Blender run the way a shell runs it, with PWD set (Blender takes its working
directory, which `//` output paths are relative to, from $PWD)."""
import os
import shutil
import subprocess
import sys


def find_blender():
    blender = shutil.which("blender")
    if not blender:
        sys.exit("FAIL: blender is not installed (scripts/install-deps.sh installs it)")
    return blender


def install_addon(tmp, addon, library):
    """The environment for Blender with the add-on folder linked into tmp/scripts/addons/veach."""
    scripts = os.path.join(tmp, "scripts")
    os.makedirs(os.path.join(scripts, "addons"))
    os.symlink(os.path.abspath(addon), os.path.join(scripts, "addons", "veach"))
    return dict(os.environ, BLENDER_USER_SCRIPTS=scripts, VEACH_LIBRARY=os.path.abspath(library))


def run_blender(command, cwd, env, timeout=300):
    """(exit code, stdout + stderr) of a Blender command run in cwd."""
    p = subprocess.run(command, cwd=cwd, env=dict(env, PWD=cwd), capture_output=True, text=True, timeout=timeout)
    return p.returncode, p.stdout + p.stderr


def failed(code, log):
    """Blender exits 0 after a Python exception or a failed render: its log says so."""
    return code != 0 or "Error" in log or "Traceback" in log


def run_or_exit(command, cwd, env, what, timeout=300):
    """The log of a Blender command that must succeed; a failure ends the test with its log."""
    code, log = run_blender(command, cwd, env, timeout)
    if failed(code, log):
        sys.exit(f"FAIL: {what}: exit {code}\n$ {' '.join(command)}\n{log[-4000:]}")
    return log

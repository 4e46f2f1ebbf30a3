#!/usr/bin/python3
"""The `veach` command on a full disk: every file it writes is replaced whole or not at all.

What must hold, for every image format (EXR, HDR, PNG, JPEG, TIFF), the checkpoint and
--stats-json, on a filesystem too small for the file:
- exit code 3 and exactly one stderr line naming the file and "No space left on device" (JPEG
  included: libjpeg must not exit() the process from inside OpenImageIO);
- the file that was there before is untouched, and no temporary file is left beside it.
The same renders on a filesystem with room write files OpenImageIO reads back (so the test
fails if the small filesystem were not what stopped them). `--stats-json /dev/full` fails the
same way (a device is written in place, every write checked).

With --host, the same through the C API inside one host process (disk_full_host.c, linking
libveach): veachWriteImage of every format (and a .vpart) on a disk too small for it returns
VEACH_ERROR_OUTPUT naming the file and "No space left on device", leaves the previous file and
no temporary; veachWriteFile to /dev/full and a render whose checkpoint does not fit fail the
same way; and the host is still alive after all of them (libjpeg's error handler calls exit():
the encoders never write to the disk themselves).

The small filesystems are tmpfs mounts with size=, made in a private mount namespace
(`unshare -m`, or `unshare -r -m` when not root): they vanish with the process, nothing to clean.
Exit 0 pass, 1 fail.
"""
import argparse
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
from check_report import FAILURES, check, import_oiio  # noqa: E402

oiio = import_oiio()

FORMATS = ["exr", "hdr", "png", "jpg", "tif"]
HOST_FORMATS = FORMATS + ["vpart"]
VEACH_ERROR_NONE, VEACH_ERROR_OUTPUT = 0, 4


def mount_tmpfs(folder, size):
    os.makedirs(folder, exist_ok=True)
    subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", folder], check=True)


def render(veach, scene, outputs, extra=()):
    cmd = [veach, "render", scene, "--width", "256", "--spp", "1", "--integrator", "pt", "-q"]
    for o in outputs:
        cmd += ["-o", o]
    return subprocess.run(cmd + list(extra), capture_output=True, text=True, timeout=120)


def expect_refused(result, target, what):
    lines = result.stderr.strip().splitlines()
    check(result.returncode == 3, f"{what}: exit {result.returncode}, expected 3 ({result.stderr.strip()})")
    check(len(lines) == 1, f"{what}: {len(lines)} stderr lines, expected 1: {lines}")
    check(bool(lines) and target in lines[-1] and "No space left on device" in lines[-1],
          f"{what}: message does not name the file and the cause: {lines}")


def only_entries(folder, names, what):
    left = sorted(os.listdir(folder))
    check(left == sorted(names), f"{what}: the folder holds {left}, expected {sorted(names)}")


def in_namespace(veach, scene, root):
    # Room for every file: the control.
    roomy = os.path.join(root, "roomy")
    mount_tmpfs(roomy, "64m")
    result = render(veach, scene, [os.path.join(roomy, f"ok.{ext}") for ext in FORMATS])
    check(result.returncode == 0, f"control render failed: {result.stderr.strip()}")
    for ext in FORMATS:
        path = os.path.join(roomy, f"ok.{ext}")
        buf = oiio.ImageBuf(path)
        check(not buf.has_error and buf.spec().width == 256, f"control {ext}: not a readable 256 px image")
    only_entries(roomy, [f"ok.{ext}" for ext in FORMATS], "control")

    # Each format alone on 16 KiB that already holds the old file: the encoded image (tens of
    # KiB of noise at 256x256, 1 spp) does not fit.
    for ext in FORMATS:
        small = os.path.join(root, f"small_{ext}")
        mount_tmpfs(small, "16k")
        target = os.path.join(small, f"image.{ext}")
        with open(target, "w") as f:
            f.write("old")
        result = render(veach, scene, [target])
        expect_refused(result, target, f"{ext} on a full disk")
        with open(target) as f:
            check(f.read() == "old", f"{ext}: the previous file was changed")
        only_entries(small, [f"image.{ext}"], ext)

    # The checkpoint (the film's sums: megabytes) on a small disk: the render fails with exit 3
    # before any image is written, and leaves no checkpoint.
    small = os.path.join(root, "small_checkpoint")
    mount_tmpfs(small, "256k")
    target = os.path.join(small, "ck.exr")
    result = render(veach, scene, [target], ["--checkpoint", "0", "--spp", "4"])
    expect_refused(result, target + ".checkpoint", "checkpoint on a full disk")
    only_entries(small, [], "checkpoint")

    # --stats-json on a disk filled to the last byte: the image (elsewhere) is written, the stats
    # file is not, exit 3.
    small = os.path.join(root, "small_stats")
    mount_tmpfs(small, "8k")
    with open(os.path.join(small, "filler"), "wb") as f:
        try:
            f.write(b"\0" * 65536)
        except OSError:
            pass
    stats = os.path.join(small, "stats.json")
    image = os.path.join(roomy, "stats.png")
    result = render(veach, scene, [image], ["--stats-json", stats])
    expect_refused(result, stats, "--stats-json on a full disk")
    only_entries(small, ["filler"], "stats")

    result = render(veach, scene, [os.path.join(roomy, "devfull.png")], ["--stats-json", "/dev/full"])
    expect_refused(result, "/dev/full", "--stats-json /dev/full")


def host_in_namespace(host, scene, root):
    roomy = os.path.join(root, "roomy")
    mount_tmpfs(roomy, "64m")
    for ext in HOST_FORMATS:
        small = os.path.join(root, f"small_{ext}")
        mount_tmpfs(small, "16k")
        with open(os.path.join(small, f"image.{ext}"), "w") as f:
            f.write("old")
    mount_tmpfs(os.path.join(root, "small_checkpoint"), "256k")
    result = subprocess.run([host, scene, root], capture_output=True, text=True, timeout=300)
    lines = result.stdout.splitlines()
    check(result.returncode == 0 and lines and lines[-1] == "host alive after every write",
          f"the host did not survive its writes: exit {result.returncode}, last line "
          f"{lines[-1] if lines else None!r}, stderr {result.stderr.strip()!r}")
    reports = {}
    for line in lines[:-1]:
        what, path, code, message = line.split("\t")
        reports[(what, path)] = (int(code), message)

    def expect(what, path, code, cause=None):
        got = reports.get((what, path))
        if not check(got is not None, f"{what} {path}: not reported"):
            return
        check(got[0] == code, f"{what} {path}: error {got[0]} ({got[1]}), expected {code}")
        if cause:
            check(path in got[1] and cause in got[1], f"{what} {path}: message does not name the file and the cause: {got[1]!r}")

    for ext in HOST_FORMATS:
        path = os.path.join(roomy, f"ok.{ext}")
        expect("roomy", path, VEACH_ERROR_NONE)
        if ext != "vpart":
            buf = oiio.ImageBuf(path)
            check(not buf.has_error and buf.spec().width == 256, f"host control {ext}: not a readable 256 px image")
        else:
            check(os.path.getsize(path) > 16384, f"host control vpart: {os.path.getsize(path)} bytes fit the small disk")
    only_entries(roomy, [f"ok.{ext}" for ext in HOST_FORMATS], "host control")
    for ext in HOST_FORMATS:
        small = os.path.join(root, f"small_{ext}")
        target = os.path.join(small, f"image.{ext}")
        expect("small", target, VEACH_ERROR_OUTPUT, "No space left on device")
        with open(target) as f:
            check(f.read() == "old", f"host {ext}: the previous file was changed")
        only_entries(small, [f"image.{ext}"], f"host {ext}")
    expect("devfull", "/dev/full", VEACH_ERROR_OUTPUT, "No space left on device")
    checkpoint = os.path.join(root, "small_checkpoint", "ck.checkpoint")
    expect("checkpoint", checkpoint, VEACH_ERROR_OUTPUT, "No space left on device")
    only_entries(os.path.join(root, "small_checkpoint"), [], "host checkpoint")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--veach", required=True)
    ap.add_argument("--scene", required=True)
    ap.add_argument("--host", help="the C API host (disk_full_host.c) instead of the command")
    ap.add_argument("--inside", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if not args.inside:
        # Re-run in a private mount namespace, where mounts need no cleanup.
        unshare = ["unshare", "-m"] if os.geteuid() == 0 else ["unshare", "-r", "-m"]
        cmd = unshare + [sys.executable, os.path.abspath(__file__), "--inside", "--veach",
                         os.path.abspath(args.veach), "--scene", os.path.abspath(args.scene)]
        if args.host:
            cmd += ["--host", os.path.abspath(args.host)]
        return subprocess.run(cmd).returncode
    with tempfile.TemporaryDirectory(prefix="veach_disk_full_") as root:
        if args.host:
            host_in_namespace(args.host, args.scene, root)
        else:
            in_namespace(args.veach, args.scene, root)
        # Unmount before the temporary folder is removed (the namespace would drop them anyway).
        for entry in os.listdir(root):
            subprocess.run(["umount", os.path.join(root, entry)], check=False)
    if FAILURES:
        print(f"{len(FAILURES)} failure(s)")
        return 1
    if args.host:
        print("disk full in a host: every format, /dev/full and the checkpoint returned VEACH_ERROR_OUTPUT, "
              "nothing torn, the host alive")
    else:
        print("disk full: every format, the checkpoint and the stats refused with exit 3, nothing torn")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""Farm-safe behaviour of the `veach` command.

What must hold:
- Outputs checked first: a missing folder, an unknown format, an unknown OCIO display, view or
  look, a second output in a missing folder, a --stats-json in a missing folder, a checkpoint
  that cannot be created (a folder in its place) and a folder mounted read-only (where root's
  permission bits would say yes) each exit 1 or 2 with one line, having rendered nothing: the
  render asked for would take far longer than the test waits, and no output appears. `veach
  merge` checks all its outputs before writing the first.
Exit 0 pass, 1 fail.
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile

FAILURES = []
ONLY = None  # --only NAME: one group of checks (while iterating)


def check(condition, message):
    if not condition:
        FAILURES.append(message)
        print(f"FAIL: {message}")
    return condition


def run(veach, *args, timeout=120, **kw):
    return subprocess.run([veach, *args], capture_output=True, text=True, timeout=timeout, **kw)


def one_line_refusal(r, what, codes=(1, 2)):
    lines = r.stderr.strip().splitlines()
    check(r.returncode in codes, f"{what}: exit {r.returncode}, expected one of {codes} ({r.stderr.strip()})")
    check(len(lines) == 1, f"{what}: expected one line, got {lines}")


def check_outputs_first(veach, scene, tmp):
    # Hours of rendering if it started: a refusal must come at once (the timeout is generous for a
    # loaded machine, and far shorter than the render).
    long = ["--width", "1024", "--spp", "100000", "--integrator", "pt", "-q"]
    ok = os.path.join(tmp, "ok.exr")
    os.makedirs(os.path.join(tmp, "x.exr.checkpoint"))
    cases = [
        ("a missing folder", ["-o", os.path.join(tmp, "no", "such", "x.exr")], (2,)),
        ("an unknown format", ["-o", os.path.join(tmp, "x.xyz")], (1,)),
        ("no extension", ["-o", os.path.join(tmp, "x")], (1,)),
        ("an unknown display", ["-o", os.path.join(tmp, "x.png"), "--display", "NoSuchDisplay"], (1,)),
        ("an unknown view", ["-o", os.path.join(tmp, "x.png"), "--view", "NoSuchView"], (1,)),
        ("an unknown look", ["-o", os.path.join(tmp, "x.jpg"), "--look", "NoSuchLook"], (1,)),
        ("a second output in a missing folder", ["-o", ok, "-o", os.path.join(tmp, "missing", "x.png")], (2,)),
        ("an output that is a folder", ["-o", ok, "-o", tmp], (1, 2)),
        ("--stats-json in a missing folder", ["-o", ok, "--stats-json", os.path.join(tmp, "missing", "s.json")],
         (2,)),
        ("a checkpoint that cannot be created", ["-o", os.path.join(tmp, "x.exr"), "--checkpoint", "60"], (2,)),
    ]
    for what, flags, codes in cases:
        try:
            r = run(veach, "render", scene, *long, *flags, timeout=60)
        except subprocess.TimeoutExpired:
            check(False, f"{what}: the command rendered instead of refusing")
            continue
        one_line_refusal(r, what, codes)
        check(not os.path.exists(ok), f"{what}: an output was written")
    # A batch: the second input's output folder is missing; the first input must not render.
    other = os.path.join(tmp, "other.gltf")
    shutil.copy(scene, other)
    shutil.copy(os.path.splitext(scene)[0] + ".bin", os.path.join(tmp, os.path.basename(os.path.splitext(scene)[0]) + ".bin"))
    os.makedirs(os.path.join(tmp, "batch", os.path.splitext(os.path.basename(scene))[0]))
    try:
        r = run(veach, "render", scene, other, *long, "-o", os.path.join(tmp, "batch", "{stem}", "img.exr"),
                timeout=60)
        one_line_refusal(r, "a batch whose second output folder is missing", (2,))
    except subprocess.TimeoutExpired:
        check(False, "a batch whose second output folder is missing: the first input rendered")

    # Root passes every permission check, so only creating a file tells a read-only mount.
    ro = os.path.join(tmp, "ro")
    os.makedirs(ro)
    unshare = ["unshare", "-m"] if os.geteuid() == 0 else ["unshare", "-r", "-m"]
    probe = subprocess.run(unshare + ["true"], capture_output=True)
    if probe.returncode == 0:
        script = f'mount --bind "{ro}" "{ro}" && mount -o remount,bind,ro "{ro}" && exec "$@"'
        try:
            r = subprocess.run(unshare + ["sh", "-c", script, "sh", veach, "render", scene, *long, "-o",
                                          os.path.join(ro, "x.exr")], capture_output=True, text=True, timeout=60)
            one_line_refusal(r, "a read-only folder", (2,))
            check("Read-only" in r.stderr, f"a read-only folder: the message does not say why: {r.stderr.strip()}")
        except subprocess.TimeoutExpired:
            check(False, "a read-only folder: the command rendered instead of refusing")
    else:
        print("note: no private mount namespace here; the read-only folder case is not run")

    # merge: parts made quickly; a bad second output leaves the first unwritten.
    part = os.path.join(tmp, "p.vpart")
    r = run(veach, "render", scene, "-o", part, "--width", "16", "--height", "16", "--spp", "2", "--samples", "0:2",
            "--integrator", "pt", "-q")
    if check(r.returncode == 0, f"part render: {r.stderr.strip()}"):
        merged = os.path.join(tmp, "merged.exr")
        r = run(veach, "merge", part, "-o", merged, "-o", os.path.join(tmp, "m.png"), "--view", "NoSuchView", "-q")
        one_line_refusal(r, "merge with an unknown view", (1,))
        check(not os.path.exists(merged), "merge: the first output was written before the second was refused")
        r = run(veach, "merge", part, "-o", merged, "-o", os.path.join(tmp, "missing", "m.png"), "-q")
        one_line_refusal(r, "merge into a missing folder", (2,))
        check(not os.path.exists(merged), "merge: the first output was written before the second was refused")
    leftovers = [n for n in os.listdir(tmp) if n.startswith(".")]
    check(not leftovers, f"the checks left temporary files behind: {leftovers}")


def main():
    global ONLY
    ap = argparse.ArgumentParser()
    ap.add_argument("--veach", required=True)
    ap.add_argument("--scene", required=True)
    ap.add_argument("--only")
    args = ap.parse_args()
    ONLY = args.only
    groups = [("outputs", check_outputs_first)]
    for name, fn in groups:
        if ONLY and name != ONLY:
            continue
        with tempfile.TemporaryDirectory() as tmp:
            fn(args.veach, args.scene, tmp)
    if FAILURES:
        print(f"{len(FAILURES)} failure(s)")
        return 1
    print("farm-safe behaviour: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""Farm-safe behaviour of the `veach` command.

What must hold:
- Outputs checked first: a missing folder, an unknown format, an unknown OCIO display, view or
  look, a second output in a missing folder, a --stats-json in a missing folder, a checkpoint
  that cannot be created (a folder in its place) and a folder mounted read-only (where root's
  permission bits would say yes) each exit 1 or 2 with one line, having rendered nothing: the
  render asked for would take far longer than the test waits, and no output appears. `veach
  merge` checks all its outputs before writing the first.
- --skip-existing skips an output only when it is complete (veach:complete yes, the spp asked for,
  the same sample range and tile; read from the file by the library): a real interrupted image
  (SIGTERM after its first checkpoint) is rendered again and resumed from its checkpoint with
  --resume; a part of another range or tile, an interrupted part, or a file that is no image is
  rendered again; a complete image or part is skipped.
- Progress in logs (stderr not a terminal): "Progress: [i/n] FILE N% elapsed Xs ETA Ys" lines
  ("[i/n] FILE" in batches only): one at every pass, and one whenever
  VEACH_PROGRESS_INTERVAL seconds (default 5) pass without one, so a stall detector sees life.
- --threads defaults to the CPUs the process may use: under `taskset -c` of one CPU the render
  runs on one thread (--stats-json "threads"), unrestricted on no more than the mask holds.
Exit 0 pass, 1 fail.
"""
import argparse
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
from check_report import FAILURES, check  # noqa: E402

ONLY = None  # --only NAME: one group of checks (while iterating)


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


def metadata(path):
    """veach:* keys of an EXR through OpenImageIO (the test's own reader, not the command's)."""
    import OpenImageIO as oiio
    inp = oiio.ImageInput.open(path)
    if not inp:
        return {}
    spec = inp.spec()
    # Numbers are int/float attributes in EXR: compared as the text they print as.
    out = {a.name: str(a.value) for a in spec.extra_attribs if a.name.startswith("veach:")}
    inp.close()
    return out


def check_skip_existing(veach, scene, tmp):
    small = ["--width", "32", "--height", "32", "--integrator", "pt", "--threads", "1", "--skip-existing"]
    out = os.path.join(tmp, "a.exr")
    r = run(veach, "render", scene, "-o", out, *small, "--spp", "4")
    check(r.returncode == 0 and "skipped" not in r.stderr, f"first render: {r.stderr.strip()}")
    r = run(veach, "render", scene, "-o", out, *small, "--spp", "4")
    check(r.returncode == 0 and "skipped" in r.stderr, f"a complete output was not skipped: {r.stderr.strip()}")
    r = run(veach, "render", scene, "-o", out, *small, "--spp", "8")
    check(r.returncode == 0 and "skipped" not in r.stderr, f"an output of 4 spp was skipped for --spp 8: {r.stderr}")
    check(metadata(out).get("veach:spp") == "8", f"the 8-spp rerun did not replace the image: {metadata(out)}")

    # A real interrupted render: SIGTERM once its first checkpoint is on disk. The image it leaves
    # says veach:complete no, and the checkpoint stays.
    spp = "600"
    out = os.path.join(tmp, "killed.exr")
    checkpoint = out + ".checkpoint"
    p = subprocess.Popen([veach, "render", scene, "-o", out, *small, "--spp", spp, "--checkpoint", "0", "-q"],
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 60
    while time.time() < deadline and not os.path.exists(checkpoint) and p.poll() is None:
        time.sleep(0.01)
    p.send_signal(signal.SIGTERM)
    _, err = p.communicate(timeout=60)
    if not check(p.returncode == 130 and os.path.exists(out) and os.path.exists(checkpoint),
                 f"could not interrupt a render (exit {p.returncode}: {err.strip()}); is it too fast?"):
        return
    before = metadata(out)
    check(before.get("veach:complete") == "no", f"the interrupted image is not marked incomplete: {before}")
    r = run(veach, "render", scene, "-o", out, *small, "--spp", spp, "--checkpoint", "0", "--resume")
    after = metadata(out)
    check(r.returncode == 0 and "skipped" not in r.stderr, f"an interrupted image was skipped: {r.stderr.strip()}")
    check(after.get("veach:complete") == "yes" and after.get("veach:spp") == spp,
          f"the rerun did not complete the image: {after}")
    check(int(after.get("veach:resumed_spp", "0")) > 0, f"the rerun did not resume from the checkpoint: {after}")
    r = run(veach, "render", scene, "-o", out, *small, "--spp", spp, "--checkpoint", "0", "--resume")
    check("skipped" in r.stderr, f"the completed image was not skipped: {r.stderr.strip()}")

    # Part files: complete only for the same sample range and tile; an interrupted part
    # (finished passes only) is rendered again.
    part = os.path.join(tmp, "part.vpart")
    r = run(veach, "render", scene, "-o", part, *small, "--spp", "8", "--samples", "0:4")
    check(r.returncode == 0 and "skipped" not in r.stderr, f"first part: {r.stderr.strip()}")
    r = run(veach, "render", scene, "-o", part, *small, "--spp", "8", "--samples", "0:4")
    check("skipped" in r.stderr, f"a complete part was not skipped: {r.stderr.strip()}")
    r = run(veach, "render", scene, "-o", part, *small, "--spp", "8", "--samples", "4:8")
    check("skipped" not in r.stderr, f"a part of samples 0:4 was taken for 4:8: {r.stderr.strip()}")
    r = run(veach, "render", scene, "-o", part, *small, "--spp", "8", "--samples", "4:8", "--pixelbounds", "0,16,0,32")
    check("skipped" not in r.stderr, f"a whole-frame part was taken for a tile: {r.stderr.strip()}")
    r = run(veach, "render", scene, "-o", part, *small, "--spp", "8", "--samples", "4:8", "--pixelbounds", "0,16,0,32")
    check("skipped" in r.stderr, f"a complete tile part was not skipped: {r.stderr.strip()}")
    part = os.path.join(tmp, "killed.vpart")
    p = subprocess.Popen([veach, "render", scene, "-o", part, *small, "--spp", spp, "--samples", f"0:{spp}",
                          "--checkpoint", "0", "-q"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 60
    while time.time() < deadline and not os.path.exists(part + ".checkpoint") and p.poll() is None:
        time.sleep(0.01)
    p.send_signal(signal.SIGTERM)
    p.communicate(timeout=60)
    if check(p.returncode == 130 and os.path.exists(part), f"could not interrupt a part render (exit {p.returncode})"):
        r = run(veach, "render", scene, "-o", part, *small, "--spp", spp, "--samples", f"0:{spp}", "-q")
        check(r.returncode == 0 and "skipped" not in r.stderr, f"an interrupted part was skipped: {r.stderr.strip()}")
    # Something that is not an image at all under the name: rendered over, not skipped.
    junk = os.path.join(tmp, "junk.png")
    with open(junk, "w") as f:
        f.write("not a PNG\n")
    r = run(veach, "render", scene, "-o", junk, *small, "--spp", "2")
    check(r.returncode == 0 and "skipped" not in r.stderr, f"an unreadable file was taken as complete: {r.stderr}")


PROGRESS = re.compile(r"^Progress: (\[(\d+)/(\d+)\] (.+) )?(\d+)% elapsed ([0-9.]+)s ETA ([0-9.]+s|-)$")


def check_progress(veach, scene, tmp):
    # In a log (stderr a pipe): a line at every pass, and one whenever
    # VEACH_PROGRESS_INTERVAL seconds (5 by default; 0.5 here, so that a render of a few seconds
    # has passes longer than it) pass without one. The gaps are read from the command's own
    # "elapsed", with slack for a loaded machine.
    interval = 0.5
    env = dict(os.environ, VEACH_PROGRESS_INTERVAL=str(interval))
    spp = 48  # passes of 1, 2, 4, 8, 16, 16 and 1 samples: 7 passes
    r = run(veach, "render", scene, "-o", os.path.join(tmp, "p.exr"), "--width", "96", "--height", "96",
            "--spp", str(spp), "--integrator", "bdpt", "--threads", "1", env=env)
    if not check(r.returncode == 0, f"progress render: {r.stderr.strip()}"):
        return
    lines = [l for l in r.stderr.splitlines() if l.startswith("Progress:")]
    parsed = [PROGRESS.match(l) for l in lines]
    check(all(parsed), f"progress lines not in the documented form: {[l for l, m in zip(lines, parsed) if not m]}")
    parsed = [m for m in parsed if m]
    if not check(len(parsed) >= 7, f"expected a line per pass (7), got {lines}"):
        return
    check(parsed[-1].group(5) == "100", f"the last line is not 100%: {lines[-1]}")
    percents = [int(m.group(5)) for m in parsed]
    check(percents == sorted(percents), f"progress went backwards: {percents}")
    elapsed = [float(m.group(6)) for m in parsed]
    gaps = [b - a for a, b in zip(elapsed, elapsed[1:])]
    check(max(gaps) <= interval + 2.0, f"{max(gaps):.1f}s between lines (interval {interval}s): {lines}")
    # Lines between passes: the same percent twice, printed by the heartbeat, not by a pass.
    repeats = sum(1 for a, b in zip(percents, percents[1:]) if a == b)
    if elapsed[-1] > 4 * interval:
        check(repeats >= 1, f"a render of {elapsed[-1]:.1f}s printed no line between passes: {lines}")
    check(not any(m.group(1) for m in parsed), f"a single input's lines carry [i/n]: {lines}")

    # A batch: "[i/n] FILE" on every line, each input in turn.
    other = os.path.join(tmp, "second.gltf")
    shutil.copy(scene, other)
    shutil.copy(os.path.splitext(scene)[0] + ".bin", tmp)
    r = run(veach, "render", scene, other, "-o", os.path.join(tmp, "{stem}_b.exr"), "--width", "16", "--spp", "2",
            "--integrator", "pt")
    lines = [l for l in r.stderr.splitlines() if l.startswith("Progress:")]
    parsed = [PROGRESS.match(l) for l in lines]
    check(r.returncode == 0 and lines and all(m and m.group(1) for m in parsed), f"batch progress lacks [i/n]: {lines}")
    if all(parsed):
        seen = [(m.group(2), m.group(3), m.group(4)) for m in parsed]
        check(("1", "2", scene) in seen and ("2", "2", other) in seen, f"batch progress: {seen}")
    # --quiet: no progress at all.
    r = run(veach, "render", scene, "-o", os.path.join(tmp, "q.exr"), "--width", "16", "--spp", "2", "-q")
    check(not any(l.startswith("Progress:") for l in r.stderr.splitlines()), f"--quiet printed progress: {r.stderr}")


def check_threads(veach, scene, tmp):
    # The default thread count is the CPUs the process may use, as --stats-json reports what the
    # render ran on: one under `taskset -c` of one CPU, and no more than the mask allows without.
    stats = os.path.join(tmp, "stats.json")
    small = ["--width", "16", "--height", "16", "--spp", "1", "--integrator", "pt", "-q", "--stats-json", stats]
    first = str(sorted(os.sched_getaffinity(0))[0])
    r = subprocess.run(["taskset", "-c", first, veach, "render", scene, "-o", os.path.join(tmp, "t1.exr"), *small],
                       capture_output=True, text=True, timeout=120)
    if check(r.returncode == 0, f"render under taskset: {r.stderr.strip()}"):
        got = json.load(open(stats))["threads"]
        check(got == 1, f"taskset -c {first}: the render ran on {got} threads, not 1")
    r = run(veach, "render", scene, "-o", os.path.join(tmp, "t2.exr"), *small)
    if check(r.returncode == 0, f"render: {r.stderr.strip()}"):
        allowed = len(os.sched_getaffinity(0))
        got = json.load(open(stats))["threads"]
        check(1 <= got <= allowed, f"default threads {got}, the process may use {allowed}")
    r = run(veach, "render", scene, "-o", os.path.join(tmp, "t3.exr"), *small, "--threads", "3")
    if check(r.returncode == 0, f"render --threads 3: {r.stderr.strip()}"):
        got = json.load(open(stats))["threads"]
        check(got == 3, f"--threads 3 ran on {got} threads")


def main():
    global ONLY
    ap = argparse.ArgumentParser()
    ap.add_argument("--veach", required=True)
    ap.add_argument("--scene", required=True)
    ap.add_argument("--only")
    args = ap.parse_args()
    ONLY = args.only
    groups = [("outputs", check_outputs_first), ("skip", check_skip_existing), ("progress", check_progress), ("threads", check_threads)]
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

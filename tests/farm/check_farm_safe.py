#!/usr/bin/python3
"""Farm-safe behaviour of the `veach` command.

What must hold:
- Every output is checked before rendering: a missing folder, an unknown format, an unknown
  OCIO display, view or look, or a --stats-json in a missing folder exits 1 or 2 with one line,
  having rendered nothing (the render asked for would take far longer than the test allows).
- --threads defaults to the CPUs the process may use: under an affinity mask of one CPU the
  render runs on one thread (--stats-json "threads"), unrestricted on as many as the mask holds.
- Progress in logs (stderr not a terminal): lines "Progress: N% elapsed Xs ETA Ys" at every pass
  and at most 5 s apart by the command's own clock; "[i/n] file" in a batch.
- --skip-existing on a part file skips only one with the sample range asked for.
Exit 0 pass, 1 fail.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

FAILURES = []


def check(condition, message):
    if not condition:
        FAILURES.append(message)
        print(f"FAIL: {message}")
    return condition


def run(veach, *args, **kw):
    return subprocess.run([veach, *args], capture_output=True, text=True, timeout=300, **kw)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--veach", required=True)
    ap.add_argument("--scene", required=True)
    args = ap.parse_args()
    veach, scene = args.veach, args.scene
    with tempfile.TemporaryDirectory() as tmp:
        # A render that would take hours: the checks must come first.
        long = ["--width", "1024", "--spp", "100000", "-q"]
        cases = [
            ("a missing folder", ["-o", os.path.join(tmp, "no", "such", "x.exr")]),
            ("an unknown format", ["-o", os.path.join(tmp, "x.xyz")]),
            ("an unknown display", ["-o", os.path.join(tmp, "x.png"), "--display", "NoSuchDisplay"]),
            ("an unknown view", ["-o", os.path.join(tmp, "x.png"), "--view", "NoSuchView"]),
            ("an unknown look", ["-o", os.path.join(tmp, "x.png"), "--look", "NoSuchLook"]),
            ("a second output in a missing folder", ["-o", os.path.join(tmp, "ok.exr"), "-o",
                                                     os.path.join(tmp, "missing", "x.png")]),
            ("--stats-json in a missing folder", ["-o", os.path.join(tmp, "ok.exr"), "--stats-json",
                                                  os.path.join(tmp, "missing", "s.json")]),
        ]
        for what, flags in cases:
            try:
                r = run(veach, "render", scene, *long, *flags)
            except subprocess.TimeoutExpired:
                check(False, f"{what}: the command rendered instead of refusing")
                continue
            lines = r.stderr.strip().splitlines()
            check(r.returncode in (1, 2), f"{what}: exit {r.returncode}, expected 1 or 2 ({r.stderr.strip()})")
            check(len(lines) == 1, f"{what}: expected one line, got {lines}")
            check(not os.path.exists(os.path.join(tmp, "ok.exr")), f"{what}: an output was written")

        # Threads: the affinity mask, not the machine.
        stats = os.path.join(tmp, "stats.json")
        small = ["--width", "16", "--height", "16", "--spp", "1", "-q", "--stats-json", stats]
        r = run(veach, "render", scene, "-o", os.path.join(tmp, "t1.exr"), *small,
                preexec_fn=lambda: os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]}))
        if check(r.returncode == 0, f"render under taskset: {r.stderr.strip()}"):
            check(json.load(open(stats))["threads"] == 1, "one allowed CPU: the render did not use one thread")
        r = run(veach, "render", scene, "-o", os.path.join(tmp, "t2.exr"), *small)
        if check(r.returncode == 0, f"render: {r.stderr.strip()}"):
            allowed = len(os.sched_getaffinity(0))
            got = json.load(open(stats))["threads"]
            check(1 <= got <= allowed, f"default threads {got}, the process may use {allowed}")

        # Progress lines, at every pass and within 5 s of each other (the command's own clock).
        r = run(veach, "render", scene, "-o", os.path.join(tmp, "p.exr"), "--width", "256", "--spp", "48",
                "--integrator", "bdpt")
        lines = [l for l in r.stderr.splitlines() if l.startswith("Progress:")]
        pattern = re.compile(r"^Progress: (\d+)% elapsed ([0-9.]+)s ETA ([0-9.]+)s$")
        parsed = [pattern.match(l) for l in lines]
        check(r.returncode == 0 and len(lines) >= 6, f"progress: expected a line per pass, got {lines}")
        check(all(parsed), f"progress lines not in the documented form: {lines}")
        if all(parsed) and parsed:
            elapsed = [float(m.group(2)) for m in parsed]
            gaps = [b - a for a, b in zip(elapsed, elapsed[1:])]
            check(max(gaps, default=0) <= 6.0, f"progress: {max(gaps):.1f}s between lines (at most 5 s)")
            check(int(parsed[-1].group(1)) == 100, f"progress: the last line is not 100%: {lines[-1]}")
        r = run(veach, "render", scene, scene, "-o", os.path.join(tmp, "{stem}_b.exr"), "--width", "16",
                "--spp", "2")
        check(any(l.startswith("Progress: [1/2]") for l in r.stderr.splitlines()) and
              any(l.startswith("Progress: [2/2]") for l in r.stderr.splitlines()),
              f"batch progress lacks [i/n]: {r.stderr.strip()}")

        # --skip-existing with parts: only the same sample range is complete.
        part = os.path.join(tmp, "part.vpart")
        base = ["render", scene, "-o", part, "--width", "16", "--height", "16", "--spp", "8", "--skip-existing"]
        r = run(veach, *base, "--samples", "0:4")
        check(r.returncode == 0 and "skipped" not in r.stderr, f"first part: {r.stderr.strip()}")
        r = run(veach, *base, "--samples", "0:4")
        check(r.returncode == 0 and "skipped" in r.stderr, f"--skip-existing did not skip a complete part: {r.stderr}")
        r = run(veach, *base, "--samples", "4:8")
        check(r.returncode == 0 and "skipped" not in r.stderr, f"--skip-existing skipped another range: {r.stderr}")
    if FAILURES:
        print(f"{len(FAILURES)} failure(s)")
        return 1
    print("farm-safe behaviour: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""Runs the attack suite written by make_attack_cases.py through the `veach` command and checks
each case's contract (see make_attack_cases.py): exit code, one stderr line naming the fault,
no image for a refused case, a finite non-negative image for a rendered one, never a signal or a
hang, and peak memory under the case's limit (the address space is capped with RLIMIT_AS, so an
allocation a budget should have refused fails instead of succeeding; the peak resident size is
reported per case).

Usage: check_attack_suite.py --veach VEACH --cases DIR [--generate [--full-size]] [--only SUBSTRING] [--jobs N]
(--generate first writes the cases into DIR with make_attack_cases.py.)
Exit 0 when every case keeps its contract, 1 otherwise.
"""
import argparse
import concurrent.futures
import json
import os
import resource
import shlex
import signal
import subprocess
import sys
import threading

import numpy as np
import OpenImageIO as oiio

SANITIZER_MARKS = ("AddressSanitizer", "runtime error:", "LeakSanitizer", "UndefinedBehaviorSanitizer")


def run_limited(cmd, memory_mb, timeout, stdin=None):
    """Runs `cmd` with its address space capped; returns (returncode, stderr, peak_rss_mb, timed_out)."""

    def limit():
        if memory_mb:
            resource.setrlimit(resource.RLIMIT_AS, (memory_mb << 20, memory_mb << 20))

    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, stdin=stdin or subprocess.DEVNULL,
                         preexec_fn=limit)
    timed_out = []
    timer = threading.Timer(timeout, lambda: (timed_out.append(1), p.kill()))
    timer.start()
    err = p.stderr.read().decode(errors="replace")
    _, status, usage = os.wait4(p.pid, 0)
    timer.cancel()
    p.returncode = os.waitstatus_to_exitcode(status)
    return p.returncode, err, usage.ru_maxrss / 1024.0, bool(timed_out)


def check_case(veach, c, timeout):
    """None when case `c` keeps its contract, else a one-line description of the fault."""
    image = os.path.join(c["folder"], "out.exr")
    if os.path.exists(image):
        os.remove(image)
    cmd = [veach, "render", c["input"], "-o", image, "--width", "32", "--height", "24", "--spp", "2",
           "--threads", "1", "-q"] + c["args"]
    rc, err, peak, timed_out = run_limited(cmd, c["memory_mb"], timeout)
    lines = [l for l in err.strip().splitlines() if l]
    where = f"(peak {peak:.0f} MB) stderr: {err.strip()[-600:]!r}"
    if timed_out:
        return f"hang: still running after {timeout}s {where}"
    if rc < 0:
        return f"killed by {signal.Signals(-rc).name} {where}"
    if any(m in err for m in SANITIZER_MARKS):
        return f"sanitizer report {where}"
    if c["expect"] == "refused":
        want = c["exit"] if c["exit"] is not None else 2
        if rc != want:
            return f"exit {rc}, expected {want} {where}"
        if len(lines) != 1:
            return f"{len(lines)} stderr lines, expected 1 {where}"
        if c["message"] and c["message"].lower() not in lines[0].lower():
            return f"message lacks {c['message']!r} {where}"
        if os.path.exists(image):
            return f"refused but an image was written {where}"
        return None
    if rc != 0:
        return f"exit {rc}, expected 0 {where}"
    if c["warning"] and c["warning"].lower() not in err.lower():
        return f"no warning containing {c['warning']!r} {where}"
    if not c["nonfinite_ok"] and "non-finite samples dropped" in err:
        return f"non-finite samples {where}"
    buf = oiio.ImageBuf(image)
    pixels = buf.get_pixels(oiio.FLOAT)
    if pixels is None or pixels.size == 0:
        return f"unreadable image {where}"
    if not np.all(np.isfinite(pixels)):
        return f"non-finite pixels {where}"
    if np.min(pixels) < 0:
        return f"negative pixels (min {np.min(pixels)}) {where}"
    if c.get("lit") and ("has no lights" in err or not np.max(pixels[..., :3]) > 0):
        return f"the scene's light does not light it (max {np.max(pixels[..., :3])}) {where}"
    return None


def check_reader_gone(veach, cases_dir):
    """`veach render ... 2>&1 | head -1`: the reader of stderr leaves after the first line; the
    render must still finish and write its image (exit 0), not die of SIGPIPE."""
    folder = os.path.join(cases_dir, "stderr_reader_gone")
    os.makedirs(folder, exist_ok=True)
    image = os.path.join(folder, "out.exr")
    if os.path.exists(image):
        os.remove(image)
    scene = os.path.join(cases_dir, "camera_scale_huge_uniform_renders", "scene.gltf")
    read_end, write_end = os.pipe()
    os.close(read_end)  # nobody reads: every write to stderr fails
    p = subprocess.run([veach, "render", scene, "-o", image, "--width", "32", "--spp", "64", "--threads", "1"],
                       stdout=write_end, stderr=write_end, timeout=120)
    os.close(write_end)
    if p.returncode != 0:
        return f"exit {p.returncode} with its stderr reader gone (SIGPIPE is {-signal.SIGPIPE})"
    if not os.path.exists(image):
        return "no image written with its stderr reader gone"
    return None


def check_head_one_line(veach, cases_dir):
    """`veach render ... 2>&1 | head -1` as typed in a shell: head leaves after the first line
    while the render still prints progress (checked: the same render prints more than one line),
    and the render must finish, exit 0 and write its image."""
    folder = os.path.join(cases_dir, "stderr_head_one_line")
    os.makedirs(folder, exist_ok=True)
    image = os.path.join(folder, "out.exr")
    scene = os.path.join(cases_dir, "camera_scale_huge_uniform_renders", "scene.gltf")
    cmd = [veach, "render", scene, "-o", image, "--width", "64", "--spp", "256", "--threads", "1"]
    full = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120)
    if full.returncode != 0 or len(full.stdout.splitlines()) < 2:
        return f"the render alone: exit {full.returncode}, {len(full.stdout.splitlines())} lines (need 2 or more)"
    os.remove(image)
    shell = " ".join(shlex.quote(a) for a in cmd) + ' 2>&1 | head -1; exit "${PIPESTATUS[0]}"'
    p = subprocess.run(["bash", "-c", shell], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=120)
    if p.returncode != 0:
        return f"exit {p.returncode} under `| head -1` (SIGPIPE would be {128 + signal.SIGPIPE})"
    if not os.path.exists(image):
        return "no image written under `| head -1`"
    return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--veach", required=True)
    ap.add_argument("--cases", required=True)
    ap.add_argument("--generate", action="store_true")
    ap.add_argument("--full-size", action="store_true", help="with --generate: the multi-gigabyte originals too")
    # AddressSanitizer reserves terabytes of address space: its build runs the cases unlimited.
    ap.add_argument("--no-memory-limit", action="store_true")
    ap.add_argument("--only", default="")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=60)
    args = ap.parse_args()
    if args.generate:
        generator = os.path.join(os.path.dirname(os.path.abspath(__file__)), "make_attack_cases.py")
        subprocess.run([sys.executable, generator, args.cases] + (["--full-size"] if args.full_size else []), check=True)
    with open(os.path.join(args.cases, "manifest.json")) as f:
        cases = [c for c in json.load(f) if args.only in c["name"]]
    if args.no_memory_limit:
        cases = [c for c in cases if not c.get("limit_is_the_point")]
        for c in cases:
            c["memory_mb"] = 0
    if not cases:
        print("no cases")
        return 1
    failures = 0
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        results = list(pool.map(lambda c: (c, check_case(args.veach, c, args.timeout)), cases))
    if not args.only:
        results.append(({"name": "stderr_reader_gone"}, check_reader_gone(args.veach, args.cases)))
        results.append(({"name": "stderr_head_one_line"}, check_head_one_line(args.veach, args.cases)))
    for c, fault in results:
        if fault:
            failures += 1
            print(f"FAIL {c['name']}: {fault}")
        else:
            print(f"ok   {c['name']}")
    print(f"{len(results) - failures} of {len(results)} cases keep their contract")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

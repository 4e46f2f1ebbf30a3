#!/usr/bin/python3
"""Runs the `veach` command over a corpus of glTF files and checks the batch renderer's contract
for bad input (README, "Exit codes"):

  * exit 0: the image exists, is not empty, no temporary file is left beside it, and the stats
    report zero non-finite samples;
  * exit 2: stderr holds exactly one line, and it names the file (the fault follows the name);
    no image and no temporary file was written;
  * anything else fails: another exit code, a signal (crash), a sanitizer report on stderr, or
    running past the per-file timeout (a hang).

The corpus is every .gltf and .glb under --dir folders and in the files of Debian packages named
by --dpkg (assimp-testmodels holds deliberately broken files: indices out of range, wrong JSON
types, infinite values, a missing .bin, recursive node graphs, no scene). Files run in parallel
(--jobs), each single-threaded, at a tiny resolution and one sample per pixel: the test is about
never crashing or hanging, not about the image.

Exit codes: 0 all good, 1 a file broke the contract or the corpus is empty
because the package is not installed.
"""
import argparse
import concurrent.futures
import json
import os
import pathlib
import signal
import subprocess
import sys
import tempfile

SANITIZER_MARKS = ("AddressSanitizer", "runtime error:", "LeakSanitizer", "UndefinedBehaviorSanitizer")


def corpus_files(dirs, packages):
    files = []
    for d in dirs:
        for p in sorted(pathlib.Path(d).rglob("*")):
            if p.suffix.lower() in (".gltf", ".glb") and p.is_file():
                files.append(str(p))
    for pkg in packages:
        try:
            out = subprocess.run(["dpkg", "-L", pkg], capture_output=True, text=True, check=True).stdout
        except (OSError, subprocess.CalledProcessError):
            continue
        files += sorted(line for line in out.splitlines()
                        if line.lower().endswith((".gltf", ".glb")) and os.path.isfile(line))
    return files


def check_one(veach, path, workdir, index, args):
    """Returns None when `path` keeps the contract, else a one-line description of the fault."""
    stem = f"{index:03d}"
    image = os.path.join(workdir, stem + ".exr")
    stats = os.path.join(workdir, stem + ".json")
    cmd = [veach, "render", path, "-o", image, "--width", str(args.width), "--spp", str(args.spp),
           "--threads", "1", "--time", str(args.render_seconds), "--quiet", "--stats-json", stats]
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, errors="replace", timeout=args.timeout)
    except subprocess.TimeoutExpired:
        return f"hang: still running after {args.timeout}s"
    err = proc.stderr
    leftovers = [f for f in os.listdir(workdir) if f.startswith(stem) and f not in (stem + ".exr", stem + ".json")]
    if proc.returncode < 0:
        return f"killed by signal {signal.Signals(-proc.returncode).name}: {err.strip()[-400:]}"
    if any(mark in err for mark in SANITIZER_MARKS):
        return "sanitizer report: " + err.strip()[-1500:]
    if leftovers:
        return f"left temporary files {leftovers}"
    if proc.returncode == 0:
        if not os.path.isfile(image) or os.path.getsize(image) == 0:
            return "exit 0 but no image written"
        try:
            with open(stats) as f:
                nonfinite = json.load(f)["nonfinite_samples"]
        except (OSError, ValueError, KeyError) as e:
            return f"exit 0 but unreadable stats: {e}"
        if nonfinite != 0:
            return f"{nonfinite} non-finite samples"
        return None
    if proc.returncode == 2:
        lines = err.splitlines()
        if len(lines) != 1:
            return f"exit 2 with {len(lines)} stderr lines (want exactly one): {err.strip()[:400]!r}"
        if path not in lines[0]:
            return f"exit 2 but the message does not name the file: {lines[0]!r}"
        if os.path.exists(image):
            return "exit 2 but an image was written"
        return None
    return f"exit code {proc.returncode} (want 0 or 2): {err.strip()[-400:]}"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--veach", required=True)
    ap.add_argument("--dir", action="append", default=[], help="a folder searched recursively")
    ap.add_argument("--dpkg", action="append", default=[], help="a Debian package whose files are searched")
    ap.add_argument("--jobs", type=int, default=max(1, os.cpu_count() or 1))
    ap.add_argument("--timeout", type=float, default=60.0, help="seconds per file before it counts as a hang")
    ap.add_argument("--render-seconds", type=float, default=5.0, help="the render's own --time limit")
    ap.add_argument("--width", type=int, default=32)
    ap.add_argument("--spp", type=int, default=1)
    ap.add_argument("--min-files", type=int, default=1, help="fewer files than this: fail")
    args = ap.parse_args()

    files = corpus_files(args.dir, args.dpkg)
    if len(files) < args.min_files:
        print(f"check_corpus: only {len(files)} files found (packages {args.dpkg} not installed? scripts/install-deps.sh installs them)")
        return 1
    failures = []
    counts = {0: 0, 2: 0}
    with tempfile.TemporaryDirectory(prefix="veach-corpus-") as work:
        with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
            futures = {}
            for i, path in enumerate(files):
                d = os.path.join(work, f"{i:03d}")
                os.mkdir(d)  # one folder per file: leftovers are attributed to the right file
                futures[pool.submit(check_one, args.veach, path, d, i, args)] = (path, d)
            for fut in concurrent.futures.as_completed(futures):
                path, d = futures[fut]
                fault = fut.result()
                if fault:
                    failures.append((path, fault))
                else:
                    counts[0 if any(f.endswith(".exr") for f in os.listdir(d)) else 2] += 1
    print(f"check_corpus: {len(files)} files: {counts[0]} rendered, {counts[2]} refused with exit 2, "
          f"{len(failures)} broke the contract")
    for path, fault in sorted(failures):
        print(f"FAIL {path}: {fault}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""The Blender add-on, headless: Blender builds a small scene (blender_scene.py), renders it with
the VEACH engine through libveach, and cancels a second render. Checks:
- the add-on's Combined pass agrees with `veach render` of the same glTF export (the same
  renderer, settings and seed: channel means within 2%, a margin for the export round trip only);
- Blender's image is scene-linear (its mean matches the linear EXR of the CLI, not a display
  transform of it) and has the Depth pass, finite in front of the camera;
- a cancel half a second in stops the render well before its million samples would finish;
- the stats line says "ETA unknown" before the first pass and the ETA after it;
- Blender's panels a user expects (output, format, colour management, camera lens, material and
  World surface, light) list the engine, as do its own settings and passes panels.
Fails when Blender is missing (scripts/install-deps.sh installs it).
Usage: check_blender.py --library LIBVEACH --veach VEACH_CLI --addon plugins/blender
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile


def channel_means(path, prefix=""):
    import OpenImageIO as oiio
    buf = oiio.ImageBuf(path)
    if buf.has_error:
        sys.exit(f"FAIL: cannot read {path}: {buf.geterror()}")
    names = list(buf.spec().channelnames)
    pixels = buf.get_pixels(oiio.FLOAT).reshape(-1, len(names))
    return {n[len(prefix):]: pixels[:, i] for i, n in enumerate(names) if n.startswith(prefix)}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--library", required=True)
    ap.add_argument("--veach", required=True)
    ap.add_argument("--addon", required=True)
    args = ap.parse_args()
    blender = shutil.which("blender")
    if not blender:
        sys.exit("FAIL: blender is not installed (scripts/install-deps.sh installs it)")

    needed = subprocess.run(["objdump", "-p", args.library], capture_output=True, text=True).stdout
    if "libasan" in needed:
        sys.exit("FAIL: libveach is built with AddressSanitizer; Blender cannot load it")

    tmp = tempfile.mkdtemp(prefix="veach_blender_test_")
    try:
        addons = os.path.join(tmp, "addons")
        os.makedirs(addons)
        os.symlink(os.path.abspath(args.addon), os.path.join(addons, "veach"))
        env = dict(os.environ, VEACH_LIBRARY=os.path.abspath(args.library))
        script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "blender_scene.py")
        p = subprocess.run([blender, "-b", "--factory-startup", "--python-exit-code", "1", "--python", script,
                            "--", tmp, addons], env=env, capture_output=True, text=True, timeout=180)
        report_path = os.path.join(tmp, "blender.json")
        if p.returncode != 0 or not os.path.exists(report_path):
            sys.exit(f"FAIL: blender exited {p.returncode}\n{p.stdout[-3000:]}\n{p.stderr[-3000:]}")
        with open(report_path) as f:
            report = json.load(f)
        print("Blender:", report)
        if report["render_status"] != "done":
            sys.exit(f"FAIL: the add-on's render did not finish: {report['render_status']}")

        cli_exr = os.path.join(tmp, "cli.exr")
        p = subprocess.run([args.veach, "render", os.path.join(tmp, "scene.gltf"), "-o", cli_exr, "--width", "64",
                            "--height", "48", "--spp", "32", "--integrator", "pt", "--seed", "3", "--filter",
                            "blackman-harris", "--filter-width", "1.5", "--quiet"], capture_output=True, text=True,
                           timeout=120)
        if p.returncode != 0:
            sys.exit(f"FAIL: veach render exited {p.returncode}: {p.stderr}")

        ours = channel_means(os.path.join(tmp, "blender.exr"), "ViewLayer.")
        cli = channel_means(cli_exr)
        for c in "RGB":
            a, b = float(ours[f"Combined.{c}"].mean()), float(cli[c].mean())
            print(f"channel {c}: add-on {a:.5f}, veach render {b:.5f}")
            if not b > 0.01:
                sys.exit(f"FAIL: the CLI's render is black in {c}")
            if abs(a - b) > 0.02 * b:
                sys.exit(f"FAIL: channel {c}: the add-on's mean {a:.5f} differs from the CLI's {b:.5f} by over 2%")
        # Rows: Blender stores them bottom-up, libveach top-down; the add-on flips. The two halves
        # (floor below, sky above) must each agree, or the image is upside down.
        half = 24 * 64
        for name, rows in (("top", slice(0, half)), ("bottom", slice(half, None))):
            a, b = float(ours["Combined.G"][rows].mean()), float(cli["G"][rows].mean())
            print(f"{name} half, G: add-on {a:.5f}, veach render {b:.5f}")
            if abs(a - b) > 0.02 * max(b, 1e-3):
                sys.exit(f"FAIL: the {name} half differs (add-on {a:.5f}, CLI {b:.5f}): rows flipped?")
        depth = ours.get("Depth.Z")
        if depth is None:
            sys.exit("FAIL: no Depth pass in Blender's result")
        hit = depth[depth < 1e9]
        if hit.size < depth.size // 4 or not (hit > 0).all():
            sys.exit(f"FAIL: Depth pass: {hit.size} of {depth.size} pixels hit, min {hit.min() if hit.size else None}")

        # The cancelled render asked for 2^20 samples per pixel (minutes); cancel came at 0.5 s.
        if report["cancel_status"] != "cancelled":
            sys.exit(f"FAIL: cancel: status {report['cancel_status']}")
        print(f"cancel: the render returned {report['cancel_seconds']:.2f} s after starting (cancel at 0.5 s)")
        if report["cancel_seconds"] > 20:
            sys.exit("FAIL: the cancelled render did not stop promptly")
        before, during = report["progress_lines"]
        print("stats lines:", report["progress_lines"])
        if "ETA unknown" not in before or "50%" not in during or "ETA 3 s" not in during:
            sys.exit(f"FAIL: the stats line should say 'ETA unknown' before the first pass: {report['progress_lines']}")
        if report["panels_missing"]:
            sys.exit(f"FAIL: panels without the VEACH engine: {report['panels_missing']}")
        print("PASS: the add-on renders what `veach render` renders, with Depth, and cancels")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()

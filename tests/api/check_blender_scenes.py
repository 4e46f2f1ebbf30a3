#!/usr/bin/python3
"""Committed .blend files (saved by the scene generator, another Blender process) rendered by the
Blender add-on exactly as a user types it,
  blender -b NAME.blend --addons veach -E VEACH --python-expr SAMPLES -o //out_# -F OPEN_EXR -f 1
(SAMPLES sets Render > Sampling > Samples to 256, as a user would in the panel: the files keep
the generator's 64, at which path tracing's 16x16 blocks on film_transparent scatter by 1-5% over
seeds, too close to the bound; at 256 they stay under 1%) and compared with the committed Cycles reference NAME.cycles.exr: channel means within 2% and
16x16 block means within 5% (tests/tools/image_compare.py). For the World scenes this is what
the add-on carries over beside the glTF: world_color's uniform colour x strength, world_hdri's
equirectangular image, strength and Mapping rotation (a wrong rotation moves the warm patch that
lights the scene, and the floor's shading and the background fail the blocks). A scene whose
reference has alpha (film_transparent: Film > Transparent, RGBA) is checked for it too: the
background exactly (0, 0, 0, 0) where Cycles' is (edge pixels aside), covered pixels alpha 1,
alpha's mean within 2% and its 16x16 block means within 5% of Cycles'. Then the first
scene again with a render region (border 0.25-0.75 x 0.5-1.0, Crop on, set by --python-expr as
a user would): exactly that part of the full frame.
The scenes hold nothing the add-on drops, so any "Veach:" warning in the log fails too.
Usage: check_blender_scenes.py --library LIBVEACH --addon plugins/blender --repo ROOT SCENE..."""
import argparse
import os
import shutil
import sys
import tempfile

from blender_harness import failed, find_blender, install_addon, run_blender

MEAN_TOLERANCE = 0.02
BLOCK_TOLERANCE = 0.05
SAMPLES = "import bpy; bpy.context.scene.cycles.samples = 256"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--library", required=True)
    ap.add_argument("--addon", required=True)
    ap.add_argument("--repo", required=True)
    ap.add_argument("scenes", nargs="+")
    args = ap.parse_args()
    blender = find_blender()
    sys.path.insert(0, os.path.join(args.repo, "tests", "tools"))
    import image_compare

    tmp = tempfile.mkdtemp(prefix="veach_blender_scenes_")
    failures = []
    try:
        env = install_addon(tmp, args.addon, args.library)
        for name in args.scenes:
            work = os.path.join(tmp, name)
            shutil.copytree(os.path.join(args.repo, "tests", "data", "scenes", name), work)
            command = [blender, "-b", name + ".blend", "--addons", "veach", "-E", "VEACH", "--python-expr", SAMPLES,
                       "-o", "//out_#", "-F", "OPEN_EXR", "-f", "1"]
            code, log = run_blender(command, work, env)
            out = os.path.join(work, "out_1.exr")
            if failed(code, log) or not os.path.exists(out):
                failures.append(f"{name}: exit {code}\n$ {' '.join(command)}\n{log[-3000:]}")
                continue
            warnings = [line for line in log.splitlines() if "Veach:" in line]
            result = image_compare.compare(image_compare.load(out),
                                           image_compare.load(os.path.join(work, name + ".cycles.exr")))
            worst = max(abs(m - 1) for m in result["mean"])
            ok = worst <= MEAN_TOLERANCE and result["blocks"] <= BLOCK_TOLERANCE and result["nonfinite"] == 0
            print(f"{name}: mean {' '.join('%.4f' % m for m in result['mean'])}, blocks {result['blocks']:.4f}, "
                  f"relmse {result['relmse']:.4g}{'' if ok else '  <- FAIL'}")
            for line in warnings:
                print("   ", line.strip())
            if warnings:  # these scenes hold nothing the add-on drops
                failures.append(f"{name}: unexpected warnings {warnings}")
            if not ok:
                failures.append(f"{name}: differs from Cycles (mean {result['mean']}, blocks {result['blocks']:.4f})")
            failures += image_compare.check_alpha(name, out, os.path.join(work, name + ".cycles.exr"),
                                                  MEAN_TOLERANCE, BLOCK_TOLERANCE)
        # A render region (Blender's border with Crop) is that part of the full frame: the same
        # pixels, since each pixel's samples depend only on the seed and the pixel.
        name = args.scenes[0]
        work = os.path.join(tmp, name)
        border = (SAMPLES + "; r = bpy.context.scene.render; r.use_border = True; r.use_crop_to_border = True; "
                  "r.border_min_x, r.border_max_x, r.border_min_y, r.border_max_y = 0.25, 0.75, 0.5, 1.0")
        command = [blender, "-b", name + ".blend", "--addons", "veach", "-E", "VEACH", "--python-expr", border,
                   "-o", "//border_#", "-F", "OPEN_EXR", "-f", "1"]
        code, log = run_blender(command, work, env)
        full, region = (os.path.join(work, f) for f in ("out_1.exr", "border_1.exr"))
        if failed(code, log) or not os.path.exists(region) or not os.path.exists(full):
            failures.append(f"border render: exit {code}\n{log[-3000:]}")
        else:
            whole, part = image_compare.load(full), image_compare.load(region)
            h, w = whole.shape[:2]
            expected = whole[0:h // 2, w // 4:3 * w // 4]  # rows from the top: border y 0.5..1 is the top half
            same = part.shape == expected.shape and float(abs(part - expected).max()) == 0.0
            print(f"border 0.25-0.75 x 0.5-1.0 with crop: {part.shape[1]}x{part.shape[0]}, "
                  f"{'equal to' if same else 'DIFFERENT from'} the full frame's region")
            if not same:
                failures.append("the border render is not the full frame's region")
        if failures:
            sys.exit("FAIL:\n  " + "\n  ".join(failures))
        print("PASS: the add-on's renders of the saved .blend files match Cycles'")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()

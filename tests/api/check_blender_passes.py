#!/usr/bin/python3
"""The add-on's passes and warnings, as a user gets them: a .blend saved by one Blender process
(blender_passes_scene.py: an SSS floor, a ball with a Noise Texture and a collection instance of
it, a sun, two dim area lights with a 90 degree spread, every pass on) and
rendered by another with
  blender -b passes.blend --addons veach -E VEACH -o //out_# -F OPEN_EXR_MULTILAYER -f 1
Checks, in the multi-layer EXR Blender writes:
- the passes carry Blender's names: Combined, Depth, Normal, Denoising Albedo, Denoising Normal,
  Variance, Sample Count, and, since Render > Sampling > Denoise is on (Cycles' default, taken with
  Use Cycles Settings), Denoising Depth and Noisy Image;
- Denoise denoised: on the floor the Combined pass is smoother than the Noisy Image (the mean
  squared step between neighbouring pixels at least 4 times lower), and its mean is within 2% of
  the noisy one's;
- Sample Count is the 16 samples the .blend's (Cycles) settings ask for, in every pixel;
- on the floor the Normal passes are Blender's world up (0, 0, 1) (Z up, not glTF's Y up), the
  albedo is the floor's base colour and the depth is finite; the variance is finite and >= 0;
- the ball and its collection instance are two nodes of one shared mesh in the export;
- Blender's log has exactly one WARNING for the dropped subsurface scattering, one for the
  procedural texture and one for the area lights' spread of 90 degrees (rendered as 180).
Usage: check_blender_passes.py --library LIBVEACH --addon plugins/blender"""
import argparse
import json
import os
import shutil
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

from blender_harness import find_blender, install_addon, run_or_exit

PASSES = {"Combined": "RGBA", "Depth": "Z", "Normal": "XYZ", "Denoising Albedo": "RGB",
          "Denoising Normal": "XYZ", "Variance": "RGB", "Sample Count": "X", "Denoising Depth": "Z",
          "Noisy Image": "RGBA"}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--library", required=True)
    ap.add_argument("--addon", required=True)
    args = ap.parse_args()
    blender = find_blender()
    tmp = tempfile.mkdtemp(prefix="veach_blender_passes_")
    try:
        env = install_addon(tmp, args.addon, args.library)
        builder = os.path.join(os.path.dirname(os.path.abspath(__file__)), "blender_passes_scene.py")
        run_or_exit([blender, "-b", "--factory-startup", "--addons", "veach", "--python-exit-code", "1", "--python",
                     builder, "--", os.path.join(tmp, "passes.blend")], tmp, env, "building passes.blend")
        export_dir = os.path.join(tmp, "export")
        log = run_or_exit([blender, "-b", "passes.blend", "--addons", "veach", "-E", "VEACH", "-o", "//out_#", "-F",
                           "OPEN_EXR_MULTILAYER", "-f", "1"], tmp, dict(env, VEACH_BLENDER_KEEP_EXPORT=export_dir),
                          "rendering passes.blend")
        failures = []
        with open(os.path.join(export_dir, "frame.gltf")) as f:
            gltf = json.load(f)
        balls = [n for n in gltf["nodes"] if n.get("name") == "ball"]
        print("ball nodes in the export:", [(n["mesh"], n["matrix"][12:15]) for n in balls])
        if len(balls) != 2 or balls[0]["mesh"] != balls[1]["mesh"] or balls[0]["matrix"] == balls[1]["matrix"]:
            failures.append(f"the ball and its collection instance are not two placements of one mesh: {balls}")
        for kind in ("subsurface scattering", "procedural texture", "spread"):
            lines = [line for line in log.splitlines() if "Veach:" in line and kind in line]
            print(f"warnings about {kind}: {lines}")
            if len(lines) != 1 or not lines[0].lstrip().lower().startswith("warning"):
                failures.append(f"expected one WARNING about {kind}, got {lines}")

        image = oiio.ImageBuf(os.path.join(tmp, "out_1.exr"))
        if image.has_error:
            sys.exit(f"FAIL: no multi-layer EXR: {image.geterror()}")
        names = list(image.spec().channelnames)
        pixels = image.get_pixels(oiio.FLOAT).reshape(image.spec().height, image.spec().width, -1)
        channel = {n: pixels[..., i] for i, n in enumerate(names)}
        for name, ids in PASSES.items():
            missing = [f"ViewLayer.{name}.{c}" for c in ids if f"ViewLayer.{name}.{c}" not in channel]
            if missing:
                failures.append(f"pass {name}: channels {missing} missing (have {names})")
        if failures:
            sys.exit("FAIL:\n  " + "\n  ".join(failures))

        def get(name, ids):
            return np.stack([channel[f"ViewLayer.{name}.{c}"] for c in ids], axis=-1)

        counts = get("Sample Count", "X")
        print(f"Sample Count: {np.unique(counts)}")
        if not (counts == 16).all():
            failures.append(f"Sample Count is not 16 everywhere: {np.unique(counts)}")
        floor = (slice(-4, None), slice(4, 12))  # the bottom rows, left of the ball: the floor
        for name in ("Normal", "Denoising Normal"):
            n = get(name, "XYZ")[floor].reshape(-1, 3).mean(axis=0)
            print(f"{name} on the floor: {n}")
            if np.abs(n - [0, 0, 1]).max() > 0.02:
                failures.append(f"{name} on the floor is {n}, not Blender's up (0, 0, 1)")
        albedo = get("Denoising Albedo", "RGB")[floor].reshape(-1, 3).mean(axis=0)
        print(f"Denoising Albedo on the floor: {albedo}")
        if np.abs(albedo - [0.8, 0.5, 0.3]).max() > 0.02:
            failures.append(f"Denoising Albedo on the floor is {albedo}, not its base colour (0.8, 0.5, 0.3)")
        depth = get("Depth", "Z")[floor]
        if not (np.isfinite(depth) & (depth > 0) & (depth < 100)).all():
            failures.append(f"Depth on the floor is not a distance: {depth.min()} .. {depth.max()}")
        variance = get("Variance", "RGB")
        if not (np.isfinite(variance).all() and (variance >= 0).all() and variance.max() > 0):
            failures.append("Variance is not finite and >= 0 (and somewhere > 0)")
        combined = get("Combined", "RGB")
        if not combined.mean() > 0.01:
            failures.append("the Combined pass is black")
        noisy = get("Noisy Image", "RGB")

        def roughness(x):
            return float((np.diff(x, axis=1) ** 2).mean() + (np.diff(x, axis=0) ** 2).mean())

        smooth, rough = roughness(combined[floor]), roughness(noisy[floor])
        print(f"Combined: mean {combined.mean():.4f}, roughness on the floor {smooth:.3g}; "
              f"Noisy Image: mean {noisy.mean():.4f}, roughness on the floor {rough:.3g}")
        if not smooth * 4 < rough:
            failures.append("Denoise did not denoise: the Combined pass is as rough as the Noisy Image")
        if abs(combined.mean() / noisy.mean() - 1) > 0.02:
            failures.append(f"the denoised mean {combined.mean()} is not within 2% of the noisy {noisy.mean()}")
        depth = get("Denoising Depth", "Z")[floor]
        if not (np.isfinite(depth) & (depth > 0) & (depth < 100)).all():
            failures.append(f"Denoising Depth on the floor is not a distance: {depth.min()} .. {depth.max()}")
        if failures:
            sys.exit("FAIL:\n  " + "\n  ".join(failures))
        print("PASS: Blender's passes and one warning per dropped kind")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()

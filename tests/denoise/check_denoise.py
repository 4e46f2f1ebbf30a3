#!/usr/bin/python3
"""check_denoise.py --veach BIN --scenes DIR --scene NAME [--integrator I] [--ratio R] [--block-tol T]
                    [--edges] [--reference-floor F]

Renders SCENES/NAME/NAME.gltf at the reference's resolution with --denoise and the noisy image
kept (--passes combined,noisy), at 16 and 64 spp, and compares both with the Cycles reference
(tests/tools/image_compare.py's relMSE):
  - the denoised image's error is at least --ratio times lower than the noisy image's, both
    counted above --reference-floor (default 0): the relMSE a converged render keeps against this
    reference, which is converged far but not perfectly (its own noise shows in spheres'
    caustics), so that no image can come closer to it than that;
  - no darkening or brightening: each channel's mean within --block-tol of the noisy image's,
    and every 32x32 block mean (RGB summed; the blocks brighter than 5% of the average) no
    further from the reference's than --block-tol plus the noisy block's own distance from it
    (a block mean of a few samples per pixel is that far off by noise alone, fireflies above
    all, and the denoiser is judged on what it adds);
  - with --edges, a texture's edges survive: across the reference's sharpest 2% of pixel steps
    (the checker's edges), the denoised image's steps keep at least 90% of the reference's
    contrast on average (a blur of one pixel halves it);
  - the stats report the denoiser's time.
Exit 0 pass, 1 fail. VEACH_TEST_SPP_DIVISOR (make test-sanitize) divides the sample counts and
checks only that the denoiser runs, gives finite values and keeps the means (within the
tolerance times the square root of the divisor)."""
import argparse, json, os, subprocess, sys, tempfile

import numpy as np
import OpenImageIO as oiio

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
import image_compare as compare  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--veach", required=True)
ap.add_argument("--scenes", required=True)
ap.add_argument("--scene", required=True)
ap.add_argument("--integrator", default="pt")
ap.add_argument("--ratio", type=float, default=4.0)
ap.add_argument("--block-tol", type=float, default=0.02)
ap.add_argument("--edges", action="store_true")
ap.add_argument("--reference-floor", type=float, default=0.0)
a = ap.parse_args()
divisor = max(1, int(os.environ.get("VEACH_TEST_SPP_DIVISOR", "1") or 1))
spps = [16, 64]


def layer(path, name):
    image = oiio.ImageBuf(path)
    names = list(image.spec().channelnames)
    pixels = np.asarray(image.get_pixels(oiio.FLOAT), dtype=np.float64)
    return pixels[..., [names.index("ViewLayer.%s.%s" % (name, c)) for c in "RGB"]]


def worst_block(denoised, noisy, reference, block):
    """The most a denoised block mean is further (relative) from the reference's than the noisy
    one's, over the lit blocks."""
    bd, bn, br = (compare.block_means(i, block).sum(-1) for i in (denoised, noisy, reference))
    lit = br > 0.05 * br.mean()
    return float(np.max(np.abs(bd[lit] - br[lit]) / br[lit] - np.abs(bn[lit] - br[lit]) / br[lit]))


def edge_contrast(image, reference):
    """The image's pixel-to-pixel steps (across and down, RGB summed) over the reference's sharpest
    2%, as a fraction of the reference's."""
    def steps(x):
        return np.concatenate([np.abs(np.diff(x, axis=1)).sum(-1).ravel(), np.abs(np.diff(x, axis=0)).sum(-1).ravel()])
    s_image, s_reference = steps(image), steps(reference)
    sharp = s_reference >= np.quantile(s_reference, 0.98)
    return float(s_image[sharp].mean() / s_reference[sharp].mean())


scene_dir = os.path.join(a.scenes, a.scene)
meta = json.load(open(os.path.join(scene_dir, a.scene + ".cycles.json")))
reference = compare.load(os.path.join(scene_dir, a.scene + ".cycles.exr"))
results = {}
ok = True
with tempfile.TemporaryDirectory() as tmp:
    for spp in spps:
        out, stats = os.path.join(tmp, "%d.exr" % spp), os.path.join(tmp, "%d.json" % spp)
        subprocess.run([a.veach, "render", os.path.join(scene_dir, a.scene + ".gltf"), "-o", out,
                        "--width", str(meta["width"]), "--height", str(meta["height"]),
                        "--spp", str(max(2, spp // divisor)), "--integrator", a.integrator, "--denoise",
                        "--passes", "combined,noisy", "--quiet", "--stats-json", stats] + meta.get("veach_args", []),
                       check=True)
        denoised, noisy = layer(out, "Combined"), layer(out, "Noisy")
        seconds = json.load(open(stats))["seconds"]
        results[spp] = dict(den=compare.compare(denoised, reference), noisy=compare.compare(noisy, reference),
                            blocks=worst_block(denoised, noisy, reference, 32),
                            edges=edge_contrast(denoised, reference),
                            render=seconds["render"], denoise=seconds["denoise"])
floor = a.reference_floor
for spp in spps:
    r = results[spp]
    noisy, den = r["noisy"]["relmse"], r["den"]["relmse"]
    ratio = (noisy - floor) / max(den - floor, 1e-12)
    print("%s %s %d spp: relMSE noisy %.5f denoised %.5f (reference's share %.5f): %.1fx lower; "
          "blocks further from the reference than the noisy ones by at most %.4f (32x32); edge contrast %.3f; "
          "render %.2fs denoise %.2fs" % (a.scene, a.integrator, max(2, spp // divisor), noisy, den, floor, ratio, r["blocks"],
                                         r["edges"], r["render"], r["denoise"]))
    if r["den"]["nonfinite"]:
        print("FAIL: non-finite values in the denoised image"); ok = False
    if divisor > 1:
        continue
    if ratio < a.ratio:
        print("FAIL: the denoised error is only %.2fx lower than the noisy one's (at least %.1fx)" % (ratio, a.ratio))
        ok = False
    if r["blocks"] > a.block_tol:
        print("FAIL: a 32x32 block mean moved %.4f further from the reference (> %.3f)" % (r["blocks"], a.block_tol))
        ok = False
    if a.edges and r["edges"] < 0.9:
        print("FAIL: the texture's edges keep only %.3f of their contrast (at least 0.9)" % r["edges"]); ok = False
# At a fraction of the samples (sanitizer builds) the means are noisier by sqrt(divisor).
mean_tol = a.block_tol * divisor ** 0.5
for spp in spps:
    for c, m in zip("RGB", results[spp]["den"]["mean"]):
        if abs(m / results[spp]["noisy"]["mean"]["RGB".index(c)] - 1.0) > mean_tol:
            print("FAIL: channel %s mean moved by more than %.3f" % (c, mean_tol)); ok = False
sys.exit(0 if ok else 1)

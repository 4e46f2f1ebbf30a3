#!/usr/bin/python3
"""image_compare.py TEST.exr REFERENCE.exr [--json]

How far a render is from a reference, in the measures the tests and `make bench` use:
  relmse     mean over pixels of the channel-averaged (x - r)^2 / (r^2 + 0.01); the worst 0.1% of
             pixels are left out, so one firefly does not decide a comparison of converged images
  mean       per channel, mean(x) / mean(r): 1 means no bias in overall brightness
  blocks     the largest relative difference of 16x16 block means (RGB summed), over the blocks
             brighter than 5% of the average block: a systematic error shows here even when
             per-pixel noise is high
  nonfinite  NaN and infinite values in TEST (they count as 0 in the other measures)
check_alpha compares a transparent film's alpha with a reference's.
Needs Debian's python3-numpy and python3-openimageio."""
import json
import sys

import numpy as np
import OpenImageIO as oiio

BLOCK = 16


def load(path):
    """The first three channels of an image as a float64 H x W x 3 array."""
    image = oiio.ImageBuf(path)
    if image.has_error:
        raise IOError("cannot read %s: %s" % (path, image.geterror()))
    pixels = image.get_pixels(oiio.FLOAT)
    if pixels is None or pixels.size == 0:
        raise IOError("cannot read the pixels of %s" % path)
    return np.asarray(pixels, dtype=np.float64)[..., :3]


def block_means(image, block=BLOCK):
    """Means of the whole block x block tiles (a partial last row or column is left out)."""
    h, w = image.shape[0] // block * block, image.shape[1] // block * block
    return image[:h, :w].reshape(h // block, block, w // block, block, image.shape[2]).mean(axis=(1, 3))


def compare(test, reference):
    if test.shape != reference.shape:
        raise ValueError("sizes differ: %s against %s" % (test.shape, reference.shape))
    nonfinite = int(np.count_nonzero(~np.isfinite(test)))
    test = np.where(np.isfinite(test), test, 0.0)
    per_pixel = ((test - reference) ** 2 / (reference ** 2 + 0.01)).mean(axis=2).ravel()
    kept = np.sort(per_pixel)[: max(1, int(per_pixel.size * 0.999))]
    mean = test.reshape(-1, 3).mean(axis=0) / np.maximum(reference.reshape(-1, 3).mean(axis=0), 1e-12)
    bt = block_means(test).sum(axis=-1)
    br = block_means(reference).sum(axis=-1)
    lit = br > 0.05 * br.mean()
    blocks = float(np.max(np.abs(bt[lit] - br[lit]) / br[lit])) if lit.any() else 0.0
    return {"relmse": float(kept.mean()), "mean": mean.tolist(), "blocks": blocks, "nonfinite": nonfinite}


def alpha(path):
    """The alpha channel of an image (H x W float64), or None when it has none."""
    image = oiio.ImageBuf(path)
    names = list(image.spec().channelnames)
    if "A" not in names:
        return None
    return np.asarray(image.get_pixels(oiio.FLOAT))[..., names.index("A")].astype(np.float64)


def interior(mask):
    """The pixels of mask whose 8 neighbours are in mask too (edges left out: partly covered)."""
    padded = np.pad(mask, 1, constant_values=False)
    h, w = mask.shape
    return np.all([padded[1 + dy:1 + dy + h, 1 + dx:1 + dx + w] for dy in (-1, 0, 1) for dx in (-1, 0, 1)], axis=0)


def check_alpha(name, ours_path, reference_path, mean_tol, block_tol):
    """A transparent film's alpha against a reference's (Cycles' Film > Transparent): the
    background (where the reference's alpha is 0, edges aside) exactly (0, 0, 0, 0), covered pixels
    alpha 1, the mean alpha within mean_tol and 16x16 block means of alpha within block_tol.
    Returns the failures (none for an opaque reference)."""
    reference, ours = alpha(reference_path), alpha(ours_path)
    if reference is None or reference.min() >= 1.0:
        return []  # an opaque film: alpha 1, nothing to compare
    if ours is None:
        return [f"{name}: the image has no alpha channel"]
    rgb = load(ours_path)
    background, covered = interior(reference == 0.0), interior(reference == 1.0)
    problems = []
    leaks = np.count_nonzero((rgb[background] != 0.0).any(axis=-1) | (ours[background] != 0.0))
    opaque = np.count_nonzero(ours[covered] != 1.0)
    mean = ours.mean() / reference.mean()
    blocks_ours, blocks_ref = (block_means(a[..., None])[..., 0] for a in (ours, reference))
    lit = blocks_ref > 0.05 * blocks_ref.mean()
    blocks = float(np.max(np.abs(blocks_ours[lit] - blocks_ref[lit]) / blocks_ref[lit]))
    print(f"{name} alpha: mean {mean:.4f} of the reference's, blocks {blocks:.4f}; {leaks} of "
          f"{np.count_nonzero(background)} background pixels not (0, 0, 0, 0), {opaque} of "
          f"{np.count_nonzero(covered)} covered pixels not alpha 1")
    if leaks:
        problems.append(f"{name}: {leaks} background pixels are not (0, 0, 0, 0)")
    if opaque:
        problems.append(f"{name}: {opaque} covered pixels do not have alpha 1")
    if abs(mean - 1.0) > mean_tol or blocks > block_tol:
        problems.append(f"{name}: alpha differs from the reference's (mean ratio {mean:.4f}, blocks {blocks:.4f})")
    return problems


def main(argv):
    paths = [a for a in argv if not a.startswith("--")]
    if len(paths) != 2:
        sys.exit(__doc__)
    result = compare(load(paths[0]), load(paths[1]))
    if "--json" in argv:
        print(json.dumps(result))
    else:
        print("relmse %.5g  mean %s  blocks %.4f  nonfinite %d" % (
            result["relmse"], " ".join("%.4f" % m for m in result["mean"]), result["blocks"], result["nonfinite"]))


if __name__ == "__main__":
    main(sys.argv[1:])

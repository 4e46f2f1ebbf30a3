#!/usr/bin/env python3
"""The example gallery stays what README and `make gallery` promise.

- every scene of examples/gallery/gallery.json exists and renders (tiny: 48 px wide, 2 spp)
  with its own arguments, from its own folder, to a PNG that is not black;
- the command in examples/gallery/README.md for each scene is exactly gallery.json's (the
  arguments `make gallery` uses, at the gallery's resolution);
- docs/gallery.png, the contact sheet README shows, exists with one tile per scene in rows of
  three at the gallery's resolution plus each tile's title strip.
Usage: check_gallery.py --source REPO --veach VEACH_CLI
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
from gallery import COLUMNS, LABEL_HEIGHT  # noqa: E402  (the contact sheet's layout)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--source", required=True)
    ap.add_argument("--veach", required=True)
    args = ap.parse_args()
    gallery_dir = os.path.join(args.source, "examples", "gallery")
    with open(os.path.join(gallery_dir, "gallery.json")) as f:
        gallery = json.load(f)
    with open(os.path.join(gallery_dir, "README.md")) as f:
        readme = f.read()
    failures = []
    with tempfile.TemporaryDirectory(prefix="veach_gallery_") as tmp:
        for scene in gallery["scenes"]:
            path = os.path.normpath(os.path.join(gallery_dir, scene["file"]))
            if not os.path.exists(path):
                failures.append("%s: %s does not exist" % (scene["name"], path))
                continue
            expected = "`veach render %s -o %s.png --width %d --height %d %s`" % (
                os.path.basename(path), scene["name"], gallery["width"], gallery["height"], " ".join(scene["args"]))
            if expected not in readme:
                failures.append("%s: README does not give the command %s" % (scene["name"], expected))
            tiny = list(scene["args"])
            k = tiny.index("--spp")
            tiny[k + 1] = "2"
            out = os.path.join(tmp, scene["name"] + ".png")
            result = subprocess.run([args.veach, "render", os.path.basename(path), "-o", out, "--width", "48", "-q"]
                                    + tiny, cwd=os.path.dirname(path), capture_output=True, text=True)
            if result.returncode != 0:
                failures.append("%s: veach exited %d: %s" % (scene["name"], result.returncode, result.stderr.strip()))
                continue
            pixels = oiio.ImageBuf(out).get_pixels(oiio.FLOAT)
            if not np.isfinite(pixels).all() or pixels[..., :3].mean() < 0.02:
                failures.append("%s: the image is black or not finite (mean %.4f)" % (scene["name"], pixels.mean()))
            else:
                print("gallery: %-12s renders (mean %.3f)" % (scene["name"], pixels[..., :3].mean()))
    sheet = os.path.join(args.source, "docs", "gallery.png")
    if not os.path.exists(sheet):
        failures.append("docs/gallery.png is missing: run make gallery")
    else:
        spec = oiio.ImageInput.open(sheet).spec()
        rows = (len(gallery["scenes"]) + COLUMNS - 1) // COLUMNS
        size = (gallery["width"] * COLUMNS, (gallery["height"] + LABEL_HEIGHT) * rows)
        if (spec.width, spec.height) != size:
            failures.append("docs/gallery.png is %dx%d, make gallery writes %dx%d" % (spec.width, spec.height, *size))
    for f in failures:
        print("FAIL: " + f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

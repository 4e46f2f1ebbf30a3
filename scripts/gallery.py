#!/usr/bin/env python3
"""Render the example gallery and assemble its contact sheet (`make gallery`).

  scripts/gallery.py --veach build/veach [--out out/gallery] [--sheet docs/gallery.png]
                     [--width W] [--spp-scale F]

Reads examples/gallery/gallery.json (scene file, title and the `veach render` arguments the
gallery README gives), renders each scene to OUT/NAME.png from its own folder (so relative
arguments such as --env sky.hdr resolve as in the README), and writes the contact sheet: the
images in rows of three, each with its title, as one PNG. --spp-scale multiplies every scene's
samples (0.1 for a quick look). Exit codes: 0 done, 1 a render or the sheet failed, 2 bad
arguments.
"""
import argparse
import json
import os
import subprocess
import sys
import time

import OpenImageIO as oiio

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FONT = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"  # fonts-dejavu-core
COLUMNS = 3
LABEL_HEIGHT = 22


def scaled_spp(args, scale):
    out = list(args)
    if "--spp" in out and scale != 1.0:
        k = out.index("--spp") + 1
        out[k] = str(max(1, round(int(out[k]) * scale)))
    return out


def render(veach, gallery_dir, scene, size, out_dir, scale):
    path = os.path.normpath(os.path.join(gallery_dir, scene["file"]))
    output = os.path.join(out_dir, scene["name"] + ".png")
    command = [veach, "render", os.path.basename(path), "-o", output, "--width", str(size[0]), "--height", str(size[1]), "-q"]
    command += scaled_spp(scene["args"], scale)
    start = time.time()
    result = subprocess.run(command, cwd=os.path.dirname(path))
    if result.returncode != 0:
        raise RuntimeError("%s: veach exited %d" % (scene["name"], result.returncode))
    print("gallery: %-12s %5.1f s  %s" % (scene["name"], time.time() - start, " ".join(command[1:])), flush=True)
    return output


def contact_sheet(images, titles, path):
    tiles = [oiio.ImageBuf(p) for p in images]
    width = max(t.spec().width for t in tiles)
    height = max(t.spec().height for t in tiles) + LABEL_HEIGHT
    rows = (len(tiles) + COLUMNS - 1) // COLUMNS
    sheet = oiio.ImageBuf(oiio.ImageSpec(width * COLUMNS, height * rows, 3, oiio.UINT8))
    oiio.ImageBufAlgo.fill(sheet, (0.08, 0.08, 0.08))
    for k, (tile, title) in enumerate(zip(tiles, titles)):
        x, y = (k % COLUMNS) * width, (k // COLUMNS) * height
        rgb = oiio.ImageBufAlgo.channels(tile, (0, 1, 2))
        if not oiio.ImageBufAlgo.paste(sheet, x, y + LABEL_HEIGHT, 0, 0, rgb):
            raise RuntimeError("paste: " + oiio.geterror())
        if os.path.exists(FONT):
            oiio.ImageBufAlgo.render_text(sheet, x + 6, y + LABEL_HEIGHT - 6, title, 15, FONT, (0.9, 0.9, 0.9))
    temporary = path + ".partial.png"
    if not sheet.write(temporary):
        raise RuntimeError("%s: %s" % (path, sheet.geterror()))
    os.replace(temporary, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--veach", required=True)
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "gallery"))
    ap.add_argument("--sheet", default=os.path.join(ROOT, "docs", "gallery.png"))
    ap.add_argument("--width", type=int, help="image width (default: gallery.json's; the height follows)")
    ap.add_argument("--spp-scale", type=float, default=1.0)
    args = ap.parse_args()
    if args.spp_scale <= 0 or (args.width is not None and args.width < 1):
        ap.error("--spp-scale and --width must be positive")
    gallery_dir = os.path.join(ROOT, "examples", "gallery")
    with open(os.path.join(gallery_dir, "gallery.json")) as f:
        gallery = json.load(f)
    os.makedirs(args.out, exist_ok=True)
    veach = os.path.abspath(args.veach)
    try:
        width = args.width or gallery["width"]
        size = (width, max(1, round(width * gallery["height"] / gallery["width"])))
        images = [render(veach, gallery_dir, s, size, os.path.abspath(args.out), args.spp_scale)
                  for s in gallery["scenes"]]
        contact_sheet(images, [s["title"] for s in gallery["scenes"]], args.sheet)
    except RuntimeError as e:
        print("gallery: %s" % e, file=sys.stderr)
        return 1
    print("gallery: %s" % args.sheet)
    return 0


if __name__ == "__main__":
    sys.exit(main())

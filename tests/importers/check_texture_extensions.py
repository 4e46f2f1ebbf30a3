#!/usr/bin/env python3
"""Image-format extensions on the textured reference scene: EXT_texture_webp and KHR_texture_basisu.

- EXT_texture_webp: the checker as WebP (Debian's OIIO writes it, lossy) in the extension, the
  original PNG as the texture's fallback `source`. The scene must render as its twin that
  references a PNG of the same decoded WebP pixels (to 1e-6: the two decoders may round the
  8-bit to float conversion differently), so the WebP is what is read, and differ from the
  original PNG scene (the lossy WebP moves texels by far more).
- KHR_texture_basisu: a KTX2 image in the extension (never decoded: Debian has no transcoder)
  with the PNG as `source`: renders bit for bit as the original; the same texture with no
  `source` in a file that requires the extension is refused with exit 2 and one line.
Renders: pt, 48 px wide, 16 spp, one seed, so equal inputs give equal images.
Usage: check_texture_extensions.py --veach VEACH_CLI --scenes tests/data/scenes
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

FAILURES = []


def fail(message):
    print("FAIL: " + message, flush=True)
    FAILURES.append(message)


def render(veach, gltf, out):
    return subprocess.run([veach, "render", gltf, "-o", out, "--width", "48", "--spp", "16", "--integrator", "pt",
                           "--seed", "5", "-q"], capture_output=True, text=True)


def pixels(path):
    return np.asarray(oiio.ImageBuf(path).get_pixels(oiio.FLOAT))


def variant(tmp, doc, name, textures, images, extensions):
    d = json.loads(json.dumps(doc))
    d["textures"], d["images"] = textures, images
    d["extensionsUsed"] = sorted(set(d.get("extensionsUsed", []) + extensions))
    path = os.path.join(tmp, name + ".gltf")
    with open(path, "w") as f:
        json.dump(d, f)
    return path


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--veach", required=True)
    ap.add_argument("--scenes", required=True)
    args = ap.parse_args()
    source = os.path.join(args.scenes, "textured")
    with tempfile.TemporaryDirectory(prefix="veach_texture_ext_") as tmp:
        for f in os.listdir(source):
            if f.endswith((".gltf", ".bin", ".png")):
                shutil.copy(os.path.join(source, f), tmp)
        subprocess.run(["oiiotool", os.path.join(tmp, "checker.png"), "-o", os.path.join(tmp, "checker.webp")],
                       check=True)
        subprocess.run(["oiiotool", os.path.join(tmp, "checker.webp"), "-o", os.path.join(tmp, "webp_twin.png")],
                       check=True)
        with open(os.path.join(tmp, "checker.ktx2"), "wb") as f:
            f.write(b"\xabKTX 20\xbb\r\n\x1a\n" + bytes(64))  # a KTX2 signature: never decoded
        with open(os.path.join(tmp, "textured.gltf")) as f:
            doc = json.load(f)
        sampler = doc["textures"][0].get("sampler", 0)
        png = {"mimeType": "image/png", "uri": "checker.png"}
        scenes = {
            "original": os.path.join(tmp, "textured.gltf"),
            "webp": variant(tmp, doc, "webp", [{"sampler": sampler, "source": 0,
                                                "extensions": {"EXT_texture_webp": {"source": 1}}}],
                            [png, {"mimeType": "image/webp", "uri": "checker.webp"}], ["EXT_texture_webp"]),
            "webp_twin": variant(tmp, doc, "webp_twin", [{"sampler": sampler, "source": 0}],
                                 [{"mimeType": "image/png", "uri": "webp_twin.png"}], []),
            "basisu": variant(tmp, doc, "basisu", [{"sampler": sampler, "source": 0,
                                                    "extensions": {"KHR_texture_basisu": {"source": 1}}}],
                              [png, {"mimeType": "image/ktx2", "uri": "checker.ktx2"}], ["KHR_texture_basisu"]),
        }
        images = {}
        for name, path in scenes.items():
            out = os.path.join(tmp, name + ".exr")
            result = render(args.veach, path, out)
            if result.returncode != 0:
                fail("%s: veach exited %d: %s" % (name, result.returncode, result.stderr.strip()))
                return 1
            images[name] = pixels(out)
        # OpenImageIO (WebP) and stb (PNG) turn the same 8-bit texels into floats that may differ
        # in the last bit; anything beyond that would be different texels.
        if np.abs(images["webp"] - images["webp_twin"]).max() > 1e-6:
            fail("the WebP scene does not render as its PNG twin of the decoded WebP (largest difference %g)"
                 % np.abs(images["webp"] - images["webp_twin"]).max())
        if np.abs(images["webp"] - images["original"]).max() < 1e-3:
            fail("the WebP scene renders the fallback PNG, not the WebP")
        if not np.array_equal(images["basisu"], images["original"]):
            fail("the BasisU scene does not render its fallback PNG")

        only = json.loads(json.dumps(doc))
        only["textures"] = [{"sampler": sampler, "extensions": {"KHR_texture_basisu": {"source": 0}}}]
        only["images"] = [{"mimeType": "image/ktx2", "uri": "checker.ktx2"}]
        only["extensionsUsed"] = sorted(set(only.get("extensionsUsed", []) + ["KHR_texture_basisu"]))
        only["extensionsRequired"] = ["KHR_texture_basisu"]
        path = os.path.join(tmp, "basisu_only.gltf")
        with open(path, "w") as f:
            json.dump(only, f)
        result = render(args.veach, path, os.path.join(tmp, "basisu_only.exr"))
        lines = result.stderr.strip().splitlines()
        if result.returncode != 2 or len(lines) != 1 or "KHR_texture_basisu" not in lines[0]:
            fail("a required BasisU-only texture: expected exit 2 and one line, got %d: %s"
                 % (result.returncode, result.stderr.strip()))
        else:
            print("refused: " + lines[0])
    if not FAILURES:
        print("texture extensions: WebP decoded, BasisU fallback rendered, BasisU-only refused")
    return 1 if FAILURES else 0


if __name__ == "__main__":
    sys.exit(main())

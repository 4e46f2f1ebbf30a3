#!/usr/bin/env python3
"""What gltfpack writes renders as the original does (EXT_meshopt_compression, KHR_mesh_quantization).

Debian's gltfpack repacks the reference scenes three ways: quantized only (default), -c
(EXT_meshopt_compression, required, with fallback buffers that have no data) and -cc (higher
compression, filters), as .gltf and .glb. Each must render with exit 0 and agree with the
original scene at the same seed (pt, 64 px wide, 64 spp): channel means within 1% and 16x16
block means within 5% (the 14-bit positions and 8-12 bit normals and UVs gltfpack keeps move
the paths, so the noise no longer cancels). The codec is lossless: a -c file renders the quantized-only
file's image up to rounding (relMSE < 1e-9: triangles may come back rotated), a -cc file (whose
filters re-quantize normals) within 1% per block.
Then the decoder's guards: a truncated compressed stream, a stream range outside its buffer and
a count that overruns the view are each refused with exit 2 and one line naming the bufferView.
Usage: check_gltfpack.py --veach VEACH_CLI --scenes tests/data/scenes
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
import image_compare  # noqa: E402

SCENES = ("cornell", "textured")
VARIANTS = (("quantized", []), ("meshopt", ["-c"]), ("meshopt_high", ["-cc"]))
FAILURES = []


def fail(message):
    print("FAIL: " + message, flush=True)
    FAILURES.append(message)


def render(veach, scene, out):
    result = subprocess.run([veach, "render", scene, "-o", out, "--width", "64", "--spp", "64", "--integrator", "pt",
                             "--seed", "3", "-q"], capture_output=True, text=True)
    return result


def check_scene(veach, scenes, name, tmp):
    source = os.path.join(scenes, name, name + ".gltf")
    reference = os.path.join(tmp, name + ".exr")
    if render(veach, source, reference).returncode != 0:
        fail("%s: the original does not render" % name)
        return
    for variant, flags in VARIANTS:
        for extension in (".gltf", ".glb"):
            folder = os.path.join(tmp, name + "_" + variant + extension[1:])
            os.makedirs(folder)
            for image in os.listdir(os.path.join(scenes, name)):  # gltfpack keeps image URIs as they are
                if image.endswith(".png"):
                    shutil.copy(os.path.join(scenes, name, image), folder)
            packed = os.path.join(folder, name + extension)
            pack = subprocess.run(["gltfpack", "-i", source, "-o", packed] + flags, capture_output=True, text=True)
            if pack.returncode != 0:
                fail("gltfpack %s on %s: %s" % (" ".join(flags), name, pack.stderr.strip()))
                continue
            out = packed + ".exr"
            result = render(veach, packed, out)
            label = "%s %s%s" % (name, variant, extension)
            if result.returncode != 0:
                fail("%s: veach exited %d: %s" % (label, result.returncode, result.stderr.strip()))
                continue
            m = image_compare.compare(image_compare.load(out), image_compare.load(reference))
            worst_mean = max(abs(c - 1.0) for c in m["mean"])
            ok = worst_mean < 0.01 and m["blocks"] < 0.05 and m["nonfinite"] == 0
            print("%-28s mean %+.4f  blocks %.4f  %s" % (label, worst_mean, m["blocks"], "ok" if ok else "FAIL"))
            if not ok:
                fail("%s differs from the original: %s" % (label, m))
            if variant != "quantized":
                quantized = os.path.join(tmp, name + "_quantized" + extension[1:], name + extension + ".exr")
                q = image_compare.compare(image_compare.load(out), image_compare.load(quantized))
                print("%-28s against the quantized file: relmse %.2e, blocks %.5f" % ("", q["relmse"], q["blocks"]))
                # -c is lossless (triangles may come back rotated, which moves hit points by
                # rounding only); -cc's filters re-quantize normals and UVs a little further.
                if (variant == "meshopt" and q["relmse"] > 1e-9) or q["blocks"] > 0.01:
                    fail("%s: the decoded data is not the quantized file's: %s" % (label, q))


def check_refused(veach, scenes, tmp):
    """Corrupt the -c cornell's first compressed view three ways: each is exit 2, one line."""
    folder = os.path.join(tmp, "corrupt")
    os.makedirs(folder)
    packed = os.path.join(folder, "cornell.gltf")
    subprocess.run(["gltfpack", "-i", os.path.join(scenes, "cornell", "cornell.gltf"), "-o", packed, "-c"],
                   check=True, capture_output=True)
    with open(packed) as f:
        doc = json.load(f)
    views = [k for k, v in enumerate(doc["bufferViews"]) if "EXT_meshopt_compression" in v.get("extensions", {})]
    if not views:
        fail("gltfpack -c wrote no EXT_meshopt_compression view")
        return
    k = views[0]
    buffer_bytes = doc["buffers"][doc["bufferViews"][k]["extensions"]["EXT_meshopt_compression"]["buffer"]]["byteLength"]
    cases = {
        "truncated stream": ("byteLength", lambda e: max(1, e["byteLength"] // 3)),
        "stream outside its buffer": ("byteOffset", lambda e: buffer_bytes),
        "count overruns the view": ("count", lambda e: e["count"] * 4 + 3),
    }
    for case, (field, value) in cases.items():
        bad = json.loads(json.dumps(doc))
        ext = bad["bufferViews"][k]["extensions"]["EXT_meshopt_compression"]
        ext[field] = value(ext)
        path = os.path.join(folder, "bad.gltf")
        with open(path, "w") as f:
            json.dump(bad, f)
        result = render(veach, path, os.path.join(folder, "bad.exr"))
        lines = result.stderr.strip().splitlines()
        if result.returncode != 2 or len(lines) != 1 or ("bufferView %d" % k) not in lines[0]:
            fail("%s: expected exit 2 and one line naming bufferView %d, got exit %d: %s"
                 % (case, k, result.returncode, result.stderr.strip()))
        else:
            print("refused %-26s %s" % (case + ":", lines[0]))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--veach", required=True)
    ap.add_argument("--scenes", required=True)
    args = ap.parse_args()
    if shutil.which("gltfpack") is None:
        sys.exit("FAIL: gltfpack is not installed (scripts/install-deps.sh installs it)")
    with tempfile.TemporaryDirectory(prefix="veach_gltfpack_") as tmp:
        for name in SCENES:
            check_scene(args.veach, args.scenes, name, tmp)
        check_refused(args.veach, args.scenes, tmp)
    return 1 if FAILURES else 0


if __name__ == "__main__":
    sys.exit(main())

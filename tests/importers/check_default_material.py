#!/usr/bin/python3
"""What an object without a material renders as, through the `veach` command.

What must hold:
- A file whose asset.generator names Blender: Cycles' default surface, a Lambertian of albedo
  0.8. A quad filling the view in a uniform environment of radiance 1 (a furnace: the quad sees
  only the environment) then comes out at exactly 0.8.
- Any other generator: the glTF spec's default material (white, metallic 1, roughness 1), a
  white rough metal, which in the same furnace reflects nearly everything (>= 0.95; the
  material furnace test holds white metal to >= 0.98).
- --default-material blender|gltf forces either whatever the generator says; a bad value is a
  usage error (exit 1, one line).
- The choice is part of the render's identity: parts rendered with different choices do not
  merge (exit 2, one line).
Exit 0 pass, 1 fail.
"""
import argparse
import base64
import json
import os
import struct
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
from check_report import FAILURES, check, import_oiio  # noqa: E402

oiio = import_oiio()

BLENDER = "Khronos glTF Blender I/O v3.4.50"


def quad_without_material(path, generator):
    """A 4x4 quad at z = -1 facing a camera at the origin whose view (yfov 0.5) it fills."""
    positions = [-2, -2, -1, 2, -2, -1, 2, 2, -1, -2, 2, -1]
    indices = [0, 1, 2, 0, 2, 3]
    data = struct.pack("<12f", *positions) + struct.pack("<6H", *indices)
    doc = {
        "asset": {"version": "2.0", "generator": generator},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"camera": 0}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.01, "aspectRatio": 1}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                       "min": [-2, -2, -1], "max": [2, 2, -1]},
                      {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}],
    }
    with open(path, "w") as f:
        json.dump(doc, f)
    return path


def render(veach, scene, out, *extra):
    return subprocess.run([veach, "render", scene, "-o", out, "--width", "16", "--spp", "16", "--integrator", "pt",
                           "--env-color", "1,1,1", "-q", *extra], capture_output=True, text=True, timeout=120)


def mean(path):
    buf = oiio.ImageBuf(path)
    px = buf.get_pixels(oiio.FLOAT)
    return float(px[..., :3].mean())


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--veach", required=True)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="veach_default_material_") as tmp:
        blender = quad_without_material(os.path.join(tmp, "blender.gltf"), BLENDER)
        other = quad_without_material(os.path.join(tmp, "other.gltf"), "Some Other Tool")
        cases = [("Blender export, auto", blender, [], "lambert"),
                 ("other generator, auto", other, [], "metal"),
                 ("Blender export, --default-material gltf", blender, ["--default-material", "gltf"], "metal"),
                 ("other generator, --default-material blender", other, ["--default-material", "blender"], "lambert"),
                 ("other generator, --default-material auto", other, ["--default-material", "auto"], "metal")]
        for i, (what, scene, extra, want) in enumerate(cases):
            out = os.path.join(tmp, f"{i}.exr")
            r = render(args.veach, scene, out, *extra)
            if not check(r.returncode == 0, f"{what}: exit {r.returncode}: {r.stderr.strip()}"):
                continue
            m = mean(out)
            if want == "lambert":
                check(abs(m - 0.8) < 0.008, f"{what}: furnace mean {m:.4f}, Cycles' default surface gives 0.8")
            else:
                check(0.95 <= m <= 1.001, f"{what}: furnace mean {m:.4f}, white rough metal gives 0.95..1")
            print(f"{what}: mean {m:.4f} ({want})")

        r = render(args.veach, other, os.path.join(tmp, "bad.exr"), "--default-material", "grey")
        check(r.returncode == 1 and "--default-material expects auto, blender or gltf" in r.stderr
              and r.stderr.count("\n") == 1, f"bad --default-material: exit {r.returncode}, {r.stderr!r}")

        a, b = os.path.join(tmp, "a.vpart"), os.path.join(tmp, "b.vpart")
        ra = render(args.veach, other, a, "--samples", "0:8")
        rb = render(args.veach, other, b, "--samples", "8:16", "--default-material", "blender")
        check(ra.returncode == 0 and rb.returncode == 0, f"parts: {ra.stderr.strip()} {rb.stderr.strip()}")
        r = subprocess.run([args.veach, "merge", a, b, "-o", os.path.join(tmp, "merged.exr")],
                           capture_output=True, text=True, timeout=60)
        check(r.returncode == 2 and r.stderr.count("\n") == 1,
              f"parts with different default materials merged: exit {r.returncode}, {r.stderr!r}")
    if FAILURES:
        print(f"{len(FAILURES)} failure(s)")
        return 1
    print("default material: Cycles' for Blender exports, glTF's otherwise, the flag forces, identity differs")
    return 0


if __name__ == "__main__":
    sys.exit(main())

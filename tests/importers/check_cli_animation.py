#!/usr/bin/python3
"""`veach render --frame N` on an animated glTF written here.

The scene: an orthographic camera at the origin looking down -Z over [-1, 1] x [-1, 1], and an
emissive quad (radiance 1, black base) covering the left half, x in [-1, 0], y in [-1, 1].
Animation "slide" moves the quad by -1 in x between t = 0 and t = 1 (LINEAR); animation "idle"
keeps the camera where it is. What must hold, the image mean being the fraction of the frame the quad covers
(the quad is seen directly, so each pixel is exactly 0 or 1 but at no edge: the edges fall on
pixel boundaries):
- no --frame: the file's static pose, mean 0.5;
- --frame 0: 0.5; --frame 12 (t = 12/24 = 0.5): 0.25; --frame 24 (t = 1): 0, the quad out of
  view; --frame 6 --fps 12 (t = 0.5): 0.25; --frame 48 (past the last key): 0;
- --animation idle --frame 24: 0.5; --animation 0 --frame 24 (index of "slide"): 0;
  --animation all --frame 24 (the default, spelled out: both play): 0;
- the frame is part of a render's identity: part files (--samples) of two frames refuse to merge,
  two parts of one frame merge;
- an empty shutter (--shutter 0,0) renders bit for bit what no --shutter renders;
- bad values are refused before rendering with one line and no file: --frame abc, --frame 1.5,
  --fps 0 and --fps without --frame, --shutter opening after it closes, not a number, one value,
  or without --frame (usage, exit 1); --animation walk (bad input, exit 2, the line lists the
  file's animations).
Exit 0 pass, 1 fail.
"""
import argparse
import json
import os
import struct
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
from check_report import FAILURES, check, import_numpy_oiio  # noqa: E402

np, oiio = import_numpy_oiio()


def write_scene(path, extra_extension=None):
    floats = lambda values: struct.pack("<%df" % len(values), *values)
    positions = floats([-1, -1, -1, 0, -1, -1, 0, 1, -1, -1, 1, -1])
    indices = struct.pack("<6H", 0, 1, 2, 0, 2, 3) + b"\0\0"
    times = floats([0, 1])
    slide = floats([0, 0, 0, -1, 0, 0])
    still = floats([0, 0, 0, 0, 0, 0])
    blob = positions + indices + times + slide + still
    offsets = [0, len(positions), len(positions) + len(indices), len(positions) + len(indices) + 8,
               len(positions) + len(indices) + 8 + 24]
    lengths = [len(positions), 12, 8, 24, 24]
    views = [{"buffer": 0, "byteOffset": o, "byteLength": n} for o, n in zip(offsets, lengths)]
    accessors = [
        {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, -1], "max": [0, 1, -1]},
        {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"},
        {"bufferView": 2, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [1]},
        {"bufferView": 3, "componentType": 5126, "count": 2, "type": "VEC3"},
        {"bufferView": 4, "componentType": 5126, "count": 2, "type": "VEC3"},
    ]
    import base64
    doc = {
        "asset": {"version": "2.0", "generator": "veach check_cli_animation"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"name": "quad", "mesh": 0}, {"name": "camera", "camera": 0}],
        "cameras": [{"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1, "znear": 0.01, "zfar": 10}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0},
                       "emissiveFactor": [1, 1, 1]}],
        "animations": [
            {"name": "slide", "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}],
             "samplers": [{"input": 2, "output": 3}]},
            {"name": "idle", "channels": [{"sampler": 0, "target": {"node": 1, "path": "translation"}}],
             "samplers": [{"input": 2, "output": 4}]},
        ],
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
        "bufferViews": views,
        "accessors": accessors,
    }
    if extra_extension:
        doc["extensionsUsed"] = [extra_extension]
    with open(path, "w") as f:
        json.dump(doc, f)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--veach", required=True)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="veach_cli_animation_") as tmp:
        scene = os.path.join(tmp, "slide.gltf")
        write_scene(scene)
        common = ["--width", "32", "--height", "32", "--spp", "4", "--integrator", "pt", "--threads", "2", "-q"]

        def render_pixels(name, *flags):
            out = os.path.join(tmp, name + ".exr")
            proc = subprocess.run([args.veach, "render", scene, "-o", out, *common, *flags],
                                  capture_output=True, text=True, timeout=120)
            if not check(proc.returncode == 0, f"{name}: exit {proc.returncode}: {proc.stderr.strip()}"):
                return None
            return np.asarray(oiio.ImageBuf(out).get_pixels(oiio.FLOAT))[..., :3]

        def render(name, *flags):
            pixels = render_pixels(name, *flags)
            return None if pixels is None else float(pixels.mean())

        cases = [("static", [], 0.5), ("frame0", ["--frame", "0"], 0.5), ("frame12", ["--frame", "12"], 0.25),
                 ("frame24", ["--frame", "24"], 0.0), ("fps12", ["--frame", "6", "--fps", "12"], 0.25),
                 ("frame48", ["--frame", "48"], 0.0), ("idle", ["--animation", "idle", "--frame", "24"], 0.5),
                 ("index0", ["--animation", "0", "--frame", "24"], 0.0),
                 ("all", ["--animation", "all", "--frame", "24"], 0.0)]
        for name, flags, want in cases:
            mean = render(name, *flags)
            if mean is not None:
                ok = check(abs(mean - want) < 1e-4, f"{name} ({' '.join(flags)}): mean {mean:.5f}, expected {want}")
                if ok:
                    print(f"{name:>8} {' '.join(flags):<28} mean {mean:.5f} (expected {want})")

        plain = render_pixels("plain", "--frame", "7")
        empty = render_pixels("empty_shutter", "--frame", "7", "--shutter", "0,0")
        if plain is not None and empty is not None:
            check(np.array_equal(plain, empty), "--shutter 0,0 changed the image of --frame 7")

        def part(name, samples, frame):
            out = os.path.join(tmp, name + ".vpart")
            proc = subprocess.run([args.veach, "render", scene, "-o", out, *common, "--samples", samples,
                                   "--frame", frame], capture_output=True, text=True, timeout=120)
            check(proc.returncode == 0, f"part {name}: exit {proc.returncode}: {proc.stderr.strip()}")
            return out

        a, b, c = part("a", "0:2", "12"), part("b", "2:4", "12"), part("c", "2:4", "0")
        merged = os.path.join(tmp, "merged.exr")
        same = subprocess.run([args.veach, "merge", a, b, "-o", merged], capture_output=True, text=True, timeout=60)
        check(same.returncode == 0, f"parts of one frame: merge exit {same.returncode}: {same.stderr.strip()}")
        if same.returncode == 0:
            mean = float(np.asarray(oiio.ImageBuf(merged).get_pixels(oiio.FLOAT))[..., :3].mean())
            check(abs(mean - 0.25) < 1e-4, f"frame 12 merged from parts: mean {mean}")
        other = subprocess.run([args.veach, "merge", a, c, "-o", merged + "2.exr"], capture_output=True, text=True,
                               timeout=60)
        check(other.returncode == 2, f"parts of frames 12 and 0 merged (exit {other.returncode})")
        print(f"parts of frames 12 and 0: merge exit {other.returncode}: {other.stderr.strip()}")

        refusals = [(["--frame", "abc"], 1, "--frame"), (["--frame", "1.5"], 1, "--frame"),
                    (["--frame", "1", "--fps", "0"], 1, "--fps"), (["--fps", "30"], 1, "--fps needs --frame"),
                    (["--animation", "walk", "--frame", "1"], 2, "'slide', 'idle'"),
                    (["--frame", "1", "--shutter", "0.25,-0.25"], 1, "opens after it closes"),
                    (["--frame", "1", "--shutter", "nan,0.25"], 1, "--shutter"),
                    (["--frame", "1", "--shutter", "0.5"], 1, "--shutter expects OPEN,CLOSE"),
                    (["--shutter", "-0.25,0.25"], 1, "--shutter needs --frame")]
        for flags, code, needle in refusals:
            out = os.path.join(tmp, "refused.exr")
            proc = subprocess.run([args.veach, "render", scene, "-o", out, *common, *flags],
                                  capture_output=True, text=True, timeout=60)
            lines = proc.stderr.strip().splitlines()
            check(proc.returncode == code, f"{' '.join(flags)}: exit {proc.returncode}, expected {code}")
            check(len(lines) == 1 and needle in lines[0], f"{' '.join(flags)}: message {lines!r} lacks {needle!r}")
            check(not os.path.exists(out), f"{' '.join(flags)}: wrote {out}")
            if proc.returncode == code and lines:
                print(f"refused {' '.join(flags)}: exit {code}: {lines[0]}")
    if FAILURES:
        sys.exit(1)
    print("PASS: --frame, --fps and --animation pose the scene, an empty --shutter changes nothing; bad values are "
          "refused")


if __name__ == "__main__":
    main()

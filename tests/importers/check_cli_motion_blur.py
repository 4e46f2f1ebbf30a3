#!/usr/bin/python3
"""`veach render SCENE --frame N --shutter -0.25,0.25 -o out.exr`: object motion blur from the command,
with Blender's default shutter (0.5 frames centred on the frame) typed as a user types it.

The scene (written here, keyframes at frame / 24 s as Blender's exporter writes them): an
orthographic camera at z = 2 looking down -Z over x in [-2, 2], y in [-1, 1] (128 x 64 pixels:
32 per unit); an unlit white backdrop (radiance 1, nothing else) at z = 0; an unlit black
occluder (0, reflecting nothing) x, y in [-0.5, 0.5] at z = 0.5 sliding +X at 6 units per
second (from x = -1.5 at frame 0 to 1.5 at frame 12); a grey diffuse quad x in [-1.9, -1.1] at
z = 0.3 that never moves, lit by a point light above it (its pixels are Monte Carlo noise).

At frame 6 the occluder is centred on x = 0, its edges at x = -0.5 and 0.5: pixel boundaries
(columns 48 and 80). The shutter of 0.5 frames (1/48 s) moves it 0.125 units, 4 pixels: each
edge becomes a ramp over exactly 4 columns, the box-filtered coverage 1/8, 3/8, 5/8, 7/8 of a
linear ramp. What must hold:
- the unblurred frame (no --shutter): rows across the occluder are 0 inside, 1 outside, no column
  in between;
- the blurred frame: those rows' column means match the analytic ramp within noise (per column,
  a binomial bound), and the ramp is 4 columns wide at each edge;
- the static grey quad: blurred and unblurred renders (other seeds) agree within noise, 8 x 8
  blocks and the quad's mean, by the noise measured from the two renders' difference.
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
from check_report import FAILURES, check, import_numpy_oiio  # noqa: E402

np, oiio = import_numpy_oiio()
WIDTH, HEIGHT, PER_UNIT = 128, 64, 32


def write_scene(path):
    floats = lambda values: struct.pack("<%df" % len(values), *values)

    def quad(x0, x1, y0, y1):
        return [x0, y0, 0, x1, y0, 0, x1, y1, 0, x0, y1, 0]

    quads = [quad(-3, 3, -2, 2), quad(-0.5, 0.5, -0.5, 0.5), quad(-1.9, -1.1, -0.9, 0.9)]
    chunks = [floats(q) for q in quads]
    chunks.append(struct.pack("<6H", 0, 1, 2, 0, 2, 3) + b"\0\0")
    chunks.append(floats([0, 12 / 24]))                    # keyframe times: frames 0 and 12
    chunks.append(floats([-1.5, 0, 0.5, 1.5, 0, 0.5]))     # the occluder's translation
    views, accessors, offset = [], [], 0
    for chunk in chunks:
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(chunk)})
        offset += len(chunk)
    for i, q in enumerate(quads):
        xs, ys = q[0::3], q[1::3]
        accessors.append({"bufferView": i, "componentType": 5126, "count": 4, "type": "VEC3",
                          "min": [min(xs), min(ys), 0], "max": [max(xs), max(ys), 0]})
    accessors.append({"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"})
    accessors.append({"bufferView": 4, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [0.5]})
    accessors.append({"bufferView": 5, "componentType": 5126, "count": 2, "type": "VEC3"})
    blob = b"".join(chunks)
    mesh = lambda position, material: {"primitives": [{"attributes": {"POSITION": position}, "indices": 3,
                                                       "material": material}]}
    doc = {
        "asset": {"version": "2.0", "generator": "veach check_cli_motion_blur"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_unlit"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 2000}]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2, 3, 4]}],
        "nodes": [{"name": "backdrop", "mesh": 0},
                  {"name": "occluder", "mesh": 1, "translation": [-1.5, 0, 0.5]},
                  {"name": "grey", "mesh": 2, "translation": [0, 0, 0.3]},
                  {"name": "lamp", "translation": [-1.5, 0, 1.2], "extensions": {"KHR_lights_punctual": {"light": 0}}},
                  {"name": "camera", "camera": 0, "translation": [0, 0, 2]}],
        "cameras": [{"type": "orthographic", "orthographic": {"xmag": 2, "ymag": 1, "znear": 0.01, "zfar": 10}}],
        "meshes": [mesh(0, 0), mesh(1, 1), mesh(2, 2)],
        # Unlit (KHR_materials_unlit: its colour, no reflection): the backdrop exactly 1, the
        # occluder exactly 0 under the point light, whatever the angle.
        "materials": [
            {"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1]}, "extensions": {"KHR_materials_unlit": {}}},
            {"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1]}, "extensions": {"KHR_materials_unlit": {}}},
            {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0,
                                      "roughnessFactor": 1}},
        ],
        "animations": [{"name": "slide", "channels": [{"sampler": 0, "target": {"node": 1, "path": "translation"}}],
                        "samplers": [{"input": 4, "output": 5}]}],
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
        "bufferViews": views,
        "accessors": accessors,
    }
    with open(path, "w") as f:
        json.dump(doc, f)


def analytic_column(column, lo_edge, hi_edge, shift):
    """Coverage of the occluder [lo_edge, hi_edge] (x, at the frame) in film column `column`, averaged
    over the shutter's shifts in [-shift, shift] (x units): a box pixel times a box shutter."""
    n = 4000
    total = 0.0
    for k in range(n):
        s = -shift + 2 * shift * (k + 0.5) / n
        lo = -2 + column / PER_UNIT
        hi = lo + 1 / PER_UNIT
        total += max(0.0, min(hi, hi_edge + s) - max(lo, lo_edge + s)) * PER_UNIT
    return total / n


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--veach", required=True)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="veach_cli_motion_blur_") as tmp:
        scene = os.path.join(tmp, "slide.gltf")
        write_scene(scene)
        common = ["--width", str(WIDTH), "--height", str(HEIGHT), "--spp", "256", "--integrator", "pt",
                  "--threads", "2", "-q"]

        def render(name, *flags):
            out = os.path.join(tmp, name + ".exr")
            command = [args.veach, "render", scene, *flags, "-o", out, *common]
            proc = subprocess.run(command, capture_output=True, text=True, timeout=300)
            if not check(proc.returncode == 0, f"{name}: exit {proc.returncode}: {proc.stderr.strip()}"):
                return None
            return np.asarray(oiio.ImageBuf(out).get_pixels(oiio.FLOAT))[..., :3].mean(axis=2)

        # Exactly what a user types for Blender's default shutter.
        blurred = render("blurred", "--frame", "6", "--shutter", "-0.25,0.25")
        sharp = render("sharp", "--frame", "6", "--seed", "2")
        if blurred is None or sharp is None:
            sys.exit(1)
        # Rows across the occluder (|y| < 0.4) and not across the grey quad (columns 36 on).
        rows = slice(HEIGHT // 2 - 12, HEIGHT // 2 + 12)
        columns = range(36, WIDTH)
        sharp_profile = sharp[rows].mean(axis=0)
        between = [c for c in columns if 1e-6 < sharp_profile[c] < 1 - 1e-6]
        check(not between, f"unblurred frame: columns {between} are neither occluded nor clear")
        check(sharp_profile[48:80].max() < 1e-6 and sharp_profile[80:].min() > 1 - 1e-6,
              "unblurred frame: the occluder is not at x in [-0.5, 0.5]")
        profile = blurred[rows].mean(axis=0)
        shift = 6 * (0.25 / 24)  # 6 units/s over a quarter frame each way: 0.0625 units, 2 pixels
        worst = 0.0
        ramp = []
        for c in columns:
            want = 1 - analytic_column(c, -0.5, 0.5, shift)
            # 24 rows x 256 samples of a 0/1 value per column: a binomial standard error under
            # 0.0064 (stratified in position and time, the error is smaller still).
            err = abs(profile[c] - want)
            worst = max(worst, err)
            check(err < 0.03, f"blurred column {c}: {profile[c]:.4f}, analytic {want:.4f}")
            if 0.02 < profile[c] < 0.98:
                ramp.append(c)
        left = [c for c in ramp if c < 64]
        right = [c for c in ramp if c >= 64]
        check(left == [46, 47, 48, 49], f"left edge blurred over columns {left}, expected 46 to 49")
        check(right == [78, 79, 80, 81], f"right edge blurred over columns {right}, expected 78 to 81")
        print(f"moving edge: ramps over columns {left} and {right} (4 pixels each, as 0.125 units of motion "
              f"at 32 per unit); worst column off the analytic profile by {worst:.4f}")

        # The static grey quad (x in [-1.9, -1.1]: columns 3 to 28, rows 4 to 60), 8 x 8 blocks.
        a = blurred[8:56, 4:28]
        b = render("sharp_seed3", "--frame", "6", "--seed", "3")
        if b is None:
            sys.exit(1)
        b = b[8:56, 4:28]
        check(a.mean() > 0.05, f"the grey quad is dark ({a.mean():.4f}): the light does not reach it")
        diff = a - b
        se = diff.std() / np.sqrt(diff.size)
        z = diff.mean() / se
        check(abs(z) < 4.5, f"static quad: blurred mean {a.mean():.5f}, unblurred {b.mean():.5f}, z = {z:.2f}")
        blocks_a = a.reshape(6, 8, 3, 8).mean(axis=(1, 3))
        blocks_b = b.reshape(6, 8, 3, 8).mean(axis=(1, 3))
        block_se = diff.reshape(6, 8, 3, 8).std(axis=(1, 3)) / 8
        block_z = np.abs(blocks_a - blocks_b) / np.maximum(block_se, 1e-9)
        check(block_z.max() < 4.5, f"static quad: an 8 x 8 block differs by {block_z.max():.2f} standard errors")
        print(f"static quad: mean {a.mean():.5f} blurred, {b.mean():.5f} unblurred (z = {z:.2f}); "
              f"largest 8 x 8 block difference {block_z.max():.2f} standard errors; noise per pixel "
              f"{diff.std() / np.sqrt(2):.4f}")
    if FAILURES:
        sys.exit(1)
    print("PASS: --frame 6 --shutter -0.25,0.25 blurs the moving occluder's edges over 4 pixels as the analytic "
          "profile says, and leaves the static quad as it renders without a shutter")


if __name__ == "__main__":
    main()

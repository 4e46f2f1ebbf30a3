#!/usr/bin/python3
"""The add-on's motion blur: Blender's Motion Blur (render.use_motion_blur, motion_blur_shutter)
becomes the scene option `shutter`, rendered the way farms run it:
  blender -b motion.blend --addons veach -E VEACH -o //blur_#### -F OPEN_EXR -f 7
on a .blend another Blender process built and saved (blender_motion_scene.py: a black square
sliding +X at 0.25 units per frame under an orthographic camera, 32 pixels per unit, over a white
World; Motion Blur on with Blender's default shutter 0.5, and the same scene saved with it off).
At frame 7 the square's edges fall on pixel boundaries (columns 48 and 80); the shutter of half
a frame moves it 0.125 units, 4 pixels, so each edge must ramp over exactly 4 columns with the
box-filtered coverage of a linear ramp (1/8, 3/8, 5/8, 7/8), within a binomial bound. With
Motion Blur off the same frame is sharp: every column is 0 or 1. A strip moved by a shape key
whose value rises across the shutter (the object still, its vertices sliding at the same speed)
must ramp the same way: deformation within the shutter carried as morph targets per step. And the export the add-on
renders (kept by VEACH_BLENDER_KEEP_EXPORT) carries the motion as Blender has it: a bar spinning
about Z at 22.5 degrees per frame is keyed at the shutter's three times with rotations about
glTF's +Y (Blender's Z) of 45 -/+ 5.625 degrees (check_export).
Usage: check_blender_motion_blur.py --library LIBVEACH --addon plugins/blender --repo REPO_ROOT"""
import argparse
import os
import shutil
import sys
import tempfile

from blender_harness import find_blender, install_addon, run_or_exit

WIDTH, HEIGHT, PER_UNIT = 128, 64, 32


def coverage(column, lo_edge, hi_edge, shift):
    """The square [lo_edge, hi_edge] (x at the frame) in film column `column`, averaged over the
    shutter's shifts in [-shift, shift]: a box pixel times a box shutter."""
    n = 4000
    total = 0.0
    for k in range(n):
        s = -shift + 2 * shift * (k + 0.5) / n
        lo = -2 + column / PER_UNIT
        total += max(0.0, min(lo + 1 / PER_UNIT, hi_edge + s) - max(lo, lo_edge + s)) * PER_UNIT
    return total / n


def check_export(path, check, np):
    """The export's motion: the spinner (turning 22.5 degrees per frame about Blender's Z, 45 at
    frame 7) keyed at -1/96, 0 and 1/96 s with rotations about glTF's +Y (Blender's Z) of 39.375,
    45 and 50.625 degrees, its node's own TRS the frame's; the sliding square keyed at x = -0.0625,
    0, 0.0625; the still camera not animated."""
    import json
    with open(path) as f:
        gltf = json.load(f)
    nodes = {n.get("name"): i for i, n in enumerate(gltf["nodes"])}
    animations = gltf.get("animations", [])
    if not check(len(animations) == 1, f"export: {len(animations)} animations, expected one for motion blur"):
        return
    blob = open(os.path.join(os.path.dirname(path), gltf["buffers"][0]["uri"]), "rb").read()

    def values(accessor):
        a = gltf["accessors"][accessor]
        v = gltf["bufferViews"][a["bufferView"]]
        n = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}[a["type"]]
        data = np.frombuffer(blob, dtype=np.float32, count=a["count"] * n, offset=v.get("byteOffset", 0))
        return data.reshape(a["count"], n)

    keyed = {}
    for channel in animations[0]["channels"]:
        sampler = animations[0]["samplers"][channel["sampler"]]
        keyed[(channel["target"]["node"], channel["target"]["path"])] = (values(sampler["input"]).ravel(),
                                                                         values(sampler["output"]))
    check(not any(node == nodes.get("Camera") for node, _ in keyed), "export: the still camera is animated")
    times, rotations = keyed.get((nodes["Spinner"], "rotation"), (None, None))
    if check(times is not None, "export: the spinner has no rotation keys"):
        check(np.allclose(times, [-1 / 96, 0, 1 / 96], atol=1e-7), f"export: key times {times}")
        for q, degrees in zip(rotations, (39.375, 45.0, 50.625)):
            h = np.radians(degrees) / 2
            check(np.allclose(q, [0, np.sin(h), 0, np.cos(h)], atol=1e-5),
                  f"export: spinner rotation {q}, expected {degrees} degrees about +Y")
        node = gltf["nodes"][nodes["Spinner"]]
        check("matrix" not in node and np.allclose(node.get("rotation", []), rotations[1], atol=1e-6),
              f"export: the spinner's node is not its frame's TRS: {node}")
    _, slide = keyed.get((nodes["Square"], "translation"), (None, None))
    if check(slide is not None, "export: the square has no translation keys"):
        check(np.allclose(slide[:, 0], [-0.0625, 0, 0.0625], atol=1e-5), f"export: square x keys {slide[:, 0]}")
    print(f"export: spinner keyed at {np.degrees(2 * np.arctan2(rotations[:, 1], rotations[:, 3]))} degrees "
          f"about +Y at {times * 96} / 96 s; square at x {slide[:, 0]}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--library", required=True)
    ap.add_argument("--addon", required=True)
    ap.add_argument("--repo", required=True)
    args = ap.parse_args()
    blender = find_blender()
    sys.path.insert(0, os.path.join(args.repo, "tests", "tools"))
    from check_report import FAILURES, check, import_numpy_oiio
    np, oiio = import_numpy_oiio()

    tmp = tempfile.mkdtemp(prefix="veach_blender_motion_")
    try:
        env = install_addon(tmp, args.addon, args.library)
        work = os.path.join(tmp, "scene")
        os.makedirs(work)
        run_or_exit([blender, "-b", "--factory-startup", "--python",
                     os.path.join(args.repo, "tests", "api", "blender_motion_scene.py"), "--", work,
                     os.path.join(tmp, "scripts", "addons")], tmp, env, "building motion.blend")

        def render(blend, name, environment=env):
            run_or_exit([blender, "-b", blend, "--addons", "veach", "-E", "VEACH", "-o", "//" + name + "_####",
                         "-F", "OPEN_EXR", "-f", "7"], work, environment, f"{blend} -f 7")
            pixels = np.asarray(oiio.ImageBuf(os.path.join(work, name + "_0007.exr")).get_pixels(oiio.FLOAT))
            check(pixels.shape[:2] == (HEIGHT, WIDTH), f"{name}: {pixels.shape[:2]}, expected {(HEIGHT, WIDTH)}")
            return pixels[..., :3].mean(axis=2)

        kept = os.path.join(work, "export")
        blurred = render("motion.blend", "blur", dict(env, VEACH_BLENDER_KEEP_EXPORT=kept))
        check_export(os.path.join(kept, "frame.gltf"), check, np)
        sharp = render("still.blend", "sharp")
        rows = slice(HEIGHT // 2 - 12, HEIGHT // 2 + 12)  # |y| < 0.375: across the square
        sharp_profile = sharp[rows].mean(axis=0)
        between = [c for c in range(WIDTH) if 1e-3 < sharp_profile[c] < 1 - 1e-3]
        check(not between, f"Motion Blur off: columns {between} are neither covered nor clear")
        check(sharp_profile[48:80].max() < 1e-3 and sharp_profile[:48].min() > 1 - 1e-3,
              "Motion Blur off: the square is not at x in [-0.5, 0.5] at frame 7")
        profile = blurred[rows].mean(axis=0)
        shift = 0.25 * 0.25  # a quarter frame each way at 0.25 units per frame
        worst, ramp = 0.0, []
        for c in range(WIDTH):
            want = 1 - coverage(c, -0.5, 0.5, shift)
            # 24 rows x 256 samples of a 0/1 value: a binomial standard error under 0.0064.
            err = abs(profile[c] - want)
            worst = max(worst, err)
            check(err < 0.03, f"Motion Blur on: column {c}: {profile[c]:.4f}, analytic {want:.4f}")
            if 0.02 < profile[c] < 0.98:
                ramp.append(c)
        check(ramp == [46, 47, 48, 49, 78, 79, 80, 81], f"Motion Blur on: edges ramp over columns {ramp}, "
              "expected 46 to 49 and 78 to 81")
        # The shape-keyed strip (rows 51 to 61: y in [-0.9, -0.6]) at x in [-1, 0] at frame 7, its
        # vertices sliding at the square's speed: the same ramps, 4 columns at columns 32 and 64.
        strip_rows = slice(51, 62)
        strip_sharp = sharp[strip_rows].mean(axis=0)
        check(strip_sharp[32:64].max() < 1e-3 and strip_sharp[:32].min() > 1 - 1e-3 and
              strip_sharp[64:].min() > 1 - 1e-3, "Motion Blur off: the strip is not at x in [-1, 0] at frame 7")
        strip = blurred[strip_rows].mean(axis=0)
        strip_ramp = []
        for c in range(WIDTH):
            want = 1 - coverage(c, -1.0, 0.0, shift)
            # 11 rows x 256 samples: a binomial standard error under 0.0095.
            err = abs(strip[c] - want)
            worst = max(worst, err)
            check(err < 0.04, f"Motion Blur on: strip column {c}: {strip[c]:.4f}, analytic {want:.4f}")
            if 0.02 < strip[c] < 0.98:
                strip_ramp.append(c)
        check(strip_ramp == [30, 31, 32, 33, 62, 63, 64, 65], f"Motion Blur on: the shape-keyed strip ramps over "
              f"columns {strip_ramp}, expected 30 to 33 and 62 to 65")
        print(f"Motion Blur on: the square's edges ramp over columns {ramp}, the shape-keyed strip's over "
              f"{strip_ramp}; worst column off the analytic profile by {worst:.4f}; off: sharp")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    if FAILURES:
        sys.exit(1)
    print("PASS: Blender's Motion Blur (shutter 0.5) blurs a moving square's and a shape-keyed strip's edges over "
          "the analytic 4 pixels")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""check_scene_generator.py --source DIR [--jobs N]

The scene generator (scripts/blender/make_scene.py), run as a user types it, with Debian's Blender:
- bad arguments (an unknown scene, a frame of a still scene) exit 2 with one
  line on stderr, before anything is written;
- every committed scene of tests/data/scenes rebuilt from its definition (--spp 0) is the
  committed scene: the same node transforms, cameras, lights, materials (and "lambert" tags),
  triangles (position, normal, UV; in any order) and image pixels, so the committed references
  still belong to the definitions (a render comparison could not tell a small change from
  noise in corridor or the spheres' caustics);
- a Cycles reference of a still scene (cornell, 32 px, 2 spp) and of two frames of the
  animated one (keyframes): half-float zip EXR at the asked size, a json with what was asked,
  and, for the animated scene, a glTF with its animation and one EXR per frame.
Exit 0 pass, 1 fail. Blender is installed by scripts/install-deps.sh: its absence is a failure.
"""
import argparse
import concurrent.futures
import json
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tools"))
import image_compare  # noqa: E402
import numpy as np  # noqa: E402

COMMITTED = ("cornell", "textured", "lights", "spheres", "corridor", "animated", "grooves", "many_lights")
failures = []


def fail(message):
    print("FAIL: " + message, flush=True)
    failures.append(message)


def make_scene(source, *args):
    command = ["blender", "-b", "--factory-startup", "--python",
               os.path.join(source, "scripts", "blender", "make_scene.py"), "--"] + list(args)
    return subprocess.run(command, capture_output=True, text=True, timeout=600)


def check_bad_arguments(source, tmp):
    cases = [(["--scene", "no_such_scene", "--out", os.path.join(tmp, "bad1")], "unknown scene"),
             (["--scene", "cornell", "--out", os.path.join(tmp, "bad2"), "--frames", "2"], "not animated")]
    for args, words in cases:
        p = make_scene(source, *args)
        lines = [line for line in p.stderr.splitlines() if line.startswith("make_scene:")]
        if p.returncode != 2 or len(lines) != 1 or words not in lines[0]:
            fail("make_scene %s: exit %d, stderr %r (expected exit 2 and one line about %s)"
                 % (" ".join(args), p.returncode, p.stderr[-500:], words))
        if os.path.exists(args[3]) and os.listdir(args[3]):
            fail("make_scene %s wrote %s" % (" ".join(args), os.listdir(args[3])))


def load_gltf(path):
    """The glTF's JSON and a function giving accessor i as a numpy array (float64, rows)."""
    with open(path) as f:
        gltf = json.load(f)
    folder = os.path.dirname(path)
    buffers = [open(os.path.join(folder, b["uri"]), "rb").read() for b in gltf.get("buffers", [])]
    kinds = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}
    widths = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}

    def accessor(i):
        a = gltf["accessors"][i]
        view = gltf["bufferViews"][a["bufferView"]]
        offset = view.get("byteOffset", 0) + a.get("byteOffset", 0)
        n = widths[a["type"]]
        data = np.frombuffer(buffers[view["buffer"]], kinds[a["componentType"]], a["count"] * n, offset)
        return data.reshape(-1, n).astype(np.float64)
    return gltf, accessor


def triangles(accessor, primitive):
    """The primitive's triangles as rows of (position, normal, uv) x 3 corners, each triangle
    turned to start at its smallest corner (winding kept), sorted: the same surface gives the
    same rows whatever order the exporter wrote triangles and vertices in."""
    attributes = primitive["attributes"]
    columns = [accessor(attributes[k]) for k in ("POSITION", "NORMAL", "TEXCOORD_0") if k in attributes]
    vertices = np.hstack(columns)
    corners = vertices[accessor(primitive["indices"]).astype(np.int64).reshape(-1, 3)]
    first = np.array([min(range(3), key=lambda k: tuple(np.round(t[k], 3))) for t in corners])
    turned = np.stack([corners[np.arange(len(corners)), (first + k) % 3] for k in range(3)], axis=1)
    rows = turned.reshape(len(turned), -1)
    return rows[np.lexsort(np.round(rows, 3).T[::-1])]


def material_signature(gltf, index):
    material = dict(gltf["materials"][index]) if index is not None else {}
    material.pop("name", None)
    extras = material.pop("extras", {})
    material["lambert"] = bool(extras.get("lambert"))  # the tag the Cycles reference relies on
    return json.dumps(material, sort_keys=True)


def same_scene(path_a, path_b):
    """None when the two glTF files hold the same scene (node transforms, cameras, lights,
    materials, triangles; names and orders aside), else what differs."""
    (a, acc_a), (b, acc_b) = load_gltf(path_a), load_gltf(path_b)
    for key in ("cameras", "extensions"):
        if a.get(key) != b.get(key):
            return key
    if len(a["nodes"]) != len(b["nodes"]):
        return "node count %d against %d" % (len(a["nodes"]), len(b["nodes"]))
    for node_a, node_b in zip(a["nodes"], b["nodes"]):
        for key in ("translation", "rotation", "scale"):
            if not np.allclose(node_a.get(key, []), node_b.get(key, []), atol=1e-6):
                return "node %s %s" % (node_a.get("name"), key)
        if ("mesh" in node_a) != ("mesh" in node_b):
            return "node %s mesh" % node_a.get("name")
        if "mesh" not in node_a:
            continue
        prims_a = a["meshes"][node_a["mesh"]]["primitives"]
        prims_b = b["meshes"][node_b["mesh"]]["primitives"]
        if len(prims_a) != len(prims_b):
            return "node %s primitive count" % node_a.get("name")
        for pa, pb in zip(prims_a, prims_b):
            if material_signature(a, pa.get("material")) != material_signature(b, pb.get("material")):
                return "node %s material" % node_a.get("name")
            ta, tb = triangles(acc_a, pa), triangles(acc_b, pb)
            if ta.shape != tb.shape or not np.allclose(ta, tb, atol=1e-5):
                return "node %s triangles" % node_a.get("name")
    for image_a, image_b in zip(a.get("images", []), b.get("images", [])):
        pixels = [image_compare.load(os.path.join(os.path.dirname(p), i["uri"]))
                  for p, i in ((path_a, image_a), (path_b, image_b))]
        if pixels[0].shape != pixels[1].shape or not np.array_equal(*pixels):
            return "image %s" % image_a["uri"]
    return None


def check_rebuilt(source, tmp, name):
    out = os.path.join(tmp, "rebuilt", name)
    p = make_scene(source, "--scene", name, "--out", out, "--spp", "0")
    if p.returncode != 0:
        fail("make_scene --scene %s --spp 0: exit %d\n%s" % (name, p.returncode, p.stderr[-2000:]))
        return
    difference = same_scene(os.path.join(out, name + ".gltf"),
                            os.path.join(source, "tests", "data", "scenes", name, name + ".gltf"))
    if difference:
        fail("the rebuilt %s is not the committed scene: %s differs" % (name, difference))
    else:
        print("rebuilt %s: the same scene as the committed glTF" % name, flush=True)


def check_exr(path, width, height):
    import OpenImageIO as oiio
    image = oiio.ImageInput.open(path)
    if image is None:
        fail("%s was not written" % path)
        return
    spec = image.spec()
    image.close()
    if (spec.width, spec.height) != (width, height) or spec.format != oiio.HALF or \
            spec.get_string_attribute("compression") != "zip":
        fail("%s is %dx%d %s %s, expected %dx%d half zip" % (path, spec.width, spec.height, spec.format,
                                                             spec.get_string_attribute("compression"), width,
                                                             height))


def check_references(source, tmp):
    out = os.path.join(tmp, "still")
    p = make_scene(source, "--scene", "cornell", "--out", out, "--spp", "2", "--seed", "7", "--width", "32")
    if p.returncode != 0:
        fail("make_scene cornell with a reference: exit %d\n%s" % (p.returncode, p.stderr[-2000:]))
    else:
        for f in ("cornell.blend", "cornell.gltf", "cornell.bin"):
            if not os.path.isfile(os.path.join(out, f)):
                fail("cornell: %s missing" % f)
        with open(os.path.join(out, "cornell.blend"), "rb") as f:
            if f.read(4) != b"\x28\xb5\x2f\xfd":  # Blender 3.x compresses with zstd
                fail("cornell.blend is not compressed")
        check_exr(os.path.join(out, "cornell.cycles.exr"), 32, 32)
        with open(os.path.join(out, "cornell.cycles.json")) as f:
            meta = json.load(f)
        expected = {"scene": "cornell", "spp": 2, "seed": 7, "width": 32, "height": 32, "frames": [1]}
        if any(meta.get(k) != v for k, v in expected.items()) or not meta.get("blender") or \
                not meta.get("seconds", 0) > 0:
            fail("cornell.cycles.json is %s, expected %s plus blender and seconds" % (meta, expected))

    out = os.path.join(tmp, "animated")
    p = make_scene(source, "--scene", "keyframes", "--out", out, "--spp", "1", "--frames", "11,12",
                   "--width", "32", "--height", "24")
    if p.returncode != 0:
        fail("make_scene keyframes: exit %d\n%s" % (p.returncode, p.stderr[-2000:]))
        return
    for frame in (11, 12):
        check_exr(os.path.join(out, "keyframes.cycles.%04d.exr" % frame), 32, 24)
    if os.path.exists(os.path.join(out, "keyframes.cycles.exr")):
        fail("keyframes: a still-scene reference name for an animated scene")
    with open(os.path.join(out, "keyframes.cycles.json")) as f:
        meta = json.load(f)
    if meta.get("frames") != [11, 12] or len(meta.get("frame_seconds", [])) != 2:
        fail("keyframes.cycles.json frames %s, frame_seconds %s" % (meta.get("frames"), meta.get("frame_seconds")))
    with open(os.path.join(out, "keyframes.gltf")) as f:
        gltf = json.load(f)
    paths = sorted(c["target"]["path"] for a in gltf.get("animations", []) for c in a["channels"])
    if paths != ["translation", "weights"]:
        fail("keyframes.gltf animates %s, expected translation and weights" % paths)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--source", required=True, help="the repository root")
    ap.add_argument("--jobs", type=int, default=2)
    args = ap.parse_args()
    if shutil.which("blender") is None:
        sys.exit("FAIL: blender is not installed; scripts/install-deps.sh installs it")
    tmp = tempfile.mkdtemp(prefix="veach_scene_generator_")
    try:
        with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
            jobs = [pool.submit(check_bad_arguments, args.source, tmp),
                    pool.submit(check_references, args.source, tmp)]
            jobs += [pool.submit(check_rebuilt, args.source, tmp, name) for name in COMMITTED]
            for job in jobs:
                job.result()
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    if failures:
        sys.exit(1)
    print("scene generator: all checks passed")


if __name__ == "__main__":
    main()

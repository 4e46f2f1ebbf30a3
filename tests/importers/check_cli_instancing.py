#!/usr/bin/python3
"""EXT_mesh_gpu_instancing through `veach render`.

The scene: a ground quad and a cube (diffuse, lit by a uniform world) placed 3 x 2 times by one
node's TRANSLATION / ROTATION / SCALE accessors, seen by a perspective camera. What must hold:
- the instanced file renders exactly the image of the same placements written as six child
  nodes of a node with the instancing node's transform (pt, same seed): the importer composes
  instance and node transforms as a child's TRS and its parent's are composed, so both files
  become the same Scene (one mesh, six instances with equal transforms) and the same Embree
  instances, and pt's samples are keyed by (seed, pixel, sample) only;
- with --frame, an animated instancing node moves every instance: the frame equals the explicit
  file whose parent node stands where the animation puts it;
- malformed instancing accessors (counts that disagree, a wrong type, an accessor past its
  buffer view) are bad input: exit 2, one line naming the node, no image written.
Exit 0 pass, 1 fail.
"""
import argparse
import base64
import copy
import json
import math
import os
import struct
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
from check_report import FAILURES, check, import_numpy_oiio  # noqa: E402

np, oiio = import_numpy_oiio()


class Gltf:
    """A glTF document with one embedded buffer."""

    def __init__(self):
        self.blob = b""
        self.doc = {"asset": {"version": "2.0", "generator": "veach check_cli_instancing"},
                    "bufferViews": [], "accessors": [], "nodes": [], "meshes": [], "scene": 0,
                    "scenes": [{"nodes": []}]}

    def accessor(self, fmt, values, component, kind, count, normalized=False):
        data = struct.pack("<%d%s" % (len(values), fmt), *values)
        while len(self.blob) % 4:
            self.blob += b"\0"
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": len(self.blob), "byteLength": len(data)})
        self.blob += data
        a = {"bufferView": len(self.doc["bufferViews"]) - 1, "componentType": component, "count": count, "type": kind}
        if normalized:
            a["normalized"] = True
        self.doc["accessors"].append(a)
        return len(self.doc["accessors"]) - 1

    def floats(self, values, kind):
        n = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}[kind]
        return self.accessor("f", values, 5126, kind, len(values) // n)

    def node(self, node, root=True):
        self.doc["nodes"].append(node)
        if root:
            self.doc["scenes"][0]["nodes"].append(len(self.doc["nodes"]) - 1)
        return len(self.doc["nodes"]) - 1

    def write(self, path):
        doc = copy.deepcopy(self.doc)
        doc["buffers"] = [{"byteLength": len(self.blob),
                           "uri": "data:application/octet-stream;base64," + base64.b64encode(self.blob).decode()}]
        with open(path, "w") as f:
            json.dump(doc, f)


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


# Six instances: a 3 x 2 grid, each turned about Y and scaled differently.
TRANSLATIONS = [[f32(1.5 * (i % 3) - 1.5), 0.0, f32(-1.5 * (i // 3))] for i in range(6)]
ROTATIONS = [[0.0, f32(math.sin(0.2 * i)), 0.0, f32(math.cos(0.2 * i))] for i in range(6)]
SCALES = [[f32(0.5 + 0.1 * i), f32(0.5 + 0.05 * i), f32(0.5)] for i in range(6)]
NODE = {"translation": [0.0, 0.5, -4.0], "rotation": [0.0, f32(math.sin(0.1)), 0.0, f32(math.cos(0.1))]}


def base_scene():
    g = Gltf()
    cube = []
    for z in (-1, 1):
        for y in (-1, 1):
            for x in (-1, 1):
                cube += [0.5 * x, 0.5 * y, 0.5 * z]
    faces = [0, 1, 3, 0, 3, 2, 4, 6, 7, 4, 7, 5, 0, 4, 5, 0, 5, 1, 2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 5, 7, 1, 7, 3]
    g.doc["materials"] = [{"pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.6, 0.5, 1], "metallicFactor": 0,
                                                    "roughnessFactor": 1}}]
    pos = g.floats(cube, "VEC3")
    idx = g.accessor("H", faces, 5123, "SCALAR", len(faces))
    g.doc["meshes"].append({"name": "cube", "primitives": [{"attributes": {"POSITION": pos}, "indices": idx,
                                                             "material": 0}]})
    ground = g.floats([-6, -1, 2, 6, -1, 2, 6, -1, -12, -6, -1, -12], "VEC3")
    gidx = g.accessor("H", [0, 1, 2, 0, 2, 3], 5123, "SCALAR", 6)
    g.doc["meshes"].append({"name": "ground", "primitives": [{"attributes": {"POSITION": ground},
                                                               "indices": gidx, "material": 0}]})
    g.node({"mesh": 1})
    g.doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.05}}]
    g.node({"camera": 0, "translation": [0.0, 1.0, 1.0]})
    return g


def instanced_scene(node=NODE, attributes=None, animate_to=None):
    g = base_scene()
    flat = lambda rows: [v for r in rows for v in r]
    if attributes is None:
        attributes = {"TRANSLATION": g.floats(flat(TRANSLATIONS), "VEC3"),
                      "ROTATION": g.floats(flat(ROTATIONS), "VEC4"), "SCALE": g.floats(flat(SCALES), "VEC3")}
    elif callable(attributes):
        attributes = attributes(g)
    g.doc["extensionsUsed"] = ["EXT_mesh_gpu_instancing"]
    n = g.node(dict(node, mesh=0, extensions={"EXT_mesh_gpu_instancing": {"attributes": attributes}}))
    if animate_to is not None:
        times = g.floats([0.0, 1.0], "SCALAR")
        values = g.floats(NODE["translation"] + animate_to, "VEC3")
        g.doc["animations"] = [{"channels": [{"sampler": 0, "target": {"node": n, "path": "translation"}}],
                                "samplers": [{"input": times, "output": values}]}]
    return g


def explicit_scene(node=NODE):
    g = base_scene()
    children = [g.node({"mesh": 0, "translation": t, "rotation": r, "scale": s}, root=False)
                for t, r, s in zip(TRANSLATIONS, ROTATIONS, SCALES)]
    g.node(dict(node, children=children))
    return g


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--veach", required=True)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="veach_cli_instancing_") as tmp:
        common = ["--width", "64", "--height", "48", "--spp", "4", "--integrator", "pt", "--threads", "2", "-q",
                  "--env-color", "1,1,1", "--max-depth", "3"]

        def render(name, scene, *flags):
            path = os.path.join(tmp, name + ".gltf")
            scene.write(path)
            out = os.path.join(tmp, name + ".exr")
            proc = subprocess.run([args.veach, "render", path, "-o", out, *common, *flags],
                                  capture_output=True, text=True, timeout=120)
            if not check(proc.returncode == 0, f"{name}: exit {proc.returncode}: {proc.stderr.strip()}"):
                return None
            return np.asarray(oiio.ImageBuf(out).get_pixels(oiio.FLOAT))[..., :3]

        def same(a, b, what):
            if a is None or b is None:
                return
            diff = float(np.abs(a - b).max())
            if check(diff == 0.0, f"{what}: images differ (max |difference| {diff})"):
                print(f"{what}: identical images (mean {a.mean():.4f})")

        inst = render("instanced", instanced_scene())
        expl = render("explicit", explicit_scene())
        same(inst, expl, "instanced vs explicit nodes")
        none = render("no_cubes", base_scene())
        if inst is not None and none is not None:
            check(float(np.abs(inst - none).max()) > 0.1, "the instances do not show in the image")

        moved = dict(NODE, translation=[0.5, 0.5, -5.0])
        anim = render("animated", instanced_scene(animate_to=moved["translation"]), "--frame", "24")
        expl_moved = render("explicit_moved", explicit_scene(moved))
        same(anim, expl_moved, "animated instancing node at frame 24 vs explicit nodes moved there")

        flat = lambda rows: [v for r in rows for v in r]
        bad = {
            "count mismatch": lambda g: {"TRANSLATION": g.floats(flat(TRANSLATIONS), "VEC3"),
                                         "SCALE": g.floats(flat(SCALES[:4]), "VEC3")},
            "wrong type": lambda g: {"TRANSLATION": g.floats(flat(ROTATIONS), "VEC4")},
            "out of bounds": lambda g: {"TRANSLATION": g.accessor("f", flat(TRANSLATIONS), 5126, "VEC3", 600)},
        }
        for what, attributes in bad.items():
            path = os.path.join(tmp, "bad.gltf")
            instanced_scene(attributes=attributes).write(path)
            out = os.path.join(tmp, "bad.exr")
            proc = subprocess.run([args.veach, "render", path, "-o", out, *common], capture_output=True, text=True,
                                  timeout=60)
            lines = proc.stderr.strip().splitlines()
            check(proc.returncode == 2, f"{what}: exit {proc.returncode}, expected 2")
            check(len(lines) == 1 and "EXT_mesh_gpu_instancing" in lines[0],
                  f"{what}: message {lines!r} is not one line naming the extension")
            check(not os.path.exists(out), f"{what}: wrote {out}")
            if lines:
                print(f"refused ({what}): exit {proc.returncode}: {lines[0]}")
    if FAILURES:
        sys.exit(1)
    print("PASS: EXT_mesh_gpu_instancing renders as explicit nodes, moves with its node, refuses bad accessors")


if __name__ == "__main__":
    main()

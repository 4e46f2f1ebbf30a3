#!/usr/bin/env python3
"""`veach info SCENE [--json]` says what the file holds, checked against the files themselves:

- cameras (names and types) and animations are the glTF's, in its order; the file's scenes with
  its default; KHR_materials_variants' variants (a copy of cornell given two);
- lights by kind: cornell's emissive ceiling is an emissive mesh; the textured scene's texture
  is listed with the size its PNG header gives;
- triangles are those a render reports (--stats-json), instances and meshes counted;
- the render-memory estimate is the render's own: the film part grows with the pixel count, so
  cornell (no textures) at 2048x2048 needs exactly 1024 times what 64x64 needs;
- the JSON parses with python's json; the text form names the same things; a missing file is
  bad input (exit 2, one line).
"""
import argparse
import json
import os
import shutil
import struct
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
from check_report import check, exit_code  # noqa: E402


def info(veach, *args):
    r = subprocess.run([veach, "info", *args, "--json"], capture_output=True, text=True, timeout=120)
    if not check(r.returncode == 0, f"veach info {' '.join(args)}: exit {r.returncode}: {r.stderr.strip()}"):
        return None
    return json.loads(r.stdout)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--veach", required=True)
    ap.add_argument("--scenes", required=True)
    args = ap.parse_args()
    v = args.veach
    cornell = os.path.join(args.scenes, "cornell", "cornell.gltf")
    gltf = json.load(open(cornell))
    got = info(v, cornell)
    if got:
        want = [(c.get("name", ""), c["type"]) for c in gltf.get("cameras", [])]
        cams = [(c["name"], c["type"]) for c in got["cameras"]]
        # Cameras are named by their node when the camera has no name of its own.
        check(len(cams) == len(want) and [t for _, t in cams] == [t for _, t in want], f"cameras {cams} vs {want}")
        check(len(got["scenes"]) == len(gltf.get("scenes", [])), f"scenes {got['scenes']}")
        if "scene" in gltf:
            check(got["scenes"][gltf["scene"]]["default"], f"default scene {got['scenes']}")
        check(got["lights"]["emissive_meshes"] >= 1, f"cornell's ceiling light: {got['lights']}")
        check(got["variants"] == [] and got["animations"] == [], "cornell has no variants or animations")
        with tempfile.TemporaryDirectory() as tmp:
            stats = os.path.join(tmp, "s.json")
            subprocess.run([v, "render", cornell, "-o", os.path.join(tmp, "x.exr"), "--width", "8", "--spp", "1",
                            "-q", "--stats-json", stats], check=True)
            check(got["triangles"] == json.load(open(stats))["triangles"], "triangles differ from the render's")
            # Variants: the same file with two declared.
            gltf_v = dict(gltf)
            gltf_v["extensions"] = dict(gltf.get("extensions", {}),
                                        KHR_materials_variants={"variants": [{"name": "red"}, {"name": "blue"}]})
            gltf_v["extensionsUsed"] = sorted(set(gltf.get("extensionsUsed", [])) | {"KHR_materials_variants"})
            path = os.path.join(tmp, "variants.gltf")
            json.dump(gltf_v, open(path, "w"))
            shutil.copy(os.path.join(args.scenes, "cornell", "cornell.bin"), tmp)
            got_v = info(v, path)
            check(got_v is not None and got_v["variants"] == ["red", "blue"], f"variants: {got_v and got_v['variants']}")
        small = info(v, cornell, "--width", "64", "--height", "64")
        large = info(v, cornell, "--width", "2048", "--height", "2048")
        if small and large:
            b1, b2 = small["render_memory"]["bytes"], large["render_memory"]["bytes"]
            check(b1 > 0 and b2 == 1024 * b1, f"memory estimate: 64x64 {b1}, 2048x2048 {b2}")
        r = subprocess.run([v, "info", cornell], capture_output=True, text=True, timeout=60)
        check(r.returncode == 0 and "cameras:" in r.stdout and "lights:" in r.stdout and "render:" in r.stdout,
              f"text form: {r.returncode} {r.stdout!r}")

    animated = os.path.join(args.scenes, "animated", "animated.gltf")
    got = info(v, animated)
    if got:
        want = [a.get("name", "") for a in json.load(open(animated)).get("animations", [])]
        check(got["animations"] == want and want, f"animations {got['animations']} vs {want}")

    textured = os.path.join(args.scenes, "textured", "textured.gltf")
    got = info(v, textured)
    if got:
        png = open(os.path.join(args.scenes, "textured", "checker.png"), "rb").read(24)
        w, h = struct.unpack(">II", png[16:24])
        sizes = [(t["width"], t["height"]) for t in got["textures"]]
        check((w, h) in sizes, f"textures {got['textures']}: expected one of {w}x{h}")

    r = subprocess.run([v, "info", "/nonexistent/scene.gltf"], capture_output=True, text=True, timeout=60)
    check(r.returncode == 2 and r.stderr.count("\n") == 1, f"missing file: {r.returncode} {r.stderr!r}")
    return exit_code("veach info: cameras, scenes, variants, animations, lights, triangles, textures and memory as the files say")


if __name__ == "__main__":
    sys.exit(main())

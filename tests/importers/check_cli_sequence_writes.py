#!/usr/bin/python3
"""`veach render --frames`: frame N's files are written while frame N+1 renders, and nothing of
what the writes promise changes for it.

The scene: a diffuse floor and a cube sliding across it under a white environment, path traced
at a few samples (noisy: the cube's shadow and the floor's inter-reflections), so that a frame
holding another frame's pixels, or another seed's, would show. What must hold:
- exactness: every frame of a sequence (with --animated-seed, --stats-json) has, bit for bit, the
  pixels of the same frame rendered alone by its own process (--frame N), and its stats file;
- a write that fails in the middle of a sequence stops it: frame 2's output is a folder, so its
  write fails: exit 3, one stderr line naming the file, frames 0 and 1 complete, nothing written
  for frames 3 and later, no temporary file left; the same when frame 3's --stats-json cannot be
  written (its image was written first, as for a still). (A symlink to /dev/full would not do:
  the atomic writer replaces a symlink at the target instead of writing through it.)
- an interrupt (SIGINT) mid-sequence: exit 130; every frame file there is complete and readable,
  the frames before the last one written complete (veach:complete yes), none after it, no
  temporary file left: the write in flight is finished before the process exits;
- one load: with the buffer in a .bin and a texture in a PNG, the three files removed once
  frame 0 is written, the later frames are bit for bit those frames rendered alone.
Exit 0 pass, 1 fail.
"""
import argparse
import base64
import json
import os
import signal
import struct
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
from check_report import FAILURES, check, import_numpy_oiio  # noqa: E402

np, oiio = import_numpy_oiio()


def write_scene(path, external=False):
    """The scene; `external`: its buffer in a .bin beside it and the floor's base colour from a
    checker PNG beside it (files a sequence must never read again after its load)."""
    floats = lambda values: struct.pack("<%df" % len(values), *values)
    floor = floats([-4, 0, -4, 4, 0, -4, 4, 0, 4, -4, 0, 4])
    floor_idx = struct.pack("<6H", 0, 2, 1, 0, 3, 2)
    floor_uv = floats([0, 0, 4, 0, 4, 4, 0, 4])
    c = [(x, y, z) for z in (-0.5, 0.5) for y in (0, 1) for x in (-0.5, 0.5)]
    cube = floats([v for p in c for v in p])
    cube_idx = struct.pack("<36H", 0, 3, 1, 0, 2, 3, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 4, 6,
                           0, 6, 2, 1, 3, 7, 1, 7, 5)
    times = floats([0, 1])
    slide = floats([-2.5, 0, 0, 2.5, 0, 0])
    parts = [floor, floor_idx, cube, cube_idx, times, slide, floor_uv]
    blob, views = b"", []
    for p in parts:
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(p)})
        blob += p + b"\0" * (-len(p) % 4)
    doc = {
        "asset": {"version": "2.0", "generator": "veach check_cli_sequence_writes"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [{"name": "floor", "mesh": 0}, {"name": "cube", "mesh": 1},
                  {"name": "camera", "camera": 0, "translation": [0, 5, 6],
                   "rotation": [-0.3826834, 0, 0, 0.9238795]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.05}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]},
                   {"primitives": [{"attributes": {"POSITION": 2}, "indices": 3, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0,
                                                "roughnessFactor": 1}}],
        "animations": [{"name": "slide", "channels": [{"sampler": 0, "target": {"node": 1, "path": "translation"}}],
                        "samplers": [{"input": 4, "output": 5}]}],
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
        "bufferViews": views,
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-4, 0, -4],
             "max": [4, 0, 4]},
            {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"},
            {"bufferView": 2, "componentType": 5126, "count": 8, "type": "VEC3", "min": [-0.5, 0, -0.5],
             "max": [0.5, 1, 0.5]},
            {"bufferView": 3, "componentType": 5123, "count": 36, "type": "SCALAR"},
            {"bufferView": 4, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [1]},
            {"bufferView": 5, "componentType": 5126, "count": 2, "type": "VEC3"},
            {"bufferView": 6, "componentType": 5126, "count": 4, "type": "VEC2"},
        ],
    }
    if external:
        folder, stem = os.path.split(os.path.splitext(path)[0])
        with open(os.path.join(folder, stem + ".bin"), "wb") as f:
            f.write(blob)
        doc["buffers"][0]["uri"] = stem + ".bin"
        checker = np.kron(np.indices((4, 4)).sum(axis=0) % 2, np.ones((2, 2)))[..., None] * np.array([0.9, 0.6, 0.2])
        spec = oiio.ImageSpec(8, 8, 3, oiio.UINT8)
        out = oiio.ImageOutput.create(os.path.join(folder, stem + ".png"))
        out.open(os.path.join(folder, stem + ".png"), spec)
        out.write_image((checker * 255 + 0.5).astype(np.uint8))
        out.close()
        doc["images"] = [{"uri": stem + ".png"}]
        doc["samplers"] = [{"magFilter": 9728, "minFilter": 9728}]
        doc["textures"] = [{"source": 0, "sampler": 0}]
        doc["materials"].append({"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0,
                                                          "roughnessFactor": 1}})
        doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 6
        doc["meshes"][0]["primitives"][0]["material"] = 1
    with open(path, "w") as f:
        json.dump(doc, f)


def pixels(path):
    return np.asarray(oiio.ImageBuf(path).get_pixels(oiio.FLOAT))


def attribute(path, key):
    value = oiio.ImageBuf(path).spec().getattribute(key)  # numbers are int/float attributes in EXR
    return "" if value is None else str(value)


def temporaries(folder):
    return [f for f in os.listdir(folder) if f.startswith(".") or ".tmp" in f]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--veach", required=True)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="veach_cli_sequence_writes_") as tmp:
        scene = os.path.join(tmp, "slide.gltf")
        write_scene(scene)
        common = ["--width", "48", "--height", "32", "--spp", "4", "--integrator", "pt", "--max-depth", "3",
                  "--env-color", "1,1,1", "--threads", "2", "-q"]

        def run(*flags, timeout=240):
            return subprocess.run([args.veach, "render", scene, *common, *flags], capture_output=True, text=True,
                                  timeout=timeout)

        # Exactness: the sequence's frames against each frame alone.
        seq = os.path.join(tmp, "seq")
        os.makedirs(seq)
        frames = list(range(0, 25, 4))
        proc = run("-o", os.path.join(seq, "f_####.exr"), "--stats-json", os.path.join(seq, "s_####.json"),
                   "--frames", "0-24:4", "--animated-seed")
        check(proc.returncode == 0, f"sequence: exit {proc.returncode}: {proc.stderr.strip()}")
        means = []
        for f in frames:
            alone = os.path.join(tmp, "alone_%04d.exr" % f)
            proc = run("-o", alone, "--frame", str(f), "--animated-seed")
            if not check(proc.returncode == 0, f"frame {f} alone: exit {proc.returncode}: {proc.stderr.strip()}"):
                continue
            in_seq = os.path.join(seq, "f_%04d.exr" % f)
            if not check(os.path.exists(in_seq), f"{in_seq} not written"):
                continue
            a, b = pixels(alone), pixels(in_seq)
            check(a.shape == b.shape and np.array_equal(a, b),
                  f"frame {f}: the sequence's pixels differ from the frame rendered alone "
                  f"(max |diff| {np.abs(a - b).max() if a.shape == b.shape else 'shape'})")
            check(attribute(in_seq, "veach:complete") == "yes", f"frame {f} in the sequence is not complete")
            stats = os.path.join(seq, "s_%04d.json" % f)
            if check(os.path.exists(stats), f"{stats} not written"):
                s = json.load(open(stats))
                check(s["seed"] == int(attribute(alone, "veach:seed")), f"frame {f}: stats seed {s['seed']}")
            means.append(float(b[..., :3].mean()))
        # The frames must differ from each other (the cube moves, the seed changes), or the
        # comparison above could not tell one frame's pixels from another's.
        check(len(set(means)) == len(frames), f"frame means {means} are not all different")
        print(f"sequence of {len(frames)} frames bit for bit equal to the frames alone; means {means}")
        check(not temporaries(seq), f"temporaries left: {temporaries(seq)}")

        # A failed image write in the middle stops the sequence.
        fail = os.path.join(tmp, "fail")
        os.makedirs(os.path.join(fail, "f_0002.exr"))
        proc = run("-o", os.path.join(fail, "f_####.exr"), "--frames", "0-5")
        lines = proc.stderr.strip().splitlines()
        check(proc.returncode == 3, f"frame 2's write failing: exit {proc.returncode}, expected 3")
        check(len(lines) == 1 and "f_0002.exr" in lines[0], f"frame 2's write failing: stderr {lines!r}")
        for f in (0, 1):
            path = os.path.join(fail, "f_%04d.exr" % f)
            check(os.path.exists(path) and attribute(path, "veach:complete") == "yes", f"{path} not complete")
        later = [f for f in os.listdir(fail) if f not in ("f_0000.exr", "f_0001.exr", "f_0002.exr")]
        check(not later, f"written after frame 2's write failed: {later}")
        print(f"frame 2's write failing: exit {proc.returncode}, {lines[:1]}, nothing after it")

        # A failed --stats-json write likewise.
        stats_fail = os.path.join(tmp, "stats_fail")
        os.makedirs(stats_fail)
        os.makedirs(os.path.join(stats_fail, "s_0003.json"))
        proc = run("-o", os.path.join(stats_fail, "f_####.exr"), "--stats-json", os.path.join(stats_fail, "s_####.json"),
                   "--frames", "0-5")
        lines = proc.stderr.strip().splitlines()
        check(proc.returncode == 3, f"frame 3's stats file a folder: exit {proc.returncode}, expected 3")
        check(len(lines) == 1 and "s_0003.json" in lines[0], f"frame 3's stats file a folder: stderr {lines!r}")
        want = {"f_%04d.exr" % f for f in range(4)} | {"s_%04d.json" % f for f in range(4)}  # s_0003.json: the folder
        got = set(os.listdir(stats_fail))
        check(got == want, f"frame 3's stats failing: files {sorted(got)}, expected {sorted(want)}")
        print(f"frame 3's stats failing: exit {proc.returncode}, {lines[:1]}")

        # SIGINT in the middle: every file complete, the write in flight finished.
        stop = os.path.join(tmp, "stop")
        os.makedirs(stop)
        p = subprocess.Popen([args.veach, "render", scene, *common[:-1], "--spp", "64", "-o",
                              os.path.join(stop, "f_####.exr"), "--frames", "0-200"],
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and len([f for f in os.listdir(stop) if f.endswith(".exr")]) < 3:
            time.sleep(0.02)
        p.send_signal(signal.SIGINT)
        try:
            _, err = p.communicate(timeout=60)
        except subprocess.TimeoutExpired:
            p.kill()
            _, err = p.communicate()
        check(p.returncode == 130, f"SIGINT mid-sequence: exit {p.returncode}, expected 130: {err.strip()}")
        written = sorted(f for f in os.listdir(stop) if f.endswith(".exr"))
        numbers = [int(f[2:6]) for f in written]
        check(numbers == list(range(len(numbers))) and len(numbers) >= 3,
              f"SIGINT mid-sequence: frames written {numbers}, expected 0..K")
        for i, f in enumerate(written):
            path = os.path.join(stop, f)
            try:
                complete = attribute(path, "veach:complete")
                pixels(path)
            except Exception as e:  # pragma: no cover
                check(False, f"{path} unreadable after SIGINT: {e}")
                continue
            if i < len(written) - 1:
                check(complete == "yes", f"{path} (not the last) has veach:complete {complete!r}")
        check(not temporaries(stop), f"temporaries left after SIGINT: {temporaries(stop)}")
        print(f"SIGINT: exit {p.returncode}, frames {numbers[:1]}..{numbers[-1:]} all readable")

        # One load: the .gltf, its .bin and its texture are removed once frame 0 is written (the
        # process stopped meanwhile), and every later frame is still, bit for bit, that frame
        # rendered alone from the files.
        ext = os.path.join(tmp, "ext")
        os.makedirs(ext)
        ext_scene = os.path.join(ext, "textured.gltf")
        write_scene(ext_scene, external=True)
        ext_flags = [*common[:-1], "--spp", "8", "-q"]
        last = 24
        alone = {}
        for f in (1, 12, last):
            alone[f] = os.path.join(ext, "alone_%04d.exr" % f)
            proc = subprocess.run([args.veach, "render", ext_scene, *ext_flags, "-o", alone[f], "--frame", str(f)],
                                  capture_output=True, text=True, timeout=120)
            check(proc.returncode == 0, f"textured frame {f} alone: exit {proc.returncode}: {proc.stderr.strip()}")
        out_dir = os.path.join(ext, "seq")
        os.makedirs(out_dir)
        p = subprocess.Popen([args.veach, "render", ext_scene, *ext_flags, "-o", os.path.join(out_dir, "f_####.exr"),
                              "--frames", "0-%d" % last], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        first = os.path.join(out_dir, "f_0000.exr")
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and not os.path.exists(first) and p.poll() is None:
            time.sleep(0.002)
        p.send_signal(signal.SIGSTOP)
        remaining = not os.path.exists(os.path.join(out_dir, "f_%04d.exr" % last))
        for name in ("textured.gltf", "textured.bin", "textured.png"):
            os.remove(os.path.join(ext, name))
        p.send_signal(signal.SIGCONT)
        _, err = p.communicate(timeout=180)
        check(remaining, "the sequence had written its last frame before its files could be removed")
        check(p.returncode == 0, f"sequence after its files were removed: exit {p.returncode}: {err.strip()}")
        for f, path in alone.items():
            in_seq = os.path.join(out_dir, "f_%04d.exr" % f)
            if check(os.path.exists(in_seq) and os.path.exists(path), f"textured frame {f} missing"):
                check(np.array_equal(pixels(in_seq), pixels(path)),
                      f"textured frame {f}: the sequence (its files removed after frame 0) differs from it alone")
        print(f"files removed after frame 0 (frames left: {remaining}): frames 1, 12, {last} equal to them alone")
    if FAILURES:
        sys.exit(1)
    print("PASS: sequence frames written while the next renders: exact, failures stop it, SIGINT leaves whole files")


if __name__ == "__main__":
    main()

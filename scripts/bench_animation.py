"""The animation benchmarks of `make bench` (scripts/bench.py runs them; --only-animation alone).

  - sequence: a procedural terrain of ~1M static triangles and one moving cube, rendered as a
    FRAMES-frame sequence from one load (--frames) against a single still of its middle frame at
    the same size and spp. The still pays load, BVH build and render; each frame of the sequence
    should cost its render alone (the BVH of the terrain is built once, the cube's transform set
    on Embree per frame), so the headline is sequence wall seconds per frame over the still's
    render seconds.
  - forest: one ~10k-triangle tree placed 10,000 times by EXT_mesh_gpu_instancing, against the
    same tree placed once: peak resident memory of the whole `veach render`, over the single
    tree's plus the instance table (the file's 40 bytes of TRS per instance); a forest expanded to
    triangles would need ~100M triangles.
Scenes are generated into the build folder (bench-animation/), never committed."""
import base64, json, os, struct, subprocess, time

import numpy as np

FLOAT, USHORT, UINT = 5126, 5123, 5125


class Writer:
    """A glTF with one external .bin, for scenes too large to embed."""

    def __init__(self):
        self.bin = bytearray()
        self.doc = {"asset": {"version": "2.0", "generator": "veach bench_animation"}, "scene": 0,
                    "scenes": [{"nodes": []}], "nodes": [], "meshes": [], "accessors": [], "bufferViews": [],
                    "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.55, 0.5, 1],
                                                            "metallicFactor": 0, "roughnessFactor": 0.8}}]}

    def accessor(self, array, kind, component=FLOAT, minmax=False):
        array = np.ascontiguousarray(array)
        while len(self.bin) % 4:
            self.bin.append(0)
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": len(self.bin), "byteLength": array.nbytes})
        self.bin += array.tobytes()
        count = array.shape[0] if array.ndim > 1 else array.size
        a = {"bufferView": len(self.doc["bufferViews"]) - 1, "componentType": component, "count": int(count),
             "type": kind}
        if minmax:
            a["min"] = [float(v) for v in np.atleast_1d(array.min(axis=0))]
            a["max"] = [float(v) for v in np.atleast_1d(array.max(axis=0))]
        self.doc["accessors"].append(a)
        return len(self.doc["accessors"]) - 1

    def mesh(self, positions, indices):
        pos = self.accessor(positions.astype(np.float32), "VEC3", minmax=True)
        idx = self.accessor(indices.astype(np.uint32).ravel(), "SCALAR", UINT)
        self.doc["meshes"].append({"primitives": [{"attributes": {"POSITION": pos}, "indices": idx, "material": 0}]})
        return len(self.doc["meshes"]) - 1

    def node(self, node):
        self.doc["nodes"].append(node)
        self.doc["scenes"][0]["nodes"].append(len(self.doc["nodes"]) - 1)
        return len(self.doc["nodes"]) - 1

    def write(self, path):
        name = os.path.splitext(os.path.basename(path))[0] + ".bin"
        with open(os.path.join(os.path.dirname(path), name), "wb") as f:
            f.write(self.bin)
        self.doc["buffers"] = [{"byteLength": len(self.bin), "uri": name}]
        with open(path, "w") as f:
            json.dump(self.doc, f)
        return path


def grid(n, size, height):
    """An n x n vertex height field: 2 (n - 1)^2 triangles."""
    u = np.linspace(-size / 2, size / 2, n, dtype=np.float64)
    x, z = np.meshgrid(u, u)
    y = height * (np.sin(x * 1.7) * np.cos(z * 1.3) + 0.5 * np.sin(x * 5.1 + z * 3.7))
    positions = np.stack([x, y, z], axis=-1).reshape(-1, 3)
    i = np.arange(n - 1)
    a = (i[None, :] + n * i[:, None]).ravel()
    quads = np.stack([a, a + n, a + 1, a + 1, a + n, a + n + 1], axis=-1).reshape(-1, 3)
    return positions, quads


def cube():
    c = np.array([[x, y, z] for z in (-1, 1) for y in (-1, 1) for x in (-1, 1)], dtype=np.float32) * 0.5
    f = np.array([0, 1, 3, 0, 3, 2, 4, 6, 7, 4, 7, 5, 0, 4, 5, 0, 5, 1, 2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 5, 7,
                  1, 7, 3]).reshape(-1, 3)
    return c, f


def sequence_scene(folder, frames, fps):
    w = Writer()
    terrain = w.mesh(*grid(708, 40.0, 0.6))  # 999,698 triangles
    w.node({"mesh": terrain})
    box = w.mesh(*cube())
    mover = w.node({"mesh": box, "translation": [-6.0, 1.5, 0.0]})
    times = w.accessor(np.array([0.0, (frames - 1) / fps], dtype=np.float32), "SCALAR", minmax=True)
    path = w.accessor(np.array([[-6.0, 1.5, 0.0], [6.0, 1.5, -2.0]], dtype=np.float32), "VEC3")
    w.doc["animations"] = [{"channels": [{"sampler": 0, "target": {"node": mover, "path": "translation"}}],
                            "samplers": [{"input": times, "output": path}]}]
    w.doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.05}}]
    w.node({"camera": 0, "translation": [0.0, 6.0, 14.0], "rotation": [-0.2164, 0.0, 0.0, 0.9763]})
    return w.write(os.path.join(folder, "terrain_sequence.gltf"))


def tree():
    """A trunk and a crown: ~10k triangles."""
    parts = []
    for radius, y0, y1, rings, segs in ((0.15, 0.0, 1.2, 8, 24), (1.0, 1.0, 4.0, 48, 100)):
        t = np.linspace(0, 1, rings)
        a = np.linspace(0, 2 * np.pi, segs, endpoint=False)
        r = radius * (1 - t if radius > 0.5 else np.ones_like(t)) + 0.02
        ring = np.stack([np.outer(r, np.cos(a)), np.repeat((y0 + (y1 - y0) * t)[:, None], segs, 1),
                         np.outer(r, np.sin(a))], axis=-1).reshape(-1, 3)
        i, j = np.meshgrid(np.arange(rings - 1), np.arange(segs), indexing="ij")
        v0 = i * segs + j
        v1 = i * segs + (j + 1) % segs
        faces = np.stack([v0, v0 + segs, v1, v1, v0 + segs, v1 + segs], axis=-1).reshape(-1, 3)
        parts.append((ring, faces))
    (p0, f0), (p1, f1) = parts
    return np.concatenate([p0, p1]), np.concatenate([f0, f1 + len(p0)])


def forest_scene(folder, count):
    w = Writer()
    positions, faces = tree()
    mesh = w.mesh(positions, faces)
    node = {"mesh": mesh}
    if count > 1:
        side = int(np.ceil(np.sqrt(count)))
        k = np.arange(count)
        rng = np.random.default_rng(7)
        t = np.stack([(k % side) * 3.0 - side * 1.5, np.zeros(count), (k // side) * 3.0 - side * 1.5], axis=-1)
        angle = rng.uniform(0, 2 * np.pi, count)
        q = np.stack([np.zeros(count), np.sin(angle / 2), np.zeros(count), np.cos(angle / 2)], axis=-1)
        s = np.repeat(rng.uniform(0.7, 1.3, count)[:, None], 3, 1)
        w.doc["extensionsUsed"] = ["EXT_mesh_gpu_instancing"]
        node["extensions"] = {"EXT_mesh_gpu_instancing": {"attributes": {
            "TRANSLATION": w.accessor(t.astype(np.float32), "VEC3"),
            "ROTATION": w.accessor(q.astype(np.float32), "VEC4"),
            "SCALE": w.accessor(s.astype(np.float32), "VEC3")}}}
    w.node(node)
    return w.write(os.path.join(folder, "forest_%d.gltf" % count)), len(faces)


def render(veach, scene, out, stats, *flags):
    """Wall seconds and CPU seconds (user + sys) of one `veach render`."""
    t0, c0 = time.monotonic(), os.times()
    subprocess.run([veach, "render", scene, "-o", out, "--quiet", "--stats-json", stats, *flags], check=True,
                   capture_output=True, text=True)
    c1 = os.times()
    return time.monotonic() - t0, (c1.children_user - c0.children_user) + (c1.children_system - c0.children_system)


def sequence_benchmark(veach, build, frames=120, spp=4, size=(160, 90)):
    folder = os.path.join(build, "bench-animation")
    os.makedirs(folder, exist_ok=True)
    scene = sequence_scene(folder, frames, 24.0)
    common = ["--width", str(size[0]), "--height", str(size[1]), "--spp", str(spp), "--integrator", "pt",
              "--env-color", "1,1,1", "--max-depth", "3"]
    still_stats = os.path.join(folder, "still.json")
    still_wall, still_cpu = render(veach, scene, os.path.join(folder, "still.exr"), still_stats, "--frame",
                                   str(frames // 2), *common)
    still = json.load(open(still_stats))
    seq_wall, seq_cpu = render(veach, scene, os.path.join(folder, "seq_####.exr"),
                               os.path.join(folder, "seq_####.json"), "--frames", "0-%d" % (frames - 1), *common)
    per_frame = [json.load(open(os.path.join(folder, "seq_%04d.json" % f)))["seconds"] for f in range(frames)]
    later = per_frame[1:]
    mean = lambda key: sum(s[key] for s in later) / len(later)
    s = still["seconds"]
    # What a later frame costs the sequence: a frame's files are written while the next frame
    # renders, so its own span (pose to its files written) overlaps the next one's. The cost is the
    # interval between consecutive frames' images landing (their modification times: each is
    # renamed into place once written), over frames 1..N-1, which leaves out frame 0's load and
    # build and the process's start and exit.
    landed = [os.stat(os.path.join(folder, "seq_%04d.exr" % f)).st_mtime_ns * 1e-9 for f in range(frames)]
    per_frame_wall = (landed[-1] - landed[1]) / max(frames - 2, 1)
    rows = [
        "| measure | value |",
        "|---|---|",
        "| scene | %d static triangles + one moving cube, %dx%d, %d spp, pt, depth 3 |" % (
            still["triangles"] - 12, size[0], size[1], spp),
        "| still (frame %d), own process: load / build / render / write seconds | %.2f / %.2f / %.3f / %.3f |" % (
            frames // 2, s["load"], s["build"], s["render"], s["write"]),
        "| still: wall / CPU seconds of the process | %.2f / %.2f |" % (still_wall, still_cpu),
        "| sequence of %d frames, one process: wall / CPU seconds | %.2f / %.2f |" % (frames, seq_wall, seq_cpu),
        "| sequence frame 0: load / build seconds (paid once) | %.2f / %.2f |" % (
            per_frame[0]["load"], per_frame[0]["build"]),
        "| frames 1..%d, mean seconds: update (build) / render / write / span (pose to files written) | "
        "%.4f / %.3f / %.4f / %.3f |" % (frames - 1, mean("build"), mean("render"), mean("write"), mean("total")),
        "| frames 1..%d: sequence seconds per frame (interval between images landing) | %.3f |" % (
            frames - 1, per_frame_wall),
        "| sequence seconds per frame / its render (frames 1..%d) | %.3f |" % (frames - 1,
                                                                              per_frame_wall / mean("render")),
        "| sequence seconds per frame / the still's render | %.3f |" % (per_frame_wall / s["render"]),
        "| sequence CPU per frame / the still's CPU | %.3f |" % (seq_cpu / frames / still_cpu),
    ]
    return "\n".join(rows)


def forest_benchmark(veach, build, count=10000):
    folder = os.path.join(build, "bench-animation")
    os.makedirs(folder, exist_ok=True)
    one, triangles = forest_scene(folder, 1)
    many, _ = forest_scene(folder, count)
    common = ["--width", "96", "--height", "64", "--spp", "1", "--integrator", "pt", "--env-color", "1,1,1",
              "--max-depth", "2"]
    peaks, walls = {}, {}
    for name, scene in (("one", one), ("many", many)):
        stats = os.path.join(folder, "forest_%s.json" % name)
        walls[name] = render(veach, scene, os.path.join(folder, "forest_%s.exr" % name), stats, *common)[0]
        peaks[name] = json.load(open(stats))["peak_rss_bytes"]
    table = count * 40  # TRANSLATION + ROTATION + SCALE floats per instance
    mib = lambda b: b / (1 << 20)
    rows = [
        "| measure | value |",
        "|---|---|",
        "| tree | %d triangles |" % triangles,
        "| peak RSS, one tree (whole `veach render`) | %.1f MiB |" % mib(peaks["one"]),
        "| instance table, %d instances x 40 bytes | %.2f MiB |" % (count, mib(table)),
        "| peak RSS, %d instances (%.0fM triangles instanced) | %.1f MiB |" % (
            count, count * triangles / 1e6, mib(peaks["many"])),
        "| forest / (one tree + instance table) | %.3f |" % (peaks["many"] / (peaks["one"] + table)),
        "| forest - one tree, per instance | %.0f bytes |" % ((peaks["many"] - peaks["one"]) / count),
        "| wall seconds, one tree / forest | %.2f / %.2f |" % (walls["one"], walls["many"]),
    ]
    return "\n".join(rows)

#!/usr/bin/python3
"""A generated scene of two million triangles loads and renders within the memory budget.

Writes a .glb holding one 1001 x 1001 vertex grid (2,000,000 triangles, positions, normals,
32-bit indices) bent into a shallow bowl, with an emissive quad above it, renders it with the
`veach` command at a small size and reads --stats-json: peak resident memory per triangle must
stay under --max-bytes-per-triangle (300), and the image must have no non-finite sample.
Prints the numbers docs/BENCHMARKS.md reports.

Takes a few seconds (about 3 s of load, build and render on the 2-core machine), so it runs in
`make test`.
"""
import argparse
import json
import os
import struct
import subprocess
import sys
import tempfile

import numpy as np


def write_grid_glb(path, n):
    # n x n vertices on [-1, 1]^2 in XZ, y = 0.3 (x^2 + z^2): every triangle well shaped.
    xs = np.linspace(-1.0, 1.0, n, dtype=np.float32)
    gx, gz = np.meshgrid(xs, xs)
    gy = 0.3 * (gx * gx + gz * gz)
    pos = np.stack([gx, gy, gz], axis=-1).reshape(-1, 3).astype(np.float32)
    nrm = np.stack([-0.6 * gx, np.ones_like(gx), -0.6 * gz], axis=-1).reshape(-1, 3)
    nrm = (nrm / np.linalg.norm(nrm, axis=1, keepdims=True)).astype(np.float32)
    i = np.arange(n - 1, dtype=np.uint32)
    r, c = np.meshgrid(i, i, indexing="ij")
    v00 = (r * n + c).ravel()
    v01, v10, v11 = v00 + 1, v00 + n, v00 + n + 1
    idx = np.stack([v00, v10, v01, v01, v10, v11], axis=-1).reshape(-1).astype(np.uint32)
    quad_pos = np.array([[-0.3, 1.5, -0.3], [0.3, 1.5, -0.3], [0.3, 1.5, 0.3], [-0.3, 1.5, 0.3]], np.float32)
    quad_idx = np.array([0, 1, 2, 0, 2, 3], np.uint32)
    blobs = [pos.tobytes(), nrm.tobytes(), idx.tobytes(), quad_pos.tobytes(), quad_idx.tobytes()]
    views, offset = [], 0
    for b in blobs:
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(b)})
        offset += len(b)
    binary = b"".join(blobs)
    gltf = {
        "asset": {"version": "2.0", "generator": "veach check_large_scene.py"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [{"mesh": 0}, {"mesh": 1},
                  {"camera": 0, "translation": [0, 1.2, 2.6], "rotation": [-0.2588190, 0, 0, 0.9659258]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.01, "aspectRatio": 1}}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0}},
                      {"emissiveFactor": [1, 1, 1], "doubleSided": True,
                       "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 10}}}],
        "extensionsUsed": ["KHR_materials_emissive_strength"],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]},
                   {"primitives": [{"attributes": {"POSITION": 3}, "indices": 4, "material": 1}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": n * n, "type": "VEC3",
             "min": [-1, 0, -1], "max": [1, 0.6, 1]},
            {"bufferView": 1, "componentType": 5126, "count": n * n, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5125, "count": int(idx.size), "type": "SCALAR"},
            {"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-0.3, 1.5, -0.3], "max": [0.3, 1.5, 0.3]},
            {"bufferView": 4, "componentType": 5125, "count": 6, "type": "SCALAR"},
        ],
        "bufferViews": views,
        "buffers": [{"byteLength": len(binary)}],
    }
    js = json.dumps(gltf, separators=(",", ":")).encode()
    js += b" " * (-len(js) % 4)
    binary += b"\0" * (-len(binary) % 4)
    with open(path, "wb") as f:
        f.write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(js) + 8 + len(binary)))
        f.write(struct.pack("<II", len(js), 0x4E4F534A) + js)
        f.write(struct.pack("<II", len(binary), 0x004E4942) + binary)
    return int(idx.size) // 3 + 2


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--veach", required=True)
    ap.add_argument("--grid", type=int, default=1001, help="vertices per side: 1001 gives 2,000,000 triangles")
    ap.add_argument("--max-bytes-per-triangle", type=float, default=300.0)
    ap.add_argument("--width", type=int, default=64)
    ap.add_argument("--spp", type=int, default=4)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="veach-large-") as work:
        scene = os.path.join(work, "grid.glb")
        triangles = write_grid_glb(scene, args.grid)
        file_bytes = os.path.getsize(scene)
        stats_path = os.path.join(work, "stats.json")
        cmd = [args.veach, "render", scene, "-o", os.path.join(work, "grid.exr"), "--width", str(args.width),
               "--spp", str(args.spp), "--quiet", "--stats-json", stats_path]
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
        if proc.returncode != 0:
            print(f"FAIL: veach exited {proc.returncode}: {proc.stderr.strip()}")
            return 1
        with open(stats_path) as f:
            stats = json.load(f)
    per_tri = stats["peak_rss_bytes"] / stats["triangles"]
    sec = stats["seconds"]
    print(f"check_large_scene: {stats['triangles']} triangles (file {triangles}), file "
          f"{file_bytes} bytes")
    print(f"  load {sec['load']:.2f} s, build {sec['build']:.2f} s, render {sec['render']:.2f} s "
          f"({args.width} px wide, {args.spp} spp), total {sec['total']:.2f} s")
    print(f"  peak RSS {stats['peak_rss_bytes'] / 2**20:.1f} MiB = {per_tri:.1f} bytes/triangle "
          f"(budget {args.max_bytes_per_triangle:.0f})")
    ok = True
    if stats["triangles"] != triangles:
        print(f"FAIL: rendered {stats['triangles']} triangles, the file has {triangles}")
        ok = False
    if per_tri >= args.max_bytes_per_triangle:
        print("FAIL: peak memory over budget")
        ok = False
    if stats["nonfinite_samples"] != 0:
        print(f"FAIL: {stats['nonfinite_samples']} non-finite samples")
        ok = False
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())

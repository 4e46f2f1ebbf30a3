#!/usr/bin/python3
"""Writes the Draco test twins in this folder (run from anywhere; needs Debian's `draco` package).

draco_twin.glb: a lumpy sphere (POSITION, NORMAL, TEXCOORD_0, COLOR_0, u16 indices) with a
camera and a sun, uncompressed. draco_twin_draco.glb: the same file through Debian's
draco_transcoder (a tool other than Veach), so its Draco stream, vertex order and JSON are what
that tool writes. The quantization bits below are what tests/importers/test_gltf_draco.cpp
derives its error bounds from; keep them in step.
"""
import json, math, os, struct, subprocess, sys, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
QP, QN, QT, QC = 14, 12, 12, 10  # position, normal, texcoord, colour quantization bits

def mesh(rings=10, segments=16):
    pos, nrm, uv, col = [], [], [], []
    for i in range(rings + 1):
        th = math.pi * i / rings
        for j in range(segments + 1):
            ph = 2 * math.pi * j / segments
            d = (math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph))
            r = 1 + 0.15 * math.sin(3 * ph) * math.sin(th) ** 2  # lumps: normals differ from positions
            pos += [r * c for c in d]
            uv += [j / segments, i / rings]
            col += [0.5 + 0.4 * d[0], 0.5 + 0.4 * d[1], 0.5 + 0.4 * d[2]]
    # Normals from the surface: finite differences of the parametrisation.
    def p(i, j):
        k = 3 * (i * (segments + 1) + j)
        return pos[k:k + 3]
    for i in range(rings + 1):
        for j in range(segments + 1):
            a = p(min(i + 1, rings), j); b = p(max(i - 1, 0), j)
            c = p(i, (j + 1) % segments); e = p(i, (j - 1) % segments)
            du = [a[k] - b[k] for k in range(3)]; dv = [c[k] - e[k] for k in range(3)]
            n = [du[1] * dv[2] - du[2] * dv[1], du[2] * dv[0] - du[0] * dv[2], du[0] * dv[1] - du[1] * dv[0]]
            if i in (0, rings):
                n = [0, 1 if i == 0 else -1, 0]
            length = math.sqrt(sum(x * x for x in n)) or 1
            q = p(i, j)
            s = 1 if sum(n[k] * q[k] for k in range(3)) >= 0 else -1  # outward
            nrm += [s * x / length for x in n]
    idx = []
    for i in range(rings):
        for j in range(segments):
            a = i * (segments + 1) + j; b = a + segments + 1
            if i > 0: idx += [a, a + 1, b]
            if i < rings - 1: idx += [a + 1, b + 1, b]
    return pos, nrm, uv, col, idx

def glb(doc, bin_):
    text = json.dumps(doc, separators=(',', ':')).encode()
    text += b' ' * (-len(text) % 4)
    bin_ += b'\0' * (-len(bin_) % 4)
    out = struct.pack('<4sII', b'glTF', 2, 12 + 8 + len(text) + 8 + len(bin_))
    return out + struct.pack('<I4s', len(text), b'JSON') + text + struct.pack('<I4s', len(bin_), b'BIN\0') + bin_

def main():
    pos, nrm, uv, col, idx = mesh()
    n = len(pos) // 3
    blobs, views, accessors = b'', [], []
    def add(data, fmt, ctype, type_, count, minmax=None):
        nonlocal blobs
        blobs += b'\0' * (-len(blobs) % 4)
        raw = struct.pack('<%d%s' % (len(data), fmt), *data)
        views.append({'buffer': 0, 'byteOffset': len(blobs), 'byteLength': len(raw)})
        blobs += raw
        a = {'bufferView': len(views) - 1, 'componentType': ctype, 'count': count, 'type': type_}
        if minmax: a.update(minmax)
        accessors.append(a)
        return len(accessors) - 1
    mins = [min(pos[k::3]) for k in range(3)]; maxs = [max(pos[k::3]) for k in range(3)]
    attrs = {'POSITION': add(pos, 'f', 5126, 'VEC3', n, {'min': mins, 'max': maxs}),
             'NORMAL': add(nrm, 'f', 5126, 'VEC3', n), 'TEXCOORD_0': add(uv, 'f', 5126, 'VEC2', n),
             'COLOR_0': add(col, 'f', 5126, 'VEC3', n)}
    ind = add(idx, 'H', 5123, 'SCALAR', len(idx))
    s = math.sqrt(0.5)
    doc = {
        'asset': {'version': '2.0', 'generator': 'veach tests/data/gltf/make_draco_twins.py'},
        'extensionsUsed': ['KHR_lights_punctual'],
        'extensions': {'KHR_lights_punctual': {'lights': [{'type': 'directional', 'intensity': 683 * 3}]}},
        'scene': 0, 'scenes': [{'nodes': [0, 1, 2]}],
        'nodes': [{'mesh': 0},
                  {'camera': 0, 'translation': [0, 0, 4]},
                  {'rotation': [-0.3535534, 0.3535534, 0.1464466, 0.8535534],
                   'extensions': {'KHR_lights_punctual': {'light': 0}}}],
        'cameras': [{'type': 'perspective', 'perspective': {'yfov': 0.7, 'aspectRatio': 1, 'znear': 0.1}}],
        'materials': [{'pbrMetallicRoughness': {'metallicFactor': 0, 'roughnessFactor': 1}}],
        'meshes': [{'name': 'lumpy', 'primitives': [{'attributes': attrs, 'indices': ind, 'material': 0}]}],
        'accessors': accessors, 'bufferViews': views, 'buffers': [{'byteLength': len(blobs)}],
    }
    plain = os.path.join(HERE, 'draco_twin.glb')
    with open(plain, 'wb') as f:
        f.write(glb(doc, blobs))
    out = os.path.join(HERE, 'draco_twin_draco.glb')
    subprocess.run(['draco_transcoder', '-i', plain, '-o', out, '-qp', str(QP), '-qn', str(QN),
                    '-qt', str(QT), '-qc', str(QC)], check=True)
    print(plain, os.path.getsize(plain), out, os.path.getsize(out))

if __name__ == '__main__':
    main()

"""Gallery: glass and caustics. A glass sphere, a water-clear block and a polished metal ring
focus a small, bright light onto a white floor: light paths that only bidirectional tracing
finds quickly."""
import math

import scene_kit as kit

RESOLUTION = (320, 180)
SPP = 0


def _ring(name, center, radius, tube, material, segments=64, sides=16):
    vertices, faces = [], []
    for i in range(segments):
        a = 2 * math.pi * i / segments
        for j in range(sides):
            b = 2 * math.pi * j / sides
            r = radius + tube * math.cos(b)
            vertices.append((center[0] + r * math.cos(a), center[1] + r * math.sin(a),
                             center[2] + tube * math.sin(b)))
    for i in range(segments):
        for j in range(sides):
            a, b = i * sides + j, i * sides + (j + 1) % sides
            c, d = ((i + 1) % segments) * sides + (j + 1) % sides, ((i + 1) % segments) * sides + j
            faces.append((a, d, c, b))
    return kit.mesh(name, vertices, faces, material, smooth=True)


def build():
    white = kit.lambert("white", (0.8, 0.8, 0.8))
    glass = kit.principled("glass", (1.0, 1.0, 1.0), roughness=0.0, transmission=1.0, ior=1.5)
    tinted = kit.principled("tinted_glass", (0.75, 0.9, 1.0), roughness=0.02, transmission=1.0, ior=1.45)
    chrome = kit.principled("chrome", (0.95, 0.93, 0.88), metallic=1.0, roughness=0.04)
    light = kit.emitter("light", (1.0, 0.95, 0.85), 900.0)
    kit.quad("floor", (-6, -6, 0), (6, -6, 0), (6, 6, 0), (-6, 6, 0), white)
    kit.quad("back", (-6, 3, 0), (6, 3, 0), (6, 3, 5), (-6, 3, 5), white)
    kit.uv_sphere("glass_sphere", (-1.2, 0.4, 0.7), 0.7, glass, segments=64, rings=32)
    kit.box("block", (0.6, 0.9, 0.45), (0.9, 0.9, 0.9), 30.0, tinted)
    _ring("ring", (1.7, -0.6, 0.12), 0.55, 0.12, chrome)
    kit.quad("light", (-0.1, -0.1, 3.6), (-0.1, 0.1, 3.6), (0.1, 0.1, 3.6), (0.1, -0.1, 3.6), light)
    kit.camera((0.0, -5.5, 2.6), (0.1, 0.3, 0.4), lens=38.0)

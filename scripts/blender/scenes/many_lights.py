"""A long diffuse hall (12 x 40 m, 4 m high) lit by 240 small one-sided emissive ceiling tiles
(four strengths and colours) and 48 point lights scattered low through it, with crates and
pillars between them: most lights matter only near themselves, the case for choosing lights per
receiver (a light tree) rather than by power. Blender 3.4's Cycles has no light tree.
"""
import random

import scene_kit as kit

RESOLUTION = (192, 144)
SPP = 8192

WIDTH, LENGTH, HEIGHT = 12.0, 40.0, 4.0
TILES_X, TILES_Y = 12, 20
POINTS = 48


def build():
    rng = random.Random(7)
    wall = kit.lambert("wall", (0.7, 0.7, 0.68))
    floor = kit.lambert("floor", (0.45, 0.4, 0.35))
    crate = kit.lambert("crate", (0.6, 0.35, 0.2))
    w, l, h = WIDTH, LENGTH, HEIGHT
    # Faces point into the hall.
    kit.quad("floor", (0, 0, 0), (w, 0, 0), (w, l, 0), (0, l, 0), floor)
    kit.quad("ceiling", (0, 0, h), (0, l, h), (w, l, h), (w, 0, h), wall)
    kit.quad("wall_w", (0, 0, 0), (0, l, 0), (0, l, h), (0, 0, h), wall)
    kit.quad("wall_e", (w, 0, 0), (w, 0, h), (w, l, h), (w, l, 0), wall)
    kit.quad("wall_n", (0, l, 0), (w, l, 0), (w, l, h), (0, l, h), wall)
    kit.quad("wall_s", (0, 0, 0), (0, 0, h), (w, 0, h), (w, 0, 0), wall)
    for i in range(8):
        x, y = (3.0 if i % 2 == 0 else w - 3.0), 5.0 + 8.0 * (i // 2)
        kit.box("pillar%d" % i, (x, y, h / 2), (0.6, 0.6, h), 0.0, wall)
    for i in range(14):
        x, y = 1.0 + (w - 2.0) * rng.random(), 2.0 + (l - 3.0) * rng.random()
        size = 0.4 + 0.6 * rng.random()
        kit.box("crate%d" % i, (x, y, size / 2), (size, size, size), 90.0 * rng.random(), crate)
    # Ceiling tiles, 0.3 m square, facing down, in four meshes by strength and colour.
    looks = [((1.0, 0.9, 0.75), 30.0), ((0.7, 0.8, 1.0), 15.0), ((1.0, 0.6, 0.3), 60.0), ((1.0, 1.0, 1.0), 5.0)]
    groups = [([], []) for _ in looks]
    half = 0.15
    for i in range(TILES_X):
        for j in range(TILES_Y):
            x = (i + 0.5) * w / TILES_X
            y = (j + 0.5) * l / TILES_Y
            z = h - 0.01
            verts, faces = groups[rng.randrange(len(looks))]
            base = len(verts)
            # Clockwise seen from above: the front faces down.
            verts += [(x - half, y - half, z), (x - half, y + half, z), (x + half, y + half, z), (x + half, y - half, z)]
            faces.append((base, base + 1, base + 2, base + 3))
    for k, ((color, strength), (verts, faces)) in enumerate(zip(looks, groups)):
        if faces:
            kit.mesh("tiles%d" % k, verts, faces, kit.emitter("tile%d" % k, color, strength))
    for i in range(POINTS):
        location = (0.4 + (w - 0.8) * rng.random(), 0.8 + (l - 1.2) * rng.random(), 0.3 + 1.2 * rng.random())
        color = (0.6 + 0.4 * rng.random(), 0.6 + 0.4 * rng.random(), 0.6 + 0.4 * rng.random())
        kit.point_light("point%d" % i, location, 20.0 + 130.0 * rng.random(), color=color)
    kit.camera((w / 2, 0.4, 1.7), (w / 2, l, 0.9), lens=18.0)

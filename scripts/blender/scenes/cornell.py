"""Cornell box: a diffuse box 2 m wide lit by an emissive quad filling a hole in the ceiling (it
emits down into the box; its back faces the empty outside, so one- and two-sided emission look
the same). The classic global-illumination test."""
import scene_kit as kit

RESOLUTION = (256, 256)
SPP = 8192


def build():
    white = kit.lambert("white", (0.73, 0.73, 0.73))
    red = kit.lambert("red", (0.63, 0.065, 0.05))
    green = kit.lambert("green", (0.14, 0.45, 0.091))
    light = kit.emitter("light", (1.0, 0.85, 0.6), 15.0)
    kit.quad("floor", (-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0), white)
    kit.quad("back", (-1, 1, 0), (1, 1, 0), (1, 1, 2), (-1, 1, 2), white)
    kit.quad("left", (-1, -1, 0), (-1, 1, 0), (-1, 1, 2), (-1, -1, 2), red)
    kit.quad("right", (1, -1, 0), (1, -1, 2), (1, 1, 2), (1, 1, 0), green)
    hole = 0.25  # half the side of the light's square hole
    outer = [(-1, -1, 2), (1, -1, 2), (1, 1, 2), (-1, 1, 2)]
    inner = [(-hole, -hole, 2), (hole, -hole, 2), (hole, hole, 2), (-hole, hole, 2)]
    kit.mesh("ceiling", outer + inner, [(0, 4, 5, 1), (1, 5, 6, 2), (2, 6, 7, 3), (3, 7, 4, 0)], white)
    kit.quad("light", inner[0], inner[3], inner[2], inner[1], light)
    kit.box("tall", (-0.35, 0.3, 0.6), (0.6, 0.6, 1.2), 17.0, white)
    kit.box("short", (0.35, -0.35, 0.3), (0.6, 0.6, 0.6), -17.0, white)
    kit.camera((0, -3.3, 1), (0, 0, 1), lens=32.0)

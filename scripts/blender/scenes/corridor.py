"""An L-shaped corridor whose lamp hangs round the corner, out of sight of every point the camera
sees: all light arrives after two or more diffuse bounces (where bidirectional tracing wins)."""
import scene_kit as kit

RESOLUTION = (160, 120)
SPP = 16384
HEIGHT = 2.6


def build():
    white = kit.lambert("white", (0.8, 0.8, 0.8))
    floor = kit.lambert("floor", (0.5, 0.42, 0.35))
    accent = kit.lambert("accent", (0.7, 0.25, 0.2))
    lamp = kit.emitter("lamp", (0.9, 0.95, 1.0), 150.0)
    h = HEIGHT
    # Leg A spans x 0..8, y 0..2; leg B x 6..8, y 2..8. Faces point into the corridor.
    kit.quad("floorA", (0, 0, 0), (8, 0, 0), (8, 2, 0), (0, 2, 0), floor)
    kit.quad("floorB", (6, 2, 0), (8, 2, 0), (8, 8, 0), (6, 8, 0), floor)
    kit.quad("ceilA", (0, 0, h), (0, 2, h), (8, 2, h), (8, 0, h), white)
    kit.quad("ceilB", (6, 2, h), (6, 8, h), (8, 8, h), (8, 2, h), white)
    kit.quad("wallA_s", (0, 0, 0), (0, 0, h), (8, 0, h), (8, 0, 0), white)
    kit.quad("wallA_n", (0, 2, 0), (6, 2, 0), (6, 2, h), (0, 2, h), accent)
    kit.quad("wall_e", (8, 0, 0), (8, 0, h), (8, 8, h), (8, 8, 0), white)
    kit.quad("wallB_w", (6, 2, 0), (6, 8, 0), (6, 8, h), (6, 2, h), white)
    kit.quad("endB", (6, 8, 0), (8, 8, 0), (8, 8, h), (6, 8, h), white)
    kit.quad("endA", (0, 0, 0), (0, 2, 0), (0, 2, h), (0, 0, h), white)
    kit.box("lamp", (7.0, 7.2, h - 0.1), (0.5, 0.5, 0.06), 0.0, lamp)
    kit.box("crate", (7.3, 1.2, 0.35), (0.7, 0.7, 0.7), 20.0, white)
    kit.camera((0.5, 1.0, 1.5), (8.0, 1.2, 1.0), lens=22.0)

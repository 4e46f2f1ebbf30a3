"""A diffuse floor, ball and box lit only by a uniform World (a colour times a strength): the
Blender add-on carries the World over as the environment (glTF has none)."""
import scene_kit as kit

RESOLUTION = (64, 48)
BLEND_SAMPLES = 64
SPP = 2048
VEACH_ARGS = ["--env-color", "0.9,1.05,1.35"]


def build():
    floor = kit.lambert("floor", (0.7, 0.7, 0.7))
    orange = kit.lambert("orange", (0.8, 0.3, 0.05))
    blue = kit.lambert("blue", (0.1, 0.25, 0.7))
    kit.quad("floor", (-3, -3, 0), (3, -3, 0), (3, 3, 0), (-3, 3, 0), floor)
    kit.uv_sphere("ball", (-0.5, 0.2, 0.5), 0.5, orange, segments=32, rings=16)
    kit.box("box", (0.7, 0.5, 0.4), (0.8, 0.8, 0.8), 25.0, blue)
    kit.world_color((0.6, 0.7, 0.9), strength=1.5)
    kit.camera((0, -4.5, 2.0), (0, 0.3, 0.4), lens=35.0)

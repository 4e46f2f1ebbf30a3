"""Gallery: image-based lighting. A mirror ball, a brushed (rough) metal ball and a diffuse ball
on a pedestal, lit only by an equirectangular sky map (a blue gradient with a small, very bright
sun), rotated with a Mapping node as `--env-rotate` does."""
import math

import scene_kit as kit

RESOLUTION = (320, 180)
SPP = 0
VEACH_ARGS = ["--env", "sky.hdr", "--env-rotate", "40"]

WIDTH, HEIGHT = 256, 128
SUN = (0.6, 0.78)  # (u, v) of the sun in the map


def sky(i, j):
    u, v = (i + 0.5) / WIDTH, (j + 0.5) / HEIGHT  # v = 1 at the zenith (Blender's bottom-up rows)
    if v < 0.5:  # below the horizon: warm ground
        return (0.18, 0.15, 0.12)
    height = (v - 0.5) * 2.0
    colour = (0.9 - 0.6 * height, 1.0 - 0.45 * height, 1.2)
    du, dv = (u - SUN[0]) * 2.0, v - SUN[1]
    if du * du + dv * dv < 0.02 ** 2:
        return (150.0, 135.0, 115.0)
    return tuple(0.6 * c for c in colour)


def build():
    image = kit.image_from_function("sky", WIDTH, HEIGHT, sky, float_buffer=True, file_format='HDR')
    kit.world_hdri(image, strength=1.0, rotation_z_degrees=40.0)
    stone = kit.lambert("stone", (0.5, 0.48, 0.45))
    kit.box("pedestal", (0.0, 0.0, -0.25), (4.2, 1.6, 0.5), 0.0, stone)
    kit.uv_sphere("mirror", (-1.3, 0.0, 0.5), 0.5, kit.principled("mirror", (0.97, 0.97, 0.97), metallic=1.0,
                                                                   roughness=0.0))
    kit.uv_sphere("brushed", (0.0, 0.0, 0.5), 0.5, kit.principled("brushed", (0.95, 0.7, 0.5), metallic=1.0,
                                                                   roughness=0.35))
    kit.uv_sphere("diffuse", (1.3, 0.0, 0.5), 0.5, kit.lambert("diffuse", (0.8, 0.8, 0.8)))
    kit.camera((0.0, -5.0, 1.3), (0.0, 0.0, 0.35), lens=45.0)

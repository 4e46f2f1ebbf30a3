"""The world_color scene lit only by an equirectangular World image (a small float HDR: a bright
warm patch low in the sky, a blue gradient above, a dark ground), with a strength and a Mapping
node turning it 60 degrees about Z: the Blender add-on carries the Environment Texture, its
strength and rotation over as the environment."""
import math

import scene_kit as kit
from scenes import world_color

RESOLUTION = (64, 48)
BLEND_SAMPLES = 64
SPP = 2048
VEACH_ARGS = ["--env", "sky.hdr", "--env-strength", "0.8", "--env-rotate", "60"]
SKY_W, SKY_H = 64, 32


def sky_texel(i, j):
    """Texel (i, j) with j = 0 the bottom row (straight down)."""
    u, v = (i + 0.5) / SKY_W, (j + 0.5) / SKY_H
    if v < 0.5:
        return (0.15, 0.12, 0.1)
    if abs(u - 0.3) < 0.06 and 0.55 < v < 0.68:
        return (40.0, 30.0, 18.0)
    t = (v - 0.5) * 2
    return (0.3 + 0.2 * t, 0.45 + 0.25 * t, 0.9 + 0.3 * t)


def build():
    world_color.build()
    sky = kit.image_from_function("sky", SKY_W, SKY_H, sky_texel, float_buffer=True, file_format='HDR')
    kit.world_hdri(sky, strength=0.8, rotation_z_degrees=60.0)

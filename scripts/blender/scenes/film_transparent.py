"""Film > Transparent: the world_color set-up on a small floor, so that the camera sees the
World around it, rendered with a transparent film (RGBA). The World lights the scene but the
camera sees none of it: background pixels are (0, 0, 0, 0), covered pixels have alpha 1, and
edges their covered fraction, premultiplied. For the Blender add-on's test (the `veach` command
has no transparent film: rendered from the glTF it shows the World's colour where Cycles' alpha
is 0)."""
import bpy

import scene_kit as kit

RESOLUTION = (96, 64)
BLEND_SAMPLES = 64
SPP = 1024
VEACH_ARGS = ["--env-color", "0.9,1.05,1.35"]


def build():
    floor = kit.lambert("floor", (0.7, 0.7, 0.7))
    orange = kit.lambert("orange", (0.8, 0.3, 0.05))
    blue = kit.lambert("blue", (0.1, 0.25, 0.7))
    kit.quad("floor", (-1.6, -1.2, 0), (1.6, -1.2, 0), (1.6, 1.4, 0), (-1.6, 1.4, 0), floor)
    kit.uv_sphere("ball", (-0.5, 0.2, 0.9), 0.5, orange, segments=32, rings=16)
    kit.box("box", (0.7, 0.5, 0.4), (0.8, 0.8, 0.8), 25.0, blue)
    kit.world_color((0.6, 0.7, 0.9), strength=1.5)
    kit.camera((0, -4.5, 2.0), (0, 0.3, 0.5), lens=30.0)
    render = bpy.context.scene.render
    render.film_transparent = True
    render.image_settings.color_mode = 'RGBA'

"""The Cornell box with an sRGB checker image on the floor and the back wall: texture decoding
and UV orientation. A red square marks the texel at UV (0, 0) (Blender's bottom-left), which a
flipped V would move."""
import scene_kit as kit
from scenes import cornell

RESOLUTION = (256, 256)
SPP = 4096


def checker_texel(i, j):
    if i < 8 and j < 8:
        return (0.9, 0.1, 0.1)
    return (0.9, 0.75, 0.2) if (i // 8 + j // 8) % 2 else (0.1, 0.2, 0.55)


def build():
    cornell.build()
    checker = kit.lambert("checker", (1, 1, 1), image=kit.image_from_function("checker", 64, 64, checker_texel))
    for name in ("floor", "back"):
        data = kit.bpy.data.objects[name].data
        layer = data.uv_layers.new(name="UVMap")
        for loop, uv in zip(data.loops, [(0, 0), (1, 0), (1, 1), (0, 1)]):
            layer.data[loop.index].uv = uv
        data.materials[0] = checker

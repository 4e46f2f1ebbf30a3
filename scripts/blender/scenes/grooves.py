"""Normal-mapped grooves against a flat surface under a uniform World: three Lambert 0.8 squares
side by side, seen from 2.5 m above, the left one flat, the middle one with grooves tilted +-30
degrees and the right one +-60 degrees (a Normal Map of strength 1, so glTF's
normalTexture.scale 1 means the same tilt). How dark strong grooves come out is where renderers
differ: Cycles corrects the mapped normal per view ("ensure valid reflection"), Veach makes it a
facet of a microsurface (README, "Normal maps"). The camera is near on purpose: from 20 m with a
200 mm lens, or orthographic, Cycles 3.4 showed the flat square brighter than its albedo (0.833
and 0.5835 for 0.8 and 0.5 at 20 m, 0.559 for 0.5 orthographic), as if part of each pixel saw
the World."""
import math

import scene_kit as kit

RESOLUTION = (96, 32)
SPP = 4096
VEACH_ARGS = ["--env-color", "1,1,1"]


def groove_texel(degrees):
    s, c = math.sin(math.radians(degrees)), math.cos(math.radians(degrees))

    def texel(i, j):
        # Tilted toward +u on four columns, toward -u on the next four: eight grooves per square.
        tilt = s if (i // 4) % 2 == 0 else -s
        return ((tilt + 1) / 2, 0.5, (c + 1) / 2)
    return texel


def build():
    flat = kit.lambert("flat", (0.8, 0.8, 0.8))
    kit.quad("flat", (-1.6, -0.5, 0), (-0.6, -0.5, 0), (-0.6, 0.5, 0), (-1.6, 0.5, 0), flat, uv=True)
    for degrees, x in ((30, -0.5), (60, 0.6)):
        image = kit.image_from_function("grooves%d" % degrees, 64, 64, groove_texel(degrees), colorspace='Non-Color')
        material = kit.lambert("grooves%d" % degrees, (0.8, 0.8, 0.8), normal_image=image)
        kit.quad("grooves%d" % degrees, (x, -0.5, 0), (x + 1, -0.5, 0), (x + 1, 0.5, 0), (x, 0.5, 0), material,
                 uv=True)
    kit.world_color((1.0, 1.0, 1.0), strength=1.0)
    kit.camera((0, 0, 2.5), (0, 0, 0), lens=24.0)

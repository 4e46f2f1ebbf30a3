# Regenerates the Blender reference images for the display-transform test:
#   /usr/bin/python3 make_references.py   (needs Blender 3.4 and python3-openimageio)
# It writes gradient.exr (64x4, 0..4 scene-linear, unequal channels, 0.18 at x = 3) and has
# Blender save it through its own colour management (image.save_render with the scene's view
# settings) as 8-bit PNGs, one per case below. These PNGs are what a Blender user sees.
import os
import subprocess
import sys

CASES = [
    # file stem, view, look, exposure, gamma
    ("standard", "Standard", "None", 0.0, 1.0),
    ("filmic", "Filmic", "None", 0.0, 1.0),
    ("filmic_log", "Filmic Log", "None", 0.0, 1.0),
    ("false_color", "False Color", "None", 0.0, 1.0),
    ("raw", "Raw", "None", 0.0, 1.0),
    ("filmic_medium_high_contrast", "Filmic", "Medium High Contrast", 0.0, 1.0),
    ("filmic_very_low_contrast", "Filmic", "Very Low Contrast", 0.0, 1.0),
    ("filmic_exposure1_gamma1.2", "Filmic", "None", 1.0, 1.2),
]

HERE = os.path.dirname(os.path.abspath(__file__))


def write_gradient():
    import numpy as np
    import OpenImageIO as oiio
    w, h = 64, 4
    a = np.zeros((h, w, 4), np.float32)
    for y in range(h):
        for x in range(w):
            v = 0.18 if x == 3 else 4.0 * x / (w - 1)
            a[y, x] = [v, v * (0.4 + 0.2 * y), v * (1.0 - 0.2 * y), 1.0]
    out = oiio.ImageOutput.create("exr")
    out.open(os.path.join(HERE, "gradient.exr"), oiio.ImageSpec(w, h, 4, oiio.FLOAT))
    out.write_image(a)
    out.close()


BLENDER_SCRIPT = """
import bpy
scene = bpy.context.scene
img = bpy.data.images.load({gradient!r})
scene.display_settings.display_device = "sRGB"
s = scene.render.image_settings
s.file_format, s.color_depth, s.color_mode = "PNG", "8", "RGB"
for stem, view, look, exposure, gamma in {cases!r}:
    v = scene.view_settings
    v.view_transform, v.look, v.exposure, v.gamma = view, look, exposure, gamma
    img.save_render({here!r} + "/" + stem + ".png", scene=scene)
"""

if __name__ == "__main__":
    write_gradient()
    script = BLENDER_SCRIPT.format(gradient=os.path.join(HERE, "gradient.exr"), cases=CASES, here=HERE)
    subprocess.run(["blender", "-b", "--factory-startup", "--python-expr", script], check=True)
    sys.exit(0)

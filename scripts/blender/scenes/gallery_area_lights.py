"""Gallery: Blender's area lights, which glTF cannot carry (VEACH_lights_blender carries them): a
warm square, a long cool rectangle, a disk and a pink ellipse hang tilted over a glossy dark floor
with a white sphere, a box and a pillar; each light's soft shadow and its reflection in the floor
show its shape."""
import scene_kit as kit

RESOLUTION = (320, 180)
SPP = 0  # gallery scenes have no Cycles reference


VEACH_ARGS = ["--env-color", "0.03,0.03,0.04"]


def build():
    floor = kit.principled("floor", (0.1, 0.1, 0.11), roughness=0.12)
    wall = kit.lambert("wall", (0.5, 0.5, 0.5))
    white = kit.lambert("white", (0.8, 0.8, 0.8))
    kit.quad("floor", (-8, -6, 0), (8, -6, 0), (8, 8, 0), (-8, 8, 0), floor)
    kit.quad("back", (-8, 2.5, 0), (8, 2.5, 0), (8, 2.5, 5), (-8, 2.5, 5), wall)
    kit.uv_sphere("sphere", (-1.1, 0.3, 0.55), 0.55, white)
    kit.box("box", (0.7, 0.5, 0.4), (0.8, 0.8, 0.8), 25.0,
            kit.principled("copper", (0.95, 0.6, 0.45), metallic=1.0, roughness=0.3))
    kit.box("pillar", (2.3, 1.2, 0.9), (0.35, 0.35, 1.8), 0.0, white)
    # Tilted towards the camera (which looks along +Y) so that the shapes show in the image and
    # in the floor; each one-sided light lights the objects below it in its own colour.
    kit.area_light("square", (-2.7, 0.6, 2.3), 90.0, rotation=(-30, 0, 0), color=(1.0, 0.45, 0.1),
                   shape='SQUARE', size=0.9)
    kit.area_light("rectangle", (-0.6, 1.0, 2.7), 110.0, rotation=(-25, 0, 0), color=(0.25, 0.5, 1.0),
                   shape='RECTANGLE', size=2.0, size_y=0.3)
    kit.area_light("disk", (1.2, 0.9, 2.4), 80.0, rotation=(-30, 0, 0), color=(1.0, 1.0, 0.95),
                   shape='DISK', size=0.9)
    kit.area_light("ellipse", (3.0, 0.3, 2.0), 70.0, rotation=(-35, 0, 20), color=(1.0, 0.25, 0.55),
                   shape='ELLIPSE', size=1.1, size_y=0.45)
    kit.world_color((0.03, 0.03, 0.04))
    kit.camera((0.0, -6.0, 1.3), (0.0, 0.8, 1.2), lens=30.0)

"""A diffuse room lit only by a Blender point, spot and sun light, all of radius 0 (hard
shadows): light units and the spot profile through the glTF round trip."""
import scene_kit as kit

RESOLUTION = (256, 192)
SPP = 4096


def build():
    white = kit.lambert("white", (0.7, 0.7, 0.7))
    red = kit.lambert("red", (0.6, 0.1, 0.1))
    kit.quad("floor", (-4, -4, 0), (4, -4, 0), (4, 4, 0), (-4, 4, 0), white)
    kit.quad("back", (-4, 2, 0), (4, 2, 0), (4, 2, 3), (-4, 2, 3), white)
    kit.box("cube", (-0.8, 0.5, 0.5), (1, 1, 1), 30.0, red)
    kit.box("pillar", (1.2, 0.8, 0.75), (0.4, 0.4, 1.5), 0.0, white)
    kit.point_light("point", (1.0, -0.5, 1.8), 150.0, color=(0.7, 1.0, 0.7))
    kit.spot_light("spot", (-2.0, -2.0, 3.0), 800.0, rotation=(40, 0, -35), color=(1.0, 0.9, 0.8),
                   size_degrees=35.0, blend=0.1)
    kit.sun_light("sun", 1.0, rotation=(30, 0, 60), color=(0.9, 0.9, 1.0))
    kit.camera((0.5, -6.0, 2.2), (0.2, 0.5, 0.8), lens=32.0)

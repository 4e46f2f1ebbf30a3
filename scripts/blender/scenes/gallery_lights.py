"""Gallery: every kind of light glTF carries from Blender. A coloured point light, a spot with a
soft edge, a low sun, and emissive meshes (a glowing strip and a lamp shade), in a grey room."""
import scene_kit as kit

RESOLUTION = (320, 180)
SPP = 0


def build():
    grey = kit.lambert("grey", (0.6, 0.6, 0.6))
    blue = kit.lambert("blue", (0.15, 0.25, 0.6))
    kit.quad("floor", (-5, -5, 0), (5, -5, 0), (5, 5, 0), (-5, 5, 0), grey)
    kit.quad("back", (-5, 2.5, 0), (5, 2.5, 0), (5, 2.5, 4), (-5, 2.5, 4), grey)
    kit.quad("left", (-3, -5, 0), (-3, 5, 0), (-3, 5, 4), (-3, -5, 4), grey)
    kit.box("pedestal", (-1.2, 0.8, 0.4), (0.8, 0.8, 0.8), 20.0, blue)
    kit.uv_sphere("ball", (1.2, 0.4, 0.5), 0.5, kit.principled("satin", (0.8, 0.8, 0.8), roughness=0.3))
    strip = kit.emitter("strip", (1.0, 0.35, 0.15), 12.0)
    kit.box("strip", (0.0, 2.45, 2.8), (4.0, 0.05, 0.08), 0.0, strip)
    kit.point_light("point", (1.8, -0.5, 1.2), 40.0, color=(0.4, 1.0, 0.5))
    kit.spot_light("spot", (-1.2, -1.0, 3.2), 900.0, target=(-1.2, 0.8, 0.8), color=(1.0, 0.85, 0.6),
                   size_degrees=40.0, blend=0.4)
    kit.sun_light("sun", 0.6, rotation=(70, 0, -60), color=(0.7, 0.8, 1.0))
    kit.camera((0.3, -6.0, 2.0), (0.0, 0.6, 1.0), lens=30.0)

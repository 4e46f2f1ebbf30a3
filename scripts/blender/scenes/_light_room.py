"""The room the single-light scenes share: a diffuse floor and back wall with a red cube and a
white pillar casting shadows, seen from the front; the light is placed by the scene module,
outside the camera's view."""
import scene_kit as kit

RESOLUTION = (96, 64)
SPP = 1024


def build_room():
    white = kit.lambert("white", (0.7, 0.7, 0.7))
    red = kit.lambert("red", (0.6, 0.1, 0.1))
    kit.quad("floor", (-4, -4, 0), (4, -4, 0), (4, 4, 0), (-4, 4, 0), white)
    kit.quad("back", (-4, 2, 0), (4, 2, 0), (4, 2, 3), (-4, 2, 3), white)
    kit.box("cube", (-0.8, 0.5, 0.5), (1, 1, 1), 30.0, red)
    kit.box("pillar", (1.2, 0.8, 0.75), (0.4, 0.4, 1.5), 0.0, white)
    kit.camera((0.5, -6.0, 2.2), (0.2, 0.5, 0.8), lens=32.0)

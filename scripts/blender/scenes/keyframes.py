"""The smallest animated scene: a ball keyed along a path over 24 frames, squashing through a
shape key as it lands, on a diffuse floor under a point light. Node transform and morph-weight
animation as Blender exports them; the template for animated scenes (frames, per-frame
references)."""
import scene_kit as kit

RESOLUTION = (128, 96)
SPP = 256
FRAMES = (1, 24)


def build():
    kit.frame_range(*FRAMES)
    floor = kit.lambert("floor", (0.7, 0.7, 0.7))
    orange = kit.lambert("orange", (0.8, 0.3, 0.05))
    kit.quad("floor", (-4, -4, 0), (4, -4, 0), (4, 4, 0), (-4, 4, 0), floor)
    ball = kit.uv_sphere("ball", (0, 0, 0), 0.4, orange, segments=32, rings=16)
    kit.keyframes(ball, "location", {1: (-1.5, 0, 1.6), 12: (0, 0, 0.4), 24: (1.5, 0, 1.6)})
    squash = kit.shape_key(ball, "squash", lambda k, co: (0.3 * co.x, 0.3 * co.y, -0.4 * co.z - 0.16))
    kit.keyframes(squash, "value", {1: 0.0, 10: 0.0, 12: 1.0, 14: 0.0})
    kit.point_light("point", (0.5, -1.5, 3.5), 300.0)
    kit.camera((0, -6.5, 1.8), (0, 0, 0.8), lens=35.0)

"""Gallery: an animated scene as Blender exports it, rendered at one frame with `--frame`: a ball
bounces across the floor (keyed location) and squashes as it lands (a shape key), a box spins
(keyed rotation) and a bar bends (a two-bone armature: a skin), under a warm key light and a
cool fill. 24 frames at 24 fps; the gallery shows frame 9, mid-motion."""
import math

import scene_kit as kit

RESOLUTION = (320, 180)
SPP = 0  # gallery scenes have no Cycles reference
FRAMES = (1, 24)
VEACH_ARGS = ["--env-color", "0.08,0.09,0.12"]


def build():
    kit.frame_range(*FRAMES)
    floor = kit.lambert("floor", (0.7, 0.68, 0.62))
    wall = kit.lambert("wall", (0.55, 0.58, 0.62))
    kit.quad("floor", (-6, -6, 0), (6, -6, 0), (6, 6, 0), (-6, 6, 0), floor)
    kit.quad("back", (-6, 2.5, 0), (6, 2.5, 0), (6, 2.5, 4), (-6, 2.5, 4), wall)

    ball = kit.uv_sphere("ball", (-2.4, 0.0, 0.4), 0.4, kit.principled("orange", (0.9, 0.35, 0.05), roughness=0.35),
                         segments=32, rings=16)
    # Two hops left to right: up at frames 5 and 17, on the floor at 1, 10 and 24.
    kit.keyframes(ball, "location", {1: (-2.6, 0.0, 0.4), 5: (-1.7, 0.0, 1.5), 10: (-0.8, 0.0, 0.4),
                                     17: (0.2, 0.0, 1.3), 24: (1.0, 0.0, 0.4)}, interpolation='BEZIER')
    squash = kit.shape_key(ball, "squash", lambda k, co: (0.3 * co.x, 0.3 * co.y, -0.5 * (co.z + 0.4)))
    kit.keyframes(squash, "value", {1: 0.8, 3: 0.0, 8: 0.0, 10: 0.9, 12: 0.0, 22: 0.0, 24: 0.8})

    box = kit.box("box", (2.2, 0.4, 0.45), (0.9, 0.9, 0.9), 0.0, kit.principled("teal", (0.05, 0.45, 0.45),
                                                                               roughness=0.25))
    kit.keyframes(box, "rotation_euler", {1: (0.0, 0.0, 0.0), 24: (0.0, 0.0, math.radians(180.0))})

    bar = kit.sliced_bar("bar", (0.6, 1.4, 0.0), 1.8, 0.15, 12, kit.lambert("purple", (0.35, 0.15, 0.6)))
    rig = kit.bone_chain("rig", bar, [(0.6, 1.4, 0.0), (0.6, 1.4, 0.9), (0.6, 1.4, 1.8)])
    kit.keyframes(rig.pose.bones["bone0"], "rotation_euler",
                  {1: (0.0, 0.0, 0.0), 12: (math.radians(-20.0), 0.0, 0.0), 24: (0.0, 0.0, 0.0)})
    kit.keyframes(rig.pose.bones["bone1"], "rotation_euler",
                  {1: (0.0, 0.0, 0.0), 12: (0.0, math.radians(70.0), 0.0), 24: (0.0, 0.0, 0.0)})

    kit.point_light("key", (-2.0, -2.5, 3.5), 900.0, color=(1.0, 0.88, 0.7), radius=0.3)
    kit.point_light("fill", (3.0, -3.0, 2.0), 250.0, color=(0.6, 0.75, 1.0), radius=0.5)
    kit.world_color((0.08, 0.09, 0.12))
    kit.camera((0.0, -7.0, 2.2), (0.0, 0.5, 0.8), lens=32.0)

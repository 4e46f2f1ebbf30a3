"""glTF animation as Blender's exporter writes it, for `veach render --frame N` against Cycles'
frame N: a red cube sliding and turning across the floor (node translation and rotation), a blue
bar bent by a two-bone armature (a skin: joints, inverse bind matrices, JOINTS_0/WEIGHTS_0) and a
green ball squashed by a shape key (a morph target and its animated weight), in a diffuse room
under one point light of radius 0 (KHR_lights_punctual, so nothing but the animation needs more
than the core spec). Camera and light stand still: what changes between frames is the animation.

Frame 1 is every channel's first key and the pose the file holds without animation (rest pose,
shape key 0, the cube at its start), so an importer that ignores animation renders frame 1 right
and frames 7 and 12 wrong. Keys are linear; rotations are resampled by the exporter per frame.
References at frames 1, 7 and 12 (24 fps; the exporter keys frame N at t = N / 24 s)."""
import math

import scene_kit as kit

RESOLUTION = (128, 96)
SPP = 1024
FRAMES = (1, 12)
REFERENCE_FRAMES = (1, 7, 12)


def build():
    kit.frame_range(*FRAMES)
    white = kit.lambert("white", (0.7, 0.7, 0.7))
    red = kit.lambert("red", (0.7, 0.12, 0.1))
    blue = kit.lambert("blue", (0.1, 0.25, 0.7))
    green = kit.lambert("green", (0.2, 0.6, 0.15))
    kit.quad("floor", (-4, -4, 0), (4, -4, 0), (4, 4, 0), (-4, 4, 0), white)
    kit.quad("back", (-4, 2, 0), (4, 2, 0), (4, 2, 3), (-4, 2, 3), white)

    cube = kit.box("cube", (-2.0, -0.6, 0.35), (0.7, 0.7, 0.7), 0.0, red)
    kit.keyframes(cube, "location", {1: (-2.0, -0.6, 0.35), 12: (-0.3, -0.9, 0.35)})
    kit.keyframes(cube, "rotation_euler", {1: (0.0, 0.0, 0.0), 12: (0.0, 0.0, math.radians(60.0))})

    # A bar 1.8 m tall in 12 slices, so that it bends smoothly at the joint.
    bar = kit.sliced_bar("bar", (0.9, 0.6, 0.0), 1.8, 0.17, 12, blue)
    rig = kit.bone_chain("rig", bar, [(0.9, 0.6, 0.0), (0.9, 0.6, 0.9), (0.9, 0.6, 1.8)])
    kit.keyframes(rig.pose.bones["bone0"], "rotation_euler",
                  {1: (0.0, 0.0, 0.0), 12: (math.radians(-15.0), 0.0, 0.0)})
    kit.keyframes(rig.pose.bones["bone1"], "rotation_euler",
                  {1: (0.0, 0.0, 0.0), 12: (0.0, 0.0, math.radians(-75.0))})

    ball = kit.uv_sphere("ball", (2.0, -0.2, 0.45), 0.45, green, segments=32, rings=16)
    # Squashed to a wide disc resting on the floor: z shrinks to 40% about the bottom, x and y grow.
    squash = kit.shape_key(ball, "squash", lambda k, co: (0.35 * co.x, 0.35 * co.y, -0.6 * (co.z + 0.45)))
    kit.keyframes(squash, "value", {1: 0.0, 12: 1.0})

    kit.point_light("point", (-0.5, -2.0, 3.2), 500.0)
    kit.camera((0.2, -6.5, 2.3), (0.2, 0.2, 0.7), lens=34.0)

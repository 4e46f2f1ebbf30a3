"""Animation as the depsgraph evaluates it, for the Blender add-on's frame-by-frame renders: a
ball keyed along a path that squashes through a shape key as it lands, a bar bent by a
two-bone armature (posed, never its rest shape), and a cube rounded by a Subdivision Surface
modifier, on a diffuse floor under a moving point light of radius 0, seen by a moving camera.
Frames 1 to 12; each looks different from the next. The references are small (96 x 64) because the add-on's test renders every frame."""
import math

import scene_kit as kit

RESOLUTION = (96, 64)
BLEND_SAMPLES = 64
SPP = 1024
FRAMES = (1, 12)


def build():
    kit.frame_range(*FRAMES)
    floor = kit.lambert("floor", (0.7, 0.7, 0.7))
    orange = kit.lambert("orange", (0.8, 0.3, 0.05))
    blue = kit.lambert("blue", (0.1, 0.25, 0.7))
    green = kit.lambert("green", (0.2, 0.6, 0.15))
    kit.quad("floor", (-4, -3, 0), (4, -3, 0), (4, 4, 0), (-4, 4, 0), floor)
    ball = kit.uv_sphere("ball", (0, 0, 0), 0.4, orange, segments=32, rings=16)
    kit.keyframes(ball, "location", {1: (-1.6, 0, 1.5), 7: (-0.6, 0, 0.4), 12: (0.2, 0, 1.2)})
    squash = kit.shape_key(ball, "squash", lambda k, co: (0.3 * co.x, 0.3 * co.y, -0.4 * co.z - 0.16))
    kit.keyframes(squash, "value", {1: 0.0, 5: 0.0, 7: 1.0, 9: 0.0})
    # A bar 2 m tall, cut into 16 slices so that it bends smoothly at the joint.
    slices = 16
    vertices, faces = [], []
    for k in range(slices + 1):
        z = 2.0 * k / slices
        vertices += [(x, y, z) for x, y in ((-0.15, -0.15), (0.15, -0.15), (0.15, 0.15), (-0.15, 0.15))]
    for k in range(slices):
        a, b = 4 * k, 4 * (k + 1)
        faces += [(a + i, a + (i + 1) % 4, b + (i + 1) % 4, b + i) for i in range(4)]
    faces += [(3, 2, 1, 0), (b, b + 1, b + 2, b + 3)]
    bar = kit.mesh("bar", vertices, faces, blue)
    bar.location = (1.4, 0.5, 0.0)
    rig = kit.bone_chain("rig", bar, [(1.4, 0.5, 0.0), (1.4, 0.5, 1.0), (1.4, 0.5, 2.0)])
    kit.keyframes(rig.pose.bones["bone1"], "rotation_euler",
                  {1: (0.0, 0.0, 0.0), 12: (0.0, 0.0, math.radians(-75.0))})
    kit.keyframes(rig.pose.bones["bone0"], "rotation_euler",
                  {1: (math.radians(25.0), 0.0, 0.0), 12: (math.radians(-10.0), 0.0, 0.0)})
    cube = kit.box("rounded", (-0.3, 1.6, 0.5), (1.0, 1.0, 1.0), 20.0, green)
    cube.modifiers.new("Subdivision", 'SUBSURF').levels = 2
    cube.modifiers["Subdivision"].render_levels = 2
    light = kit.point_light("point", (0.5, -1.5, 3.5), 300.0)
    kit.keyframes(light, "location", {1: (-1.5, -1.5, 3.5), 12: (1.5, -1.0, 3.2)})
    camera = kit.camera((0, -6.5, 2.2), (0, 0.5, 0.8), lens=30.0)
    kit.keyframes(camera, "location", {1: (-0.3, -6.5, 2.2), 12: (0.3, -6.2, 2.4)})

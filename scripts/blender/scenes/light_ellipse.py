"""The shared room (_light_room) lit by a Blender ellipse area light (1.6 x 0.6 m, 400 W) alone:
the light type through VEACH_lights_blender against Cycles."""
import scene_kit as kit
from scenes._light_room import RESOLUTION, SPP, build_room  # noqa: F401 (the scene's settings)


def build():
    build_room()
    kit.area_light("ellipse", (0.3, -1.0, 3.4), 400.0, rotation=(20, 0, -30), shape='ELLIPSE', size=1.6, size_y=0.6)

"""The shared room (_light_room) lit by a Blender disk area light (1.2 m, 400 W) alone: the light
type through VEACH_lights_blender against Cycles."""
import scene_kit as kit
from scenes._light_room import RESOLUTION, SPP, build_room  # noqa: F401 (the scene's settings)


def build():
    build_room()
    kit.area_light("disk", (0.3, -1.0, 3.4), 400.0, rotation=(20, 0, 10), shape='DISK', size=1.2)

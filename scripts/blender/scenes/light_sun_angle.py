"""The shared room (_light_room) lit by a Blender sun with a 12 degree angle (soft shadows),
strength 3 W/m^2 alone: the light type through VEACH_lights_blender against Cycles."""
import scene_kit as kit
from scenes._light_room import RESOLUTION, SPP, build_room  # noqa: F401 (the scene's settings)


def build():
    build_room()
    kit.sun_light("sun", 3.0, rotation=(35, 0, 50), angle_degrees=12.0)

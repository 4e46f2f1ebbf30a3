"""The shared room (_light_room) lit by a Blender spot light with a 0.15 m radius, 60 degree cone,
blend 0.2 alone: the light type through VEACH_lights_blender against Cycles."""
import scene_kit as kit
from scenes._light_room import RESOLUTION, SPP, build_room  # noqa: F401 (the scene's settings)


def build():
    build_room()
    kit.spot_light("spot", (-1.5, -2.0, 3.2), 1500.0, rotation=(40, 0, -35), size_degrees=60.0, blend=0.2,
                   radius=0.15)

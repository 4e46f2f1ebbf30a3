"""The shared room (_light_room) lit by a Blender point light with a 0.15 m radius (soft shadows;
small beside its distance, where Cycles 3.4's disc and Veach's sphere agree) alone: the light
type through VEACH_lights_blender against Cycles."""
import scene_kit as kit
from scenes._light_room import RESOLUTION, SPP, build_room  # noqa: F401 (the scene's settings)


def build():
    build_room()
    kit.point_light("point", (0.6, -0.8, 3.3), 300.0, radius=0.15)

"""Rough copper and near-smooth glass on a diffuse floor under one small, bright area light:
caustics, and specular-diffuse-specular paths that path tracing finds slowly."""
import scene_kit as kit

RESOLUTION = (256, 192)
SPP = 8192


def build():
    white = kit.lambert("white", (0.7, 0.7, 0.7))
    copper = kit.principled("copper", (0.95, 0.64, 0.54), metallic=1.0, roughness=0.35, specular=0.5)
    glass = kit.principled("glass", (0.9, 1.0, 0.95), roughness=0.05, specular=0.5, transmission=1.0, ior=1.33)
    light = kit.emitter("light", (1, 1, 1), 400.0)
    kit.quad("floor", (-5, -5, 0), (5, -5, 0), (5, 5, 0), (-5, 5, 0), white)
    kit.quad("back", (-5, 3, 0), (5, 3, 0), (5, 3, 4), (-5, 3, 4), white)
    kit.uv_sphere("copper_sphere", (-0.8, 0.5, 0.6), 0.6, copper, segments=64, rings=32)
    kit.uv_sphere("glass_sphere", (0.8, 0.2, 0.6), 0.6, glass, segments=64, rings=32)
    kit.quad("light", (-0.15, -0.15, 3.0), (-0.15, 0.15, 3.0), (0.15, 0.15, 3.0), (0.15, -0.15, 3.0), light)
    kit.camera((0.0, -5.0, 2.0), (0.0, 0.3, 0.5), lens=40.0)

"""Gallery: the glTF metallic-roughness material and its extensions side by side. Left to right:
a rough red dielectric, polished gold, a clearcoated blue paint, a velvet (sheen) and clear glass,
on a light floor under a uniform sky and one sun."""
import scene_kit as kit

RESOLUTION = (320, 180)
SPP = 0  # gallery scenes have no Cycles reference
VEACH_ARGS = ["--env-color", "0.3,0.38,0.5"]


def build():
    floor = kit.lambert("floor", (0.75, 0.75, 0.72))
    kit.quad("floor", (-8, -6, 0), (8, -6, 0), (8, 8, 0), (-8, 8, 0), floor)
    materials = [
        kit.principled("red_plastic", (0.7, 0.08, 0.06), roughness=0.45),
        kit.principled("gold", (1.0, 0.77, 0.34), metallic=1.0, roughness=0.12),
        kit.principled("blue_paint", (0.05, 0.12, 0.5), roughness=0.6, clearcoat=1.0, clearcoat_roughness=0.03),
        kit.principled("velvet", (0.25, 0.05, 0.2), roughness=0.9, sheen_color=(0.9, 0.6, 0.85), sheen_roughness=0.4),
        kit.principled("glass", (1.0, 1.0, 1.0), roughness=0.0, transmission=1.0, ior=1.5),
    ]
    for k, material in enumerate(materials):
        kit.uv_sphere(material.name, (-2.4 + 1.2 * k, 0.0, 0.5), 0.5, material, segments=48, rings=24)
    kit.sun_light("sun", 1.2, rotation=(40, 0, 35), color=(1.0, 0.95, 0.88), angle_degrees=0.0)
    kit.world_color((0.3, 0.38, 0.5))
    kit.camera((0.0, -7.5, 1.9), (0.0, 0.0, 0.4), lens=42.0)

"""Gallery: image textures. A floor of tiles with a base-colour image, a normal map of bevelled
grooves and a roughness map (glossy tiles, rough grout), and a checker-textured cube, under a
spot light and a dim sky."""
import math

import scene_kit as kit

RESOLUTION = (320, 180)
SPP = 0
VEACH_ARGS = ["--env-color", "0.05,0.06,0.08"]

TILES = 4  # tiles per texture repeat
SIZE = 256


def _tile_coordinates(i, j):
    """Position inside the tile (0..1) of texel (i, j)."""
    u = (i + 0.5) / SIZE * TILES
    v = (j + 0.5) / SIZE * TILES
    return u - math.floor(u), v - math.floor(v), int(u), int(v)


def _groove(t):
    """Height profile across a tile: flat top, bevelled 8% edges."""
    edge = 0.08
    return min(1.0, t / edge, (1.0 - t) / edge)


def base_color(i, j):
    x, y, a, b = _tile_coordinates(i, j)
    if min(x, 1 - x, y, 1 - y) < 0.03:
        return (0.55, 0.55, 0.52)  # grout (encoded sRGB)
    return (0.75, 0.42, 0.28) if (a + b) % 2 else (0.88, 0.84, 0.76)


def normal(i, j):
    x, y, _, _ = _tile_coordinates(i, j)
    step = 1.0 / SIZE * TILES
    dx = (_groove(min(1.0, x + step)) - _groove(max(0.0, x - step))) / (2 * step) * 0.05
    dy = (_groove(min(1.0, y + step)) - _groove(max(0.0, y - step))) / (2 * step) * 0.05
    nx, ny, nz = -dx, -dy, 1.0
    norm = math.sqrt(nx * nx + ny * ny + nz * nz)
    return (0.5 + 0.5 * nx / norm, 0.5 + 0.5 * ny / norm, 0.5 + 0.5 * nz / norm)


def roughness(i, j):
    x, y, _, _ = _tile_coordinates(i, j)
    grout = min(x, 1 - x, y, 1 - y) < 0.03
    return (0.0, 0.9 if grout else 0.18, 0.0)  # glTF reads roughness from green


def checker(i, j):
    return (0.9, 0.9, 0.9) if (i // 4 + j // 4) % 2 else (0.08, 0.08, 0.1)


def build():
    colour = kit.image_from_function("tiles_color", SIZE, SIZE, base_color)
    normals = kit.image_from_function("tiles_normal", SIZE, SIZE, normal, colorspace='Non-Color')
    rough = kit.image_from_function("tiles_roughness", SIZE, SIZE, roughness, colorspace='Non-Color')
    tiles = kit.principled("tiles", (1, 1, 1), roughness=1.0, base_color_image=colour, normal_image=normals,
                           roughness_image=rough)
    floor = kit.grid("floor", 6.0, 1, tiles)
    floor.data.uv_layers[0].data.foreach_set("uv", [c * 2.0 for loop in floor.data.uv_layers[0].data
                                                    for c in loop.uv])
    cube_material = kit.principled("checker", (1, 1, 1), roughness=0.5,
                                   base_color_image=kit.image_from_function("checker", 64, 64, checker))
    kit.box("cube", (0.7, 0.6, 0.45), (0.9, 0.9, 0.9), 25.0, cube_material, uv=True)
    kit.spot_light("spot", (-2.0, -1.5, 3.5), 1500.0, target=(0.0, 0.3, 0.0), size_degrees=70.0, blend=0.3)
    kit.world_color((0.05, 0.06, 0.08))
    kit.camera((-0.6, -4.2, 2.0), (0.2, 0.4, 0.2), lens=32.0)

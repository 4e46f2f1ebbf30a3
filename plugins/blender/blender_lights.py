"""Blender's light settings that glTF's KHR_lights_punctual cannot carry, written into an exported
glTF as the light-level extension VEACH_lights_blender (README, "Blender's lights"):

  area lights (square, rectangle, disk, ellipse; size; power; spread), which Blender 3.4's
  exporter drops (it writes the object as a plain node), become a KHR light on that node with
      {"shape": "square|rectangle|disk|ellipse", "size": [x, y], "power": W, "spread": radians}
  point and spot lights get {"shape": "point|spot", "radius": r, "power": W}
  sun lights get {"shape": "sun", "angle": radians}

The add-on's own exporter (gltf_export.py) puts light_extension() on each light entry and folds the
object's scale into an area light's size (its nodes drop scale); write_blender_lights() rewrites a
file Blender's exporter wrote (scripts/blender/make_scene.py). The quantities are Blender's own;
Veach's importer converts them (Cycles' units). Blender's exporter
places a light's node so that its local frame is the Blender light's (-Z the emitting direction,
X and Y the area light's size axes), for area lights too, which is what the extension relies on.
Needs no bpy: it reads the light objects it is given (anything with .name, .type == 'LIGHT' and
.data with Blender's light properties).
"""
import json
import math
import struct

EXTENSION = "VEACH_lights_blender"
PUNCTUAL = "KHR_lights_punctual"
WATTS_TO_LUMENS = 683.0  # what Blender's exporter multiplies by; Veach's importer divides


def light_extension(light):
    """The extension for one Blender light datablock, or None when glTF says it all."""
    kind = light.type
    if kind == 'AREA':
        shape = light.shape.lower()
        size_y = light.size_y if shape in ("rectangle", "ellipse") else light.size
        ext = {"shape": shape, "size": [float(light.size), float(size_y)], "power": float(light.energy)}
        spread = getattr(light, "spread", math.pi)
        ext["spread"] = float(spread)
        return ext
    if kind in ('POINT', 'SPOT'):
        radius = float(getattr(light, "shadow_soft_size", 0.0))
        if radius <= 0.0:
            return None
        return {"shape": kind.lower(), "radius": radius, "power": float(light.energy)}
    if kind == 'SUN':
        angle = float(getattr(light, "angle", 0.0))
        if angle <= 0.0:
            return None
        return {"shape": "sun", "angle": angle}
    return None


def add_blender_lights(gltf, objects):
    """Adds the extension to the glTF JSON `gltf` (a dict) for the light objects among `objects`.
    Returns one line per setting that Veach renders differently from Cycles (for the caller's
    warnings)."""
    notes = []
    nodes = gltf.get("nodes", [])
    node_of = {}
    for index, node in enumerate(nodes):
        node_of.setdefault(node.get("name"), index)
    lights = gltf.setdefault("extensions", {}).setdefault(PUNCTUAL, {}).setdefault("lights", [])
    light_of = {}
    for index, entry in enumerate(lights):
        light_of.setdefault(entry.get("name"), index)
    added = {}
    used = False
    for obj in objects:
        if getattr(obj, "type", None) != 'LIGHT' or obj.name not in node_of:
            continue
        light = obj.data
        ext = light_extension(light)
        if ext is None:
            continue
        node = nodes[node_of[obj.name]]
        if light.type == 'AREA':
            if abs(ext["spread"] - math.pi) > 1e-3:
                notes.append("area light '%s': spread %.0f degrees is rendered as 180" %
                             (light.name, math.degrees(ext["spread"])))
            index = added.get(light.name)
            if index is None:
                # A point light of the same power is the fallback for readers without the extension.
                color = [float(c) for c in light.color]
                lights.append({"name": light.name, "type": "point", "color": color,
                               "intensity": light.energy / (4.0 * math.pi) * WATTS_TO_LUMENS,
                               "extensions": {EXTENSION: ext}})
                index = added[light.name] = len(lights) - 1
            node.setdefault("extensions", {})[PUNCTUAL] = {"light": index}
            used = True
        else:
            ref = node.get("extensions", {}).get(PUNCTUAL)
            if ref is None or not isinstance(ref.get("light"), int) or ref["light"] >= len(lights):
                continue
            lights[ref["light"]].setdefault("extensions", {})[EXTENSION] = ext
            used = True
    if not lights:
        del gltf["extensions"][PUNCTUAL]
        if not gltf["extensions"]:
            del gltf["extensions"]
    if used:
        extensions_used = gltf.setdefault("extensionsUsed", [])
        for name in (PUNCTUAL, EXTENSION):
            if name not in extensions_used:
                extensions_used.append(name)
    return notes


def _read_glb(data):
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    if magic != b"glTF" or version != 2:
        raise ValueError("not a binary glTF 2.0 file")
    json_length, json_type = struct.unpack_from("<II", data, 12)
    if json_type != 0x4E4F534A:
        raise ValueError("binary glTF without a JSON chunk first")
    gltf = json.loads(data[20:20 + json_length].decode("utf-8"))
    return gltf, data[20 + json_length:length]


def _write_glb(gltf, rest):
    text = json.dumps(gltf, separators=(",", ":")).encode("utf-8")
    text += b" " * (-len(text) % 4)
    header = struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(text) + len(rest))
    return header + struct.pack("<II", len(text), 0x4E4F534A) + text + rest


def write_blender_lights(path, objects):
    """Rewrites the exported .gltf or .glb at `path` with the extension. Returns add_blender_lights'
    notes."""
    with open(path, "rb") as f:
        data = f.read()
    binary = data[:4] == b"glTF"
    if binary:
        gltf, rest = _read_glb(data)
    else:
        gltf = json.loads(data.decode("utf-8"))
    notes = add_blender_lights(gltf, objects)
    out = _write_glb(gltf, rest) if binary else json.dumps(gltf, indent=1).encode("utf-8")
    with open(path, "wb") as f:
        f.write(out)
    return notes

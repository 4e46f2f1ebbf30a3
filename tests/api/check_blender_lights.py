#!/usr/bin/python3
"""plugins/blender/blender_lights.py without Blender: the extension it writes for each Blender
light kind (what the importer reads, README "Blender's lights"), area lights given a KHR light on
their node, nothing written for lights glTF already describes, and a .glb rewritten whole.
Exit 0 pass, 1 fail."""
import json
import math
import os
import struct
import sys
import tempfile
from types import SimpleNamespace as NS

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "plugins", "blender"))
import blender_lights  # noqa: E402

failures = []


def check(condition, what):
    if not condition:
        failures.append(what)


def light(name, kind, **props):
    data = NS(name=name + "_data", type=kind, energy=props.pop("energy", 10.0), color=(1.0, 0.5, 0.25), **props)
    return NS(name=name, type='LIGHT', data=data)


objects = [
    light("area", 'AREA', shape='RECTANGLE', size=2.0, size_y=0.5, spread=math.radians(90), energy=100.0),
    light("bulb", 'POINT', shadow_soft_size=0.1),
    light("hard", 'POINT', shadow_soft_size=0.0),
    light("sun", 'SUN', angle=0.1, energy=3.0),
    NS(name="mesh", type='MESH', data=None),
]


def exported():
    return {
        "asset": {"version": "2.0"},
        "nodes": [{"name": "area"}, {"name": "bulb", "extensions": {"KHR_lights_punctual": {"light": 0}}},
                  {"name": "hard", "extensions": {"KHR_lights_punctual": {"light": 1}}},
                  {"name": "sun", "extensions": {"KHR_lights_punctual": {"light": 2}}}, {"name": "mesh"}],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"name": "bulb_data", "type": "point"}, {"name": "hard_data", "type": "point"},
            {"name": "sun_data", "type": "directional"}]}},
    }


gltf = exported()
notes = blender_lights.add_blender_lights(gltf, objects)
lights = gltf["extensions"]["KHR_lights_punctual"]["lights"]
ext = "VEACH_lights_blender"
check(lights[0]["extensions"][ext] == {"shape": "point", "radius": 0.1, "power": 10.0}, "point radius: %s" % lights[0])
check("extensions" not in lights[1], "a point of radius 0 needs nothing: %s" % lights[1])
check(lights[2]["extensions"][ext] == {"shape": "sun", "angle": 0.1}, "sun angle: %s" % lights[2])
check(len(lights) == 4, "one light added for the area light, got %d" % len(lights))
area_ref = gltf["nodes"][0].get("extensions", {}).get("KHR_lights_punctual", {}).get("light")
check(area_ref == 3, "the area light's node refers to its new light: %s" % gltf["nodes"][0])
if len(lights) == 4:
    a = lights[3]["extensions"][ext]
    check(a["shape"] == "rectangle" and a["size"] == [2.0, 0.5] and a["power"] == 100.0, "area: %s" % a)
    check(lights[3]["type"] == "point" and abs(lights[3]["intensity"] - 100 / (4 * math.pi) * 683) < 1e-6,
          "the fallback is a point light of the same power: %s" % lights[3])
check(ext in gltf.get("extensionsUsed", []) and ext not in gltf.get("extensionsRequired", []),
      "listed as used, never required")
check(len(notes) == 1 and "spread 90" in notes[0], "the spread is reported: %s" % notes)

# A .glb: the JSON chunk rewritten, the binary chunk kept, lengths consistent.
with tempfile.TemporaryDirectory() as tmp:
    path = os.path.join(tmp, "scene.glb")
    text = json.dumps(exported()).encode()
    text += b" " * (-len(text) % 4)
    binary = b"\x01\x02\x03\x04"
    chunk_bin = struct.pack("<II", len(binary), 0x004E4942) + binary
    with open(path, "wb") as f:
        f.write(struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(text) + len(chunk_bin)))
        f.write(struct.pack("<II", len(text), 0x4E4F534A) + text + chunk_bin)
    blender_lights.write_blender_lights(path, objects)
    data = open(path, "rb").read()
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    json_length, _ = struct.unpack_from("<II", data, 12)
    check(magic == b"glTF" and length == len(data) and json_length % 4 == 0, "glb header")
    check(data.endswith(chunk_bin), "the binary chunk is kept")
    rewritten = json.loads(data[20:20 + json_length])
    check(len(rewritten["extensions"]["KHR_lights_punctual"]["lights"]) == 4, "glb JSON rewritten")

for f in failures:
    print("FAIL: " + f)
print("blender_lights: %s" % ("ok" if not failures else "%d failures" % len(failures)))
sys.exit(1 if failures else 0)

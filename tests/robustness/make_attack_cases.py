#!/usr/bin/python3
"""Writes the hostile inputs of the attack suite into a folder (the build folder: nothing large is
ever committed) and a manifest.json naming, for each case, the arguments to `veach render` and
the contract it must keep:

  expect "refused": exit 2 (or `exit` when given), exactly one stderr line, containing `message`
                    when given, no image written;
  expect "rendered": exit 0, an image whose pixels are finite and >= 0, no non-finite sample
                    dropped unless `nonfinite_ok`; `warning`, when given, appears on stderr;
                    with `lit`, the image is not black and no stand-in light was added.

Every case also runs under an address-space limit (`memory_mb`, default 2048): a budget must
refuse before the allocation it covers, never after. Cases are named after what they check.

Usage: make_attack_cases.py OUTDIR [--full-size]  (--full-size adds the multi-gigabyte originals)
"""
import base64
import json
import os
import pathlib
import stat
import struct
import sys
import zlib

CASES = []


def case(name, files, expect, args=(), message=None, warning=None, exit_code=None, memory_mb=2048,
         nonfinite_ok=False, input_name=None, limit_is_the_point=False, lit=False):
    """`limit_is_the_point`: the contract is about what happens under `memory_mb` (a budget
    refusing for lack of memory), so a run without limits (the sanitizer build) leaves it out.
    `lit`: the scene's own light lights the image (not black, no stand-in light added)."""
    CASES.append({"name": name, "files": files, "expect": expect, "args": list(args), "message": message,
                  "warning": warning, "exit": exit_code, "memory_mb": memory_mb, "nonfinite_ok": nonfinite_ok,
                  "input": input_name, "limit_is_the_point": limit_is_the_point, "lit": lit})


def f32(values):
    return struct.pack(f"<{len(values)}f", *values)


def data_uri(raw):
    return "data:application/octet-stream;base64," + base64.b64encode(raw).decode()


def triangle_gltf(scale=1.0, offset=(0.0, 0.0, -2.0), camera=None, camera_node=None, material=None, extra=None,
                  lights=None, buffer_uri=None):
    """One triangle (and optionally a camera node, a material, punctual lights) as a glTF dict."""
    s = scale
    positions = f32([-s, -s, 0, s, -s, 0, 0, s, 0])
    indices = struct.pack("<3H", 0, 1, 2) + b"\0\0"
    raw = positions + indices
    g = {
        "asset": {"version": "2.0", "generator": "veach attack suite"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "tri", "mesh": 0, "translation": list(offset)}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [-s, -s, 0],
             "max": [s, s, 0]},
            {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"},
        ],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
        "buffers": [{"byteLength": len(raw), "uri": buffer_uri or data_uri(raw)}],
    }
    # Emissive by default: a scene without light would add a warning line to every case.
    g["materials"] = [material if material is not None else {"emissiveFactor": [1, 1, 1]}]
    g["meshes"][0]["primitives"][0]["material"] = 0
    if camera is not None:
        g["cameras"] = [camera]
        node = {"name": "cam", "camera": 0}
        node.update(camera_node or {})
        g["nodes"].append(node)
        g["scenes"][0]["nodes"].append(len(g["nodes"]) - 1)
    if lights is not None:
        g.setdefault("extensionsUsed", []).append("KHR_lights_punctual")
        g["extensions"] = {"KHR_lights_punctual": {"lights": [l for l, _ in lights]}}
        for i, (_, node) in enumerate(lights):
            n = {"name": f"light{i}", "extensions": {"KHR_lights_punctual": {"light": i}}}
            n.update(node)
            g["nodes"].append(n)
            g["scenes"][0]["nodes"].append(len(g["nodes"]) - 1)
    if extra:
        extra(g)
    return g


PERSPECTIVE = {"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01}}
BAD_CAMERA = "camera"  # every refused camera names itself in the message


def camera_cases():
    for name, node in [
        ("camera_scale_zero_is_refused", {"scale": [0, 0, 0]}),
        ("camera_scale_flat_is_refused", {"scale": [1, 0, 1]}),
        ("camera_translation_1e38_is_refused", {"translation": [1e38, 0, 0]}),
        # up parallel to forward: columns 1 and 2 of the matrix equal
        ("camera_up_parallel_to_forward_is_refused",
         {"matrix": [1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 1]}),
    ]:
        case(name, {"scene.gltf": triangle_gltf(camera=PERSPECTIVE, camera_node=node)}, "refused", message=BAD_CAMERA)
    # A uniform scale does not change what a camera sees: 1e-25 and 1e25 render like 1.
    for name, k in [("camera_scale_tiny_uniform_renders", 1e-25), ("camera_scale_huge_uniform_renders", 1e25)]:
        case(name, {"scene.gltf": triangle_gltf(camera=PERSPECTIVE, camera_node={"scale": [k, k, k]})}, "rendered")
    for name, mag in [("camera_ortho_mag_1e39_is_refused", 1e39), ("camera_ortho_mag_3e38_is_refused", 3e38)]:
        cam = {"type": "orthographic", "orthographic": {"xmag": mag, "ymag": mag, "znear": 0.01, "zfar": 100}}
        case(name, {"scene.gltf": triangle_gltf(camera=cam)}, "refused", message=BAD_CAMERA)
    # No camera and one triangle 1e19 away: the default camera would stand 1e19 from the origin;
    # the scene is moved to the origin first (rebasing), so it renders.
    case("far_triangle_without_camera_renders", {"scene.gltf": triangle_gltf(offset=(1e19, 0, 0))}, "rendered")
    # Geometry that still reaches past 1e18 once centred cannot be ray traced: refused.
    case("geometry_reaching_1e30_is_refused", {"scene.gltf": triangle_gltf(scale=1e30)}, "refused",
         message="1e18")
    # A light far past the limit: what its rays would need is dropped and counted, never an abort.
    far_light = [({"type": "point", "intensity": 1e30}, {"translation": [1e30, 0, 0]})]
    for integrator in ("pt", "bdpt", "lt"):
        case(f"point_light_at_1e30_renders_{integrator}", {"scene.gltf": triangle_gltf(lights=far_light)}, "rendered",
             args=["--integrator", integrator], nonfinite_ok=True)
    case("far_tiny_triangle_without_camera_renders",
         {"scene.gltf": triangle_gltf(scale=1e-3, offset=(3e37, 3e37, 3e37))}, "rendered")


def triangle_bin():
    return f32([-1, -1, 0, 1, -1, 0, 0, 1, 0]) + struct.pack("<3H", 0, 1, 2) + b"\0\0"


def symlink_to(target):
    def make(p):
        if p.is_symlink() or p.exists():
            p.unlink()
        os.symlink(target, p)
    return make


def fifo(p):
    if p.exists():
        p.unlink()
    os.mkfifo(p)


def directory(p):
    p.mkdir(exist_ok=True)


def confinement_cases():
    """URIs and inputs that must not be read: outside the folder through a symlink, FIFOs,
    devices, directories. Each is refused with exit 2 before anything blocks or spins."""
    external = triangle_gltf(buffer_uri="tri.bin")
    # The real file lives beside the case folder; the link inside the folder points at it.
    case("buffer_symlink_outside_folder_is_refused",
         {"../outside_buffer/tri.bin": triangle_bin(), "scene.gltf": external,
          "tri.bin": symlink_to("../outside_buffer/tri.bin")}, "refused", message="outside")
    case("buffer_symlink_outside_folder_allowed_renders",
         {"../outside_buffer2/tri.bin": triangle_bin(), "scene.gltf": external,
          "tri.bin": symlink_to("../outside_buffer2/tri.bin")}, "rendered", args=["--allow-external-files"])
    case("buffer_symlink_inside_folder_renders",
         {"data/real.bin": triangle_bin(), "scene.gltf": external, "tri.bin": symlink_to("data/real.bin")}, "rendered")
    case("buffer_fifo_is_refused", {"scene.gltf": external, "tri.bin": fifo}, "refused", message="regular file")
    case("buffer_directory_is_refused", {"scene.gltf": external, "tri.bin": directory}, "refused")
    case("buffer_dev_zero_is_refused", {"scene.gltf": triangle_gltf(buffer_uri="/dev/zero")}, "refused",
         args=["--allow-external-files"], message="regular file")
    case("input_fifo_is_refused", {"scene.gltf": fifo}, "refused", message="regular file")
    case("input_directory_is_refused", {"scene.gltf": directory}, "refused", message="directory")
    case("input_dev_zero_is_refused", {"scene.gltf": symlink_to("/dev/zero")}, "refused", message="regular file")
    plain = triangle_gltf()
    case("env_dev_zero_is_refused", {"scene.gltf": plain}, "refused", args=["--env", "/dev/zero"],
         message="regular file")
    case("env_fifo_is_refused", {"scene.gltf": plain, "env.hdr": fifo}, "refused", args=["--env", "{folder}/env.hdr"],
         message="regular file")
    case("env_directory_is_refused", {"scene.gltf": plain, "env.hdr": directory}, "refused",
         args=["--env", "{folder}/env.hdr"])
    # A texture behind a symlink leading out of the folder (the PNG itself is valid).
    png = png_bytes(4, 4)
    textured = triangle_gltf(material={"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}},
                                       "emissiveFactor": [1, 1, 1]},
                             extra=lambda g: g.update({"images": [{"uri": "tex.png"}], "textures": [{"source": 0}]}))
    case("texture_symlink_outside_folder_is_refused",
         {"../outside_texture/tex.png": png, "scene.gltf": textured, "tex.png": symlink_to("../outside_texture/tex.png")},
         "refused", message="outside")
    case("texture_fifo_is_refused", {"scene.gltf": textured, "tex.png": fifo}, "refused", message="regular file")
    case("texture_directory_is_refused", {"scene.gltf": textured, "tex.png": directory}, "refused", message="directory")
    device_textured = textured_triangle("/dev/zero")
    case("texture_dev_zero_is_refused", {"scene.gltf": device_textured}, "refused", args=["--allow-external-files"],
         message="regular file")


def silent_wrong_image_cases():
    """Inputs that used to render a wrong image with exit 0 and no word said."""
    lit = [({"type": "point", "intensity": 50}, {"translation": [0, 0, 0]})]
    for name, material, warning in [
        ("base_color_1e30_is_clamped", {"pbrMetallicRoughness": {"baseColorFactor": [1e30, 1e30, 1e30, 1]}},
         "baseColorFactor"),
        ("base_color_negative_is_clamped", {"pbrMetallicRoughness": {"baseColorFactor": [-1, -2, 0.5, 1]}},
         "baseColorFactor"),
        ("emissive_1e39_is_clamped", {"emissiveFactor": [1e39, 1e39, 1e39]}, "emissiveFactor"),
        ("emissive_negative_is_clamped", {"emissiveFactor": [-1, -1, -1]}, "emissiveFactor"),
        ("emissive_strength_1e39_is_clamped",
         {"emissiveFactor": [1, 1, 1], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 1e39}}},
         "emissiveStrength"),
    ]:
        def add_ext(g, m=material):
            if "extensions" in m:
                g.setdefault("extensionsUsed", []).append("KHR_materials_emissive_strength")
        case(name, {"scene.gltf": triangle_gltf(material=material, lights=lit, extra=add_ext)}, "rendered",
             warning=warning)
    # Lights whose power overflows single precision would leave every light unselectable.
    for name, light in [("point_light_1e37_renders", {"type": "point", "intensity": 1e37 * 683}),
                        ("sun_1e35_renders", {"type": "directional", "intensity": 1e35 * 683})]:
        for integrator in ("pt", "bdpt"):
            case(f"{name}_{integrator}",
                 {"scene.gltf": triangle_gltf(material={}, lights=[(light, {"translation": [0, 0, 0]})])},
                 "rendered", args=["--integrator", integrator])
    # Light colours and intensities past the extension's ranges (colour in [0, 1], intensity
    # >= 0; 2.3e41 W is 1.25e43 cd, past single precision) rendered black or were dropped, the
    # scene lit by a white stand-in environment: held to range with a warning, the light kept.
    for name, light, warning in [
        ("point_light_2e41_watts_is_clamped", {"type": "point", "intensity": 2.3e41 / (4 * 3.14159265) * 683},
         "light intensity"),
        ("point_light_negative_intensity_is_clamped", {"type": "point", "intensity": -50, "color": [1, 1, 1]},
         "light intensity"),
        ("point_light_negative_colour_is_clamped", {"type": "point", "intensity": 50, "color": [-1, 0.5, 1]},
         "light color"),
        ("point_light_colour_1e39_is_clamped", {"type": "point", "intensity": 50, "color": [1e39, 1, 1]},
         "light color"),
    ]:
        for integrator in ("pt", "bdpt"):
            case(f"{name}_{integrator}", {"scene.gltf": triangle_gltf(material={}, lights=[(light, {})])},
                 "rendered", args=["--integrator", integrator], warning=warning, lit="negative_intensity" not in name)
    # A sun over a scene 1e17 across (its emission disc's area is 1e34 m^2).
    def far_copy(g):
        g["nodes"].append({"name": "far", "mesh": 0, "translation": [1e17, 0, 0]})
        g["scenes"][0]["nodes"].append(len(g["nodes"]) - 1)

    for integrator in ("pt", "bdpt", "lt"):
        wide = triangle_gltf(material={}, lights=[({"type": "directional", "intensity": 3.0}, {})], extra=far_copy)
        case(f"sun_over_a_scene_1e17_across_renders_{integrator}", {"scene.gltf": wide}, "rendered",
             args=["--integrator", integrator])
    # Negative factors clamped: pt and bdpt both non-negative (they disagreed in sign before).
    for integrator in ("pt", "bdpt"):
        case(f"base_color_negative_is_clamped_{integrator}",
             {"scene.gltf": triangle_gltf(material={"pbrMetallicRoughness": {"baseColorFactor": [-1, -2, 0.5, 1]}},
                                          lights=lit)}, "rendered", args=["--integrator", integrator],
             warning="baseColorFactor")
    # Float vertex colours multiply the base colour: negative or huge ones are clamped to [0, 1].
    for name, colour in [("vertex_colour_negative_is_clamped", [-2.0, -2.0, -2.0, 1.0]),
                         ("vertex_colour_1e30_is_clamped", [1e30, 1e30, 1e30, 1.0])]:
        def add_colours(g, c=colour):
            raw = f32(c * 3)
            g["buffers"].append({"byteLength": len(raw), "uri": data_uri(raw)})
            g["bufferViews"].append({"buffer": 1, "byteOffset": 0, "byteLength": len(raw)})
            g["accessors"].append({"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC4"})
            g["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = 2
        for integrator in ("pt", "bdpt"):
            case(f"{name}_{integrator}",
                 {"scene.gltf": triangle_gltf(material={}, lights=lit, extra=add_colours)}, "rendered",
                 args=["--integrator", integrator], warning="COLOR_0")
    # A time limit that ends before the first pass: an error, never an image tagged complete.
    case("time_limit_before_first_pass_is_refused", {"scene.gltf": triangle_gltf()}, "refused",
         args=["--time", "1e-9", "--spp", "1000000"], message="time limit")
    # glTF 1.0 (dictionaries where 2.0 has arrays): tinygltf would read it as an empty scene.
    v1 = {"asset": {"version": "1.0"}, "scene": "s", "scenes": {"s": {"nodes": []}}, "nodes": {},
          "meshes": {}, "accessors": {}, "bufferViews": {}, "buffers": {}}
    case("gltf_1_0_is_refused", {"scene.gltf": v1}, "refused", message="glTF 1.0 is not supported")
    v1_no_version = dict(v1)
    del v1_no_version["asset"]
    case("gltf_1_0_without_version_is_refused", {"scene.gltf": v1_no_version}, "refused",
         message="glTF 1.0 is not supported")
    glb1 = json.dumps(v1).encode()
    glb1 += b" " * (-len(glb1) % 4)
    case("glb_1_0_is_refused", {"scene.glb": b"glTF" + struct.pack("<III", 1, 20 + len(glb1), len(glb1)) + struct.pack("<I", 0) + glb1},
         "refused", message="glTF 1.0 is not supported", input_name="scene.glb")


def textured_triangle(uri, extra_images=(), mime=None):
    """The triangle with a base-colour texture from image `uri` (plus images no texture uses)."""
    image = {"uri": uri}
    if mime:
        image["mimeType"] = mime
    images = [image] + [{"uri": u} for u in extra_images]
    return triangle_gltf(material={"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}},
                                   "emissiveFactor": [1, 1, 1]},
                         extra=lambda g: g.update({"images": images, "textures": [{"source": 0}]}))


def sparse_file(size):
    """A file of `size` bytes that takes no disk space (reading it gives zeros)."""
    def make(p):
        with open(p, "wb") as f:
            f.truncate(size)
    return make


def many_channel_exr(width, height, channels):
    """A constant half-float EXR with `channels` channels, zip-compressed: a few hundred KB."""
    def make(p):
        import OpenImageIO as oiio
        import numpy
        spec = oiio.ImageSpec(width, height, channels, "half")
        spec.channelnames = ("R", "G", "B", "A") + tuple(f"aov{k}" for k in range(channels - 4))
        spec.attribute("compression", "zip")
        out = oiio.ImageOutput.create(str(p))
        out.open(str(p), spec)
        row = numpy.full((width, channels), 0.5, dtype=numpy.float16)
        for y in range(height):
            if not out.write_scanline(y, 0, row):
                raise RuntimeError(out.geterror())
        out.close()
    return make


def memory_cases():
    """Small files that declare large allocations: each is charged to a budget before the
    allocation happens, refused with a message naming memory when it does not fit, and never
    read or decoded further than what the render uses."""
    # A 1x1 PNG whose header says 16384x16384: 4 GiB of float texels plus stb's buffers. Under
    # the suite's 2 GiB address space the budget refuses it before stb allocates anything.
    case("png_declaring_16384_squared_is_refused_before_decoding",
         {"scene.gltf": textured_triangle("tex.png"), "tex.png": png_bytes(1, 1, declared=(16384, 16384))},
         "refused", message="could take", limit_is_the_point=True)
    # A 16-channel EXR texture of 4096x4096: only its RGBA channels are decoded (256 MiB); all
    # sixteen as floats (1 GiB) would not fit the 1.25 GiB address space beside the process itself (about 0.7 GiB).
    case("exr_texture_with_16_channels_decodes_rgba_only",
         {"scene.gltf": textured_triangle("tex.exr", mime="image/x-exr"), "tex.exr": many_channel_exr(4096, 4096, 16)},
         "rendered", memory_mb=1280)
    # A data URI's JSON costs several times its size to parse: 96 MB of base64 under a 1 GiB
    # address space is refused by the estimate, before tinygltf parses it.
    big = triangle_gltf(buffer_uri=data_uri(triangle_bin() + bytes(72 << 20)))
    big["buffers"][0]["byteLength"] = 42 + (72 << 20)
    case("data_uri_too_large_to_parse_is_refused_before_parsing", {"scene.gltf": big}, "refused",
         message="parsing this file needs", memory_mb=1024, limit_is_the_point=True)
    # Ten million empty nodes (30 MB of JSON) would be ten million tinygltf objects, gigabytes;
    # the outline counts them on the text and refuses before tinygltf parses.
    nodes = triangle_gltf()
    nodes["nodes"].append("NODES")
    text = json.dumps(nodes).replace('"NODES"', ",".join(["{}"] * 10_000_000))
    case("ten_million_empty_nodes_are_refused_before_parsing", {"scene.gltf": text}, "refused",
         message="nodes", memory_mb=1024, limit_is_the_point=True)
    # A 16384 x 16384 render: its film's sums need about 29 GB; estimated before rendering and
    # refused with the sizes, not OOM-killed (the later --width wins over the suite's own).
    case("film_larger_than_memory_is_refused_before_rendering", {"scene.gltf": triangle_gltf()}, "refused",
         args=["--width", "16384", "--height", "16384"], message="memory available", limit_is_the_point=True)
    # An image listed by the file but used by no texture: 3 GB that are never read.
    case("unused_image_is_never_read",
         {"scene.gltf": textured_triangle("tex.png", extra_images=["unused.png"]), "tex.png": png_bytes(4, 4),
          "unused.png": sparse_file(3 << 30)}, "rendered")


def png_bytes(width, height, declared=None, pixel=b"\x80\x80\x80"):
    """An RGB PNG of width x height (`declared` overrides the header's size: a small image claiming
    to be huge)."""
    w, h = declared or (width, height)
    raw = b"".join(b"\0" + pixel * width for _ in range(height))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def write_case(folder, files):
    folder.mkdir(parents=True, exist_ok=True)
    for rel, content in files.items():
        p = folder / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(content, dict):
            p.write_text(json.dumps(content))
        elif isinstance(content, bytes):
            p.write_bytes(content)
        elif isinstance(content, str):
            p.write_text(content)
        elif callable(content):
            content(p)


def full_size_cases():
    """The adversarial review's cases at their own sizes, which take gigabytes of disk and minutes:
    only in `make test-robustness` (--full-size). The suite's other cases are their scaled-down
    forms."""
    # A 2 GB data URI (a 2.7 GB .gltf): larger than the suite's 2 GiB address space, refused
    # before it is read. Written in pieces so the generator never holds it.
    def big_data_uri(path):
        head, tail = json.dumps(triangle_gltf(buffer_uri="URI")).split('"URI"')
        with open(path, "w") as f:
            f.write(head + '"data:application/octet-stream;base64,')
            piece = base64.b64encode(bytes(3 << 20)).decode()
            for _ in range(2048 // 3 + 1):
                f.write(piece)
            f.write('"' + tail)
    case("data_uri_of_2_gb_is_refused_before_reading", {"scene.gltf": big_data_uri}, "refused",
         message="memory this process can take", limit_is_the_point=True)


def main():
    out = pathlib.Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    camera_cases()
    confinement_cases()
    silent_wrong_image_cases()
    memory_cases()
    if "--full-size" in sys.argv[2:]:
        full_size_cases()
    manifest = []
    for c in CASES:
        folder = out / c["name"]
        write_case(folder, c.pop("files"))
        c["folder"] = str(folder)
        c["input"] = str(folder / (c["input"] or "scene.gltf"))
        c["args"] = [a.replace("{folder}", str(folder)) for a in c["args"]]
        manifest.append(c)
    (out / "manifest.json").write_text(json.dumps(manifest, indent=1))
    print(f"{len(manifest)} cases in {out}")


if __name__ == "__main__":
    main()

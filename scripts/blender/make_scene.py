"""Build a procedural scene in Blender, save it, export it to glTF and render its Cycles reference.

  blender -b --factory-startup --python scripts/blender/make_scene.py -- --scene NAME --out DIR
          [--spp N] [--seed S] [--frames A-B|A,B,...] [--width W --height H] [--threads T]

Writes, in DIR:
  NAME.blend                 the scene as built (compressed), its images beside it
  NAME.gltf, NAME.bin, ...   Blender's own glTF exporter (plus VEACH_lights_blender for the light
                             settings it drops: plugins/blender/blender_lights.py): GLTF_SEPARATE, lights, cameras,
                             custom properties as extras, animation when the scene is animated
  NAME.cycles.exr            the Cycles reference: half floats, zip, scene-linear Rec.709, from
                             cycles_setup.unbiased_cycles() with "lambert" materials swapped for
                             Diffuse BSDF; an animated scene gets NAME.cycles.NNNN.exr per frame
  NAME.cycles.json           spp, seed, width, height, seconds (Cycles' render time, all frames),
                             frames, Blender's version, and the veach arguments the scene needs
--spp defaults to the scene's SPP; --spp 0 builds and exports only. --frames defaults to the
scene's REFERENCE_FRAMES, else every frame of its FRAMES (frame 1 for a still scene; a still scene accepts no other frame). --width and
--height default to the scene's RESOLUTION (one alone keeps its aspect ratio). The scenes are
the modules in scripts/blender/scenes (see tests/data/scenes/README.md to add one).
Exit codes: 0 done, 2 bad arguments (one line on stderr), 1 anything else that failed.
"""
import argparse
import json
import os
import sys
import time

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
# The add-on's writer of Blender's light settings (no bpy needed), used on the export as the add-on does.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "plugins", "blender"))
import blender_lights  # noqa: E402
import cycles_setup  # noqa: E402
import scene_kit  # noqa: E402
import scenes  # noqa: E402

IMAGE_EXTENSIONS = {'PNG': ".png", 'JPEG': ".jpg", 'HDR': ".hdr", 'OPEN_EXR': ".exr", 'TIFF': ".tif"}


class BadArguments(Exception):
    pass


class Parser(argparse.ArgumentParser):
    def error(self, message):
        raise BadArguments(message)


def parse_frames(text):
    """'A-B' (inclusive) or 'A,B,...' or 'A' to a sorted list of frame numbers."""
    try:
        if "-" in text.strip("-"):
            first, last = (int(x) for x in text.split("-", 1))
            frames = list(range(first, last + 1))
        else:
            frames = [int(x) for x in text.split(",")]
    except ValueError:
        raise BadArguments("--frames: expected A-B or a list A,B,... of frame numbers, got '%s'" % text)
    if not frames:
        raise BadArguments("--frames: '%s' is an empty range" % text)
    return sorted(set(frames))


def parse_arguments(argv):
    parser = Parser(prog="make_scene.py", description="Build, export and render a reference scene.")
    parser.add_argument("--scene", required=True, help="one of: " + ", ".join(scenes.names()))
    parser.add_argument("--out", required=True, help="output folder (created)")
    parser.add_argument("--spp", type=int, help="Cycles samples per pixel (default: the scene's; 0: no render)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--frames", help="A-B or A,B,...: frames to render (animated scenes)")
    parser.add_argument("--width", type=int)
    parser.add_argument("--height", type=int)
    parser.add_argument("--threads", type=int, default=0, help="Cycles threads (default: all cores)")
    args = parser.parse_args(argv)
    if args.scene not in scenes.names():
        raise BadArguments("unknown scene '%s' (scenes: %s)" % (args.scene, ", ".join(scenes.names())))
    for name in ("spp", "width", "height", "threads"):
        value = getattr(args, name)
        if value is not None and (value < 0 or (value == 0 and name in ("width", "height"))):
            raise BadArguments("--%s must be %s, got %d" % (name, "positive" if name in ("width", "height")
                                                            else "0 or more", value))
    args.frames = parse_frames(args.frames) if args.frames else None
    return args


def resolution(definition, args):
    width, height = definition.RESOLUTION
    if args.width and args.height:
        return args.width, args.height
    if args.width:
        return args.width, max(1, round(args.width * height / width))
    if args.height:
        return max(1, round(args.height * width / height)), args.height
    return width, height


def save_images(out):
    """Write every image made in memory into out, and point the file at it (relative once the
    .blend is saved there), so the .blend reopens with the same pixels."""
    for image in bpy.data.images:
        if image.source != 'GENERATED' and not image.is_dirty:
            continue
        extension = IMAGE_EXTENSIONS[image.file_format]
        image.filepath_raw = os.path.join(out, image.name + extension)
        if image.file_format == 'HDR':
            # Blender 3.4's image.save() of a generated float image set to HDR goes through an
            # 8-bit buffer (sRGB-decoded and clamped to 1); write the float values ourselves and
            # reload, so that the reference render sees the file's (RGBE-rounded) pixels.
            write_radiance_hdr(image.filepath_raw, image.size[0], image.size[1], image.pixels[:])
            image.source = 'FILE'
            image.reload()
            continue
        image.save()
        # Without the reload the .blend keeps the image as GENERATED (a blank image to any later
        # Blender, which would not render what the reference shows).
        image.source = 'FILE'
        image.reload()


def write_radiance_hdr(path, width, height, rgba):
    """A Radiance .hdr of flat RGBE scanlines, top row first, from Blender's bottom-up RGBA."""
    import numpy as np
    rgb = np.asarray(rgba, dtype=np.float64).reshape(height, width, 4)[::-1, :, :3].reshape(-1, 3)
    rgb = np.maximum(rgb, 0.0)
    peak = rgb.max(axis=1)
    mantissa, exponent = np.frexp(peak)
    scale = np.where(peak > 1e-32, mantissa * 256.0 / np.maximum(peak, 1e-38), 0.0)
    rgbe = np.zeros((rgb.shape[0], 4), dtype=np.uint8)
    rgbe[:, :3] = np.minimum(rgb * scale[:, None], 255).astype(np.uint8)
    rgbe[:, 3] = np.where(peak > 1e-32, exponent + 128, 0)
    rows = rgbe.reshape(height, width, 4)
    # A scanline starting 2, 2, (b < 128) would read as run-length encoded: nudge that texel.
    starts = (rows[:, 0, 0] == 2) & (rows[:, 0, 1] == 2) & (rows[:, 0, 2] < 128)
    rows[starts, 0, 0] = 3
    with open(path, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (height, width))
        f.write(rows.tobytes())


def export_gltf(path, animated):
    has_shape_keys = any(m.shape_keys is not None for m in bpy.data.meshes)
    bpy.ops.export_scene.gltf(
        filepath=path, export_format='GLTF_SEPARATE', export_lights=True, export_cameras=True,
        export_extras=True, export_animations=animated, export_frame_range=True,
        # Applying modifiers drops shape keys in Blender 3.4's exporter: apply only without them.
        export_apply=not has_shape_keys)
    # Area lights, point and spot radius and sun angle, which Blender's exporter drops.
    blender_lights.write_blender_lights(path, bpy.context.scene.objects)


def render_references(name, out, frames, animated, spp, seed, threads):
    """Cycles, frame by frame; returns the seconds each frame took."""
    scene = bpy.context.scene
    cycles_setup.lambert_materials()
    cycles_setup.unbiased_cycles(scene, samples=spp, seed=seed)
    scene.render.image_settings.color_depth = '16'  # half floats: 1e-8 relMSE from float
    scene.render.use_stamp_filename = False  # no path of this machine in the metadata
    if threads:
        scene.render.threads_mode = 'FIXED'
        scene.render.threads = threads
    seconds = []
    for frame in frames:
        scene.frame_set(frame)
        suffix = ".%04d" % frame if animated else ""
        scene.render.filepath = os.path.join(out, "%s.cycles%s.exr" % (name, suffix))
        start = time.time()
        bpy.ops.render.render(write_still=True)
        seconds.append(time.time() - start)
        print("make_scene: %s (%d spp) in %.1f s" % (scene.render.filepath, spp, seconds[-1]), flush=True)
    return seconds


def main(argv):
    args = parse_arguments(argv)
    definition = scenes.load(args.scene)
    out = os.path.abspath(args.out)
    os.makedirs(out, exist_ok=True)

    scene_kit.reset()
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = resolution(definition, args)
    scene.render.resolution_percentage = 100
    definition.build()
    animated = scene_kit.is_animated()
    first, last = getattr(definition, "FRAMES", (1, 1))
    frames = args.frames or list(getattr(definition, "REFERENCE_FRAMES", range(first, last + 1)))
    if not animated and frames != [1]:
        raise BadArguments("scene '%s' is not animated: it has frame 1 only" % args.scene)
    if animated:
        scene.frame_start, scene.frame_end = min(frames[0], first), max(frames[-1], last)
    scene.frame_set(scene.frame_start)

    save_images(out)
    if getattr(definition, "BLEND_SAMPLES", None):
        # The .blend asks its render engine (Cycles, and the Veach add-on, which follows Cycles'
        # settings) for the reference's settings at fewer samples: what its tests render.
        cycles_setup.unbiased_cycles(scene, samples=definition.BLEND_SAMPLES)
    bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out, args.scene + ".blend"), compress=True,
                                relative_remap=True)
    export_gltf(os.path.join(out, args.scene + ".gltf"), animated)
    print("make_scene: %s.blend and %s.gltf in %s" % (args.scene, args.scene, out), flush=True)

    spp = definition.SPP if args.spp is None else args.spp
    if spp == 0:
        return
    seconds = render_references(args.scene, out, frames, animated, spp, args.seed, args.threads)
    record = {
        "scene": args.scene, "spp": spp, "seed": args.seed, "seconds": sum(seconds),
        "width": scene.render.resolution_x, "height": scene.render.resolution_y, "frames": frames,
        "blender": bpy.app.version_string,
    }
    if animated:
        record["frame_seconds"] = seconds
    if getattr(definition, "VEACH_ARGS", None):
        record["veach_args"] = definition.VEACH_ARGS
    with open(os.path.join(out, args.scene + ".cycles.json"), "w") as f:
        json.dump(record, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    try:
        main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
    except BadArguments as e:
        print("make_scene: %s" % e, file=sys.stderr)
        sys.exit(2)
    except Exception as e:  # Blender would print the traceback and still exit 0
        import traceback
        traceback.print_exc()
        print("make_scene: failed: %s" % e, file=sys.stderr)
        sys.exit(1)

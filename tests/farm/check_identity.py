#!/usr/bin/python3
"""Checkpoint and part identity is the content of every input file, never a path; corrupt
checkpoints are refused.

What must hold:
- The same scene (a .gltf with a .bin and a PNG texture) copied to another folder: a checkpoint
  made through one path resumes through the other (veach:resumed_spp in the image), and parts
  rendered from the two copies merge.
- An edited texture or buffer (one byte) is another render: the checkpoint is refused and the
  parts do not merge (exit 2, one line). The environment map (--env) likewise: one map through
  two paths merges, a map with one texel changed does not.
- A checkpoint of the right length made of NaN bytes, or a real one with one flipped byte, is
  refused with exit 2 and one line, and no image is written.
- The version of veach is part of the identity: a checkpoint or a part that another version made
  (here: a real one whose recorded version is rewritten, its CRC made good again, as another
  build would have written it) is refused with exit 2 and one line naming both versions, and
  --skip-existing renders such a part again rather than keeping it.
Exit 0 pass, 1 fail.
"""
import argparse
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import zlib

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
from check_report import FAILURES, check, import_numpy_oiio  # noqa: E402

np, oiio = import_numpy_oiio()

FLAGS = ["--width", "48", "--height", "48", "--integrator", "pt", "--threads", "1"]


def run(veach, *args):
    return subprocess.run([veach, *args], capture_output=True, text=True, timeout=120)


def one_line_exit2(r, what):
    lines = r.stderr.strip().splitlines()
    check(r.returncode == 2, f"{what}: exit {r.returncode}, expected 2 ({r.stderr.strip()})")
    check(len(lines) == 1, f"{what}: expected one line, got {lines}")


def make_checkpoint(veach, scene, out):
    """Starts a long render with a checkpoint every pass and stops it (SIGTERM) once one exists."""
    checkpoint = out + ".checkpoint"
    p = subprocess.Popen([veach, "render", scene, "-o", out, *FLAGS, "--spp", "100000", "--checkpoint", "0", "-q"],
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    end = time.time() + 60
    while time.time() < end and not os.path.exists(checkpoint) and p.poll() is None:
        time.sleep(0.02)
    p.send_signal(signal.SIGTERM)
    p.communicate(timeout=60)
    if not os.path.exists(checkpoint):
        raise RuntimeError(f"no checkpoint appeared at {checkpoint}")
    if os.path.exists(out):
        os.remove(out)
    return checkpoint


def resumed_spp(path):
    spec = oiio.ImageBuf(path).spec()
    value = spec.getattribute("veach:resumed_spp")  # an int attribute in EXR
    return "" if value is None else str(value)


def with_version(data, old, new):
    """The file's bytes with its recorded version `old` replaced by `new` (same length) and its
    CRC-32 (of everything before the CRC and the 8-byte end marker) recomputed."""
    assert len(old) == len(new)
    body = data[:-12]
    if body[:8] == b"VEACHCK3":  # checkpoint: a 16-byte NUL-padded field after the magic
        check(body[8:8 + len(old)] == old, f"the checkpoint does not record version {old}")
        body = body[:8] + new + body[8 + len(new):]
    else:  # part file: a "version X" line in the text header
        line = b"\nversion " + old + b"\n"
        check(body.count(line) == 1, f"the part file does not record version {old}")
        body = body.replace(line, b"\nversion " + new + b"\n")
    return body + zlib.crc32(body).to_bytes(4, sys.byteorder) + data[-8:]


def check_versions(veach, scene, out, tmp):
    version = run(veach, "--version").stdout.split()[-1].encode()
    # Another version of the same length: every digit moved on by one (0.6.0 -> 1.7.1).
    other = bytes((c - 48 + 1) % 10 + 48 if 48 <= c <= 57 else c for c in version)
    checkpoint = make_checkpoint(veach, scene, out)
    edited = with_version(open(checkpoint, "rb").read(), version, other)
    open(checkpoint, "wb").write(edited)
    r = run(veach, "render", scene, "-o", out, *FLAGS, "--spp", "64", "--resume", "-q")
    one_line_exit2(r, "resume from another version's checkpoint")
    check(version.decode() in r.stderr and other.decode() in r.stderr,
          f"resume from another version's checkpoint: both versions should be named ({r.stderr.strip()})")
    check(not os.path.exists(out), "resume from another version's checkpoint: an image was written")
    os.remove(checkpoint)
    parts = [os.path.join(tmp, f"v{i}.vpart") for i in range(2)]
    for part, samples in zip(parts, ("0:8", "8:16")):
        r = run(veach, "render", scene, "-o", part, *FLAGS, "--spp", "16", "--samples", samples, "-q")
        check(r.returncode == 0, f"part {samples}: exit {r.returncode} ({r.stderr.strip()})")
    edited = with_version(open(parts[1], "rb").read(), version, other)
    open(parts[1], "wb").write(edited)
    r = run(veach, "merge", *parts, "-o", os.path.join(tmp, "v.exr"))
    one_line_exit2(r, "parts of two versions")
    check(all(s in r.stderr for s in (version.decode(), other.decode(), parts[0], parts[1])),
          f"parts of two versions: the line should name both files and both versions ({r.stderr.strip()})")
    r = run(veach, "render", scene, "-o", parts[1], *FLAGS, "--spp", "16", "--samples", "8:16", "--skip-existing")
    check(r.returncode == 0 and "skipped" not in r.stderr and b"\nversion " + version + b"\n" in open(parts[1], "rb").read(),
          f"--skip-existing kept another version's part (exit {r.returncode}, {r.stderr.strip()})")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--veach", required=True)
    ap.add_argument("--scene-dir", required=True, help="a scene folder with NAME.gltf, NAME.bin and a PNG")
    ap.add_argument("--name", required=True)
    args = ap.parse_args()
    veach = args.veach
    with tempfile.TemporaryDirectory() as tmp:
        copies = {}
        for c in ("a", "b", "edited_bin", "edited_png"):
            copies[c] = os.path.join(tmp, c)
            shutil.copytree(args.scene_dir, copies[c], ignore=shutil.ignore_patterns("*.blend", "*.exr", "*.json"))
        pngs = [f for f in os.listdir(copies["a"]) if f.endswith(".png")]
        if not check(pngs, "the scene folder has no PNG texture"):
            return 1
        # One byte of the vertex data; one byte of the texture's pixels (re-encoded PNG, same size).
        binary = os.path.join(copies["edited_bin"], args.name + ".bin")
        data = bytearray(open(binary, "rb").read())
        data[len(data) // 3] ^= 0x01
        open(binary, "wb").write(bytes(data))
        texture = os.path.join(copies["edited_png"], pngs[0])
        source = oiio.ImageBuf(texture)
        pixels = source.get_pixels(oiio.UINT8)
        pixels[0, 0, 0] ^= 0x10
        spec = oiio.ImageSpec(source.spec().width, source.spec().height, source.spec().nchannels, oiio.UINT8)
        del source
        png = oiio.ImageOutput.create(texture)
        check(png and png.open(texture, spec) and png.write_image(pixels), f"cannot rewrite {texture}")
        png.close()

        scene = {c: os.path.join(d, args.name + ".gltf") for c, d in copies.items()}
        out = os.path.join(tmp, "out.exr")

        # Another path, same content: resumes.
        make_checkpoint(veach, scene["a"], out)
        r = run(veach, "render", scene["b"], "-o", out, *FLAGS, "--spp", "64", "--resume", "-q")
        if check(r.returncode == 0, f"resume through another path: exit {r.returncode} ({r.stderr.strip()})"):
            check(resumed_spp(out) not in ("", "0"), "resume through another path did not resume")
        # Edited buffer or texture: refused.
        for c in ("edited_bin", "edited_png"):
            make_checkpoint(veach, scene["a"], out)
            r = run(veach, "render", scene[c], "-o", out, *FLAGS, "--spp", "64", "--resume", "-q")
            one_line_exit2(r, f"resume with an {c.replace('_', ' ')}")
            check(not os.path.exists(out), f"resume with an {c}: an image was written")
            os.remove(out + ".checkpoint")

        # Corrupt checkpoints.
        checkpoint = make_checkpoint(veach, scene["a"], out)
        good = open(checkpoint, "rb").read()
        flipped = bytearray(good)
        flipped[len(flipped) // 2] ^= 0x08
        nan = bytes([0xFF, 0xF8, 0, 0, 0, 0, 0, 0][::-1]) * (len(good) // 8) + b"\0" * (len(good) % 8)
        for what, content in (("a flipped byte", bytes(flipped)), ("NaN bytes", nan),
                              ("NaN bytes after a real header", good[:56] + nan[56:])):
            open(checkpoint, "wb").write(content)
            r = run(veach, "render", scene["a"], "-o", out, *FLAGS, "--spp", "64", "--resume", "-q")
            one_line_exit2(r, f"checkpoint with {what}")
            check(not os.path.exists(out), f"checkpoint with {what}: an image was written")

        check_versions(veach, scene["a"], out, tmp)

        # Parts: through two paths they merge; from an edited texture they do not.
        parts = {}
        for c, samples in (("a", "0:8"), ("b", "8:16"), ("edited_png", "8:16")):
            parts[c] = os.path.join(tmp, f"{c}.vpart")
            r = run(veach, "render", scene[c], "-o", parts[c], *FLAGS, "--spp", "16", "--samples", samples, "-q")
            check(r.returncode == 0, f"part from {c}: exit {r.returncode} ({r.stderr.strip()})")
        r = run(veach, "merge", parts["a"], parts["b"], "-o", os.path.join(tmp, "m.exr"), "--expect-spp", "16")
        check(r.returncode == 0, f"parts through two paths: merge exit {r.returncode} ({r.stderr.strip()})")
        r = run(veach, "merge", parts["a"], parts["edited_png"], "-o", os.path.join(tmp, "m2.exr"))
        one_line_exit2(r, "parts of an edited texture")

        # The environment map (--env) is an input file like the others: the same map through two
        # paths merges, a map with one texel changed does not.
        maps = {c: os.path.join(copies[c], "sky.exr") for c in ("a", "b", "edited_png")}
        texels = np.full((4, 8, 3), 0.5, dtype=np.float32)
        texels[1, 2] = (2.0, 1.5, 1.0)
        for c, path in maps.items():
            if c == "edited_png":
                texels[3, 5, 1] = 0.75
            out_map = oiio.ImageOutput.create(path)
            check(out_map and out_map.open(path, oiio.ImageSpec(8, 4, 3, oiio.FLOAT)) and out_map.write_image(texels),
                  f"cannot write {path}")
            out_map.close()
        env_parts = {}
        for c, samples in (("a", "0:8"), ("b", "8:16"), ("edited_png", "8:16")):
            env_parts[c] = os.path.join(tmp, f"env_{c}.vpart")
            r = run(veach, "render", scene["a"], "-o", env_parts[c], *FLAGS, "--spp", "16", "--samples", samples,
                    "--env", maps[c], "-q")
            check(r.returncode == 0, f"part with the map of {c}: exit {r.returncode} ({r.stderr.strip()})")
        r = run(veach, "merge", env_parts["a"], env_parts["b"], "-o", os.path.join(tmp, "e.exr"), "--expect-spp", "16")
        check(r.returncode == 0, f"one environment map through two paths: merge exit {r.returncode} ({r.stderr.strip()})")
        r = run(veach, "merge", env_parts["a"], env_parts["edited_png"], "-o", os.path.join(tmp, "e2.exr"))
        one_line_exit2(r, "parts of an edited environment map")
    if FAILURES:
        print(f"{len(FAILURES)} failure(s)")
        return 1
    print("identity: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())

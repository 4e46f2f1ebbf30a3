#!/usr/bin/python3
"""`veach render --frames A-B[:STEP]`: a sequence from one load of an animated glTF.

The scene is check_cli_animation.py's (an emissive quad sliding out of an orthographic view:
image mean 0.5 at t = 0, 0.25 at t = 0.5, 0 from t = 1), plus an unsupported extension in
extensionsUsed, whose warning the import prints once per load. What must hold:
- --frames 0-24:12 -o seq_####.exr writes seq_0000, seq_0012 and seq_0024 with means 0.5, 0.25
  and 0, and the import's warning is printed once: one load for the three frames;
- {frame} patterns work too (-o f_{frame}.exr --frames 3-5: f_3, f_4, f_5), and so do
  --stats-json patterns (one file per frame); {stem} with #### (-o {stem}_##.exr: slide_00, slide_01);
- a frame pattern may name a folder per frame (-o per_frame/{frame}/beauty.exr), and every
  frame's folder is checked before anything renders: with padded/0000 there and padded/0001
  missing, -o padded/####/beauty.exr --frames 0-1 is refused (exit 2, one line naming
  padded/0001) and frame 0 is not rendered;
- several frames with an output (or --stats-json) that is not a pattern, --frame with --frames,
  a range that runs backwards and a step of 0 are usage errors: exit 1, one line, nothing written;
- --skip-existing skips the frames whose outputs are complete and renders the others;
- --checkpoint keeps one checkpoint per frame (beside that frame's output) and removes each once
  its image is written;
- --animated-seed: each frame's veach:seed is the seed mixed with the frame (frames differ from
  each other and from --seed; a frame rendered alone gets the seed it got in the sequence);
  without it every frame keeps --seed.
Exit 0 pass, 1 fail.
"""
import argparse
import importlib.util
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
from check_report import FAILURES, check, import_numpy_oiio  # noqa: E402

np, oiio = import_numpy_oiio()


def load_animation_check():
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "check_cli_animation.py")
    spec = importlib.util.spec_from_file_location("check_cli_animation", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def mean_and_seed(path):
    buf = oiio.ImageBuf(path)
    pixels = np.asarray(buf.get_pixels(oiio.FLOAT))[..., :3]
    return float(pixels.mean()), str(buf.spec().getattribute("veach:seed"))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--veach", required=True)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="veach_cli_sequence_") as tmp:
        scene = os.path.join(tmp, "slide.gltf")
        load_animation_check().write_scene(scene, extra_extension="EXT_not_a_real_extension")
        common = ["--width", "32", "--height", "32", "--spp", "4", "--integrator", "pt", "--threads", "2", "-q"]

        def run(*flags):
            return subprocess.run([args.veach, "render", scene, *common, *flags], capture_output=True, text=True,
                                  timeout=180)

        out = os.path.join(tmp, "seq_####.exr")
        proc = run("-o", out, "--frames", "0-24:12")
        check(proc.returncode == 0, f"--frames 0-24:12: exit {proc.returncode}: {proc.stderr.strip()}")
        warnings = [l for l in proc.stderr.splitlines() if "EXT_not_a_real_extension" in l]
        check(len(warnings) == 1, f"the import's warning was printed {len(warnings)} times for 3 frames (one load: 1)")
        for frame, want in ((0, 0.5), (12, 0.25), (24, 0.0)):
            path = os.path.join(tmp, "seq_%04d.exr" % frame)
            if check(os.path.exists(path), f"{path} not written"):
                mean, seed = mean_and_seed(path)
                check(abs(mean - want) < 1e-4, f"frame {frame}: mean {mean:.5f}, expected {want}")
                check(seed == "0", f"frame {frame} without --animated-seed: veach:seed {seed}, expected 0")
                print(f"seq_{frame:04d}.exr mean {mean:.5f} (expected {want}), seed {seed}")
        check(not os.path.exists(os.path.join(tmp, "seq_0006.exr")), "frame 6 written with step 12")

        proc = run("-o", os.path.join(tmp, "f_{frame}.exr"), "--frames", "3-5", "--stats-json",
                   os.path.join(tmp, "s_{frame}.json"))
        check(proc.returncode == 0, f"--frames 3-5: exit {proc.returncode}: {proc.stderr.strip()}")
        for frame in (3, 4, 5):
            check(os.path.exists(os.path.join(tmp, f"f_{frame}.exr")), f"f_{frame}.exr not written")
            check(os.path.exists(os.path.join(tmp, f"s_{frame}.json")), f"s_{frame}.json not written")

        # {stem} (the scene's name) with a frame pattern.
        proc = run("-o", os.path.join(tmp, "{stem}_##.exr"), "--frames", "0-1")
        check(proc.returncode == 0, f"-o {{stem}}_##.exr: exit {proc.returncode}: {proc.stderr.strip()}")
        for frame in (0, 1):
            check(os.path.exists(os.path.join(tmp, "slide_%02d.exr" % frame)), f"slide_{frame:02d}.exr not written")

        # A frame pattern in a folder name: a folder per frame, each checked before anything
        # renders (it must exist, as any output's folder must).
        for frame in (0, 1):
            os.makedirs(os.path.join(tmp, "per_frame", str(frame)))
        proc = run("-o", os.path.join(tmp, "per_frame", "{frame}", "beauty.exr"), "--frames", "0-1")
        check(proc.returncode == 0, f"-o per_frame/{{frame}}/beauty.exr: exit {proc.returncode}: {proc.stderr.strip()}")
        for frame in (0, 1):
            check(os.path.exists(os.path.join(tmp, "per_frame", str(frame), "beauty.exr")),
                  f"per_frame/{frame}/beauty.exr not written")
        os.makedirs(os.path.join(tmp, "padded", "0000"))
        proc = run("-o", os.path.join(tmp, "padded", "####", "beauty.exr"), "--frames", "0-1")
        lines = proc.stderr.strip().splitlines()
        check(proc.returncode == 2 and len(lines) == 1 and os.path.join("padded", "0001") in lines[0],
              f"frame 1's missing folder padded/0001: exit {proc.returncode}, {lines} (expected 2, naming it)")
        check(not os.listdir(os.path.join(tmp, "padded", "0000")), "frame 0 rendered before frame 1's folder was checked")

        refusals = [(["-o", os.path.join(tmp, "plain.exr"), "--frames", "1-2"], "several frames need an output pattern"),
                    (["-o", os.path.join(tmp, "p_#.exr"), "--frames", "1-2", "--stats-json",
                      os.path.join(tmp, "plain.json")], "--stats-json pattern"),
                    (["-o", os.path.join(tmp, "p_#.exr"), "--frame", "1", "--frames", "1-2"], "exclude each other"),
                    (["-o", os.path.join(tmp, "p_#.exr"), "--frames", "5-1"], "before the first"),
                    (["-o", os.path.join(tmp, "p_#.exr"), "--frames", "1-5:0"], "--frames step")]
        for flags, needle in refusals:
            proc = run(*flags)
            lines = proc.stderr.strip().splitlines()
            check(proc.returncode == 1, f"{' '.join(flags)}: exit {proc.returncode}, expected 1")
            check(len(lines) == 1 and needle in lines[0], f"{' '.join(flags)}: message {lines!r} lacks {needle!r}")
            if lines:
                print(f"refused: {lines[0]}")
        written = [f for f in os.listdir(tmp) if f.startswith("p_") or f.startswith("plain")]
        check(not written, f"refused commands wrote {written}")

        # --skip-existing: frame 12's output is complete, so only 0 and 24 are rendered.
        skip = os.path.join(tmp, "skip_####.exr")
        check(run("-o", skip, "--frame", "12").returncode == 0, "frame 12 alone failed")
        before = os.stat(os.path.join(tmp, "skip_0012.exr")).st_mtime_ns
        proc = subprocess.run([args.veach, "render", scene, *common[:-1], "-o", skip, "--frames", "0-24:12",
                               "--skip-existing"], capture_output=True, text=True, timeout=180)
        check(proc.returncode == 0, f"--skip-existing: exit {proc.returncode}: {proc.stderr.strip()}")
        check("frame 12 skipped" in proc.stderr, f"--skip-existing did not say frame 12 was skipped: {proc.stderr!r}")
        check(os.stat(os.path.join(tmp, "skip_0012.exr")).st_mtime_ns == before, "frame 12 was rendered again")
        for frame in (0, 24):
            check(os.path.exists(os.path.join(tmp, "skip_%04d.exr" % frame)), f"frame {frame} not rendered")

        # --checkpoint: one per frame, each removed once its frame is written.
        proc = run("-o", os.path.join(tmp, "ck_####.exr"), "--frames", "0-2", "--checkpoint", "0")
        check(proc.returncode == 0, f"--checkpoint: exit {proc.returncode}: {proc.stderr.strip()}")
        left = [f for f in os.listdir(tmp) if f.endswith(".checkpoint")]
        check(not left, f"checkpoints left behind: {left}")
        check(all(os.path.exists(os.path.join(tmp, "ck_%04d.exr" % f)) for f in (0, 1, 2)), "--checkpoint frames missing")

        # --animated-seed.
        proc = run("-o", os.path.join(tmp, "as_####.exr"), "--frames", "0-24:12", "--seed", "5", "--animated-seed")
        check(proc.returncode == 0, f"--animated-seed: exit {proc.returncode}: {proc.stderr.strip()}")
        seeds = [mean_and_seed(os.path.join(tmp, "as_%04d.exr" % f))[1] for f in (0, 12, 24)]
        check(len(set(seeds)) == 3 and "5" not in seeds, f"--animated-seed seeds {seeds}: expected three, none 5")
        proc = run("-o", os.path.join(tmp, "alone.exr"), "--frame", "12", "--seed", "5", "--animated-seed")
        alone = mean_and_seed(os.path.join(tmp, "alone.exr"))[1] if proc.returncode == 0 else None
        check(alone == seeds[1], f"frame 12 alone has seed {alone}, in the sequence {seeds[1]}")
        print(f"--animated-seed: seeds of frames 0, 12, 24: {seeds}; frame 12 alone: {alone}")
    if FAILURES:
        sys.exit(1)
    print("PASS: --frames renders a sequence from one load, patterns, refusals, skip, checkpoints, animated seed")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""The Blender add-on as users and farms run it: the command lines of Blender's own manual on a
.blend that another Blender process built and saved (scripts/blender/make_scene.py, scene
"posed": a keyed ball with a shape key, an armature-bent bar, a subdivided cube):
  blender -b posed.blend --addons veach -E VEACH -o //out_#### -F OPEN_EXR -f 7
  blender -b posed.blend --addons veach -E VEACH -o //anim_#### -F OPEN_EXR -s 1 -e 12 -a
  blender -b posed.blend --addons veach -E VEACH -o //farm_#### -F OPEN_EXR --render-frame 1..3
Each must exit 0 and write its frames; the stats line is printed only when it changes, with the
ETA "unknown" while nothing is done. Every frame must match Cycles' render of that frame
(tests/data/scenes/posed/posed.cycles.NNNN.exr, Lambertian materials): channel means within 2%
and 16x16 block means within 5% (tests/tools/image_compare.py). Frames must differ from each
other as Cycles' frames do: each frame fails to match its neighbours' references. So a render of the rest pose,
of an unevaluated shape key or of one frame for all would fail (the scene moves enough that
Cycles' consecutive frames differ by over 1.5 times the block tolerance).
Usage: check_blender_frames.py --library LIBVEACH --addon plugins/blender --repo REPO_ROOT"""
import argparse
import os
import shutil
import sys
import tempfile

from blender_harness import find_blender, install_addon, run_or_exit

MEAN_TOLERANCE = 0.02
BLOCK_TOLERANCE = 0.05
FRAMES = range(1, 13)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--library", required=True)
    ap.add_argument("--addon", required=True)
    ap.add_argument("--repo", required=True)
    args = ap.parse_args()
    blender = find_blender()
    sys.path.insert(0, os.path.join(args.repo, "tests", "tools"))
    import image_compare

    references = os.path.join(args.repo, "tests", "data", "scenes", "posed")
    tmp = tempfile.mkdtemp(prefix="veach_blender_frames_")
    try:
        # The add-on installed as a user installs it: a folder `veach` in the user's add-ons.
        env = install_addon(tmp, args.addon, args.library)
        work = os.path.join(tmp, "scene")
        run_or_exit([blender, "-b", "--factory-startup", "--python",
             os.path.join(args.repo, "scripts", "blender", "make_scene.py"), "--",
             "--scene", "posed", "--out", work, "--spp", "0"], tmp, env, "building posed.blend")

        common = [blender, "-b", "posed.blend", "--addons", "veach", "-E", "VEACH"]
        renders = {}  # (command, frame) -> path
        log = run_or_exit(common + ["-o", "//out_####", "-F", "OPEN_EXR", "-f", "7"], work, env, "-f 7")
        renders[("-f 7", 7)] = "out_0007.exr"
        run_or_exit(common + ["-o", "//anim_####", "-F", "OPEN_EXR", "-s", "1", "-e", "12", "-a"], work, env, "-a")
        renders.update({("-a", f): "anim_%04d.exr" % f for f in FRAMES})
        run_or_exit(common + ["-o", "//farm_####", "-F", "OPEN_EXR", "--render-frame", "1..3"], work, env,
            "--render-frame 1..3")
        renders.update({("--render-frame 1..3", f): "farm_%04d.exr" % f for f in (1, 2, 3)})
        # Nothing in this scene is dropped: no warning may claim otherwise.
        dropped = [line for line in log.splitlines() if "Veach:" in line]
        if dropped:
            sys.exit(f"FAIL: warnings on a scene the add-on carries completely: {dropped}")
        # The stats line: printed only when it changes, the ETA unknown until the first pass.
        stats = [line.split("| Veach |", 1)[1].strip() for line in log.splitlines() if "| Veach |" in line]
        print("stats lines of -f 7:", stats)
        if not stats:
            sys.exit("FAIL: no Veach progress line in Blender's output: was the VEACH engine used?\n" + log[-2000:])
        repeats = [a for a, b in zip(stats, stats[1:]) if a == b]
        if repeats:
            sys.exit(f"FAIL: the stats line repeats unchanged: {repeats}")
        rendering = [line for line in stats if "%" in line]
        early = [line for line in rendering if "| 0% |" in line and "ETA unknown" not in line]
        if not rendering or early:
            sys.exit(f"FAIL: no progress lines, or an ETA before any samples were done: {early or stats}")

        failures = []
        for (command, frame), name in sorted(renders.items(), key=lambda kv: (kv[0][1], kv[0][0])):
            path = os.path.join(work, name)
            if not os.path.exists(path):
                failures.append(f"{command}: frame {frame} was not written ({name})")
                continue
            test = image_compare.load(path)
            own = image_compare.compare(test, image_compare.load(os.path.join(references,
                                                                              "posed.cycles.%04d.exr" % frame)))
            worst_mean = max(abs(m - 1) for m in own["mean"])
            ok = worst_mean <= MEAN_TOLERANCE and own["blocks"] <= BLOCK_TOLERANCE and own["nonfinite"] == 0
            print(f"{command:>20} frame {frame:2}: mean {' '.join('%.4f' % m for m in own['mean'])}, "
                  f"blocks {own['blocks']:.4f}{'' if ok else '  <- FAIL'}")
            if not ok:
                failures.append(f"{command}: frame {frame} differs from Cycles' (mean {own['mean']}, "
                                f"blocks {own['blocks']:.4f}, nonfinite {own['nonfinite']})")
        # Frames differ: Cycles' consecutive frames differ by more than the tolerance, and each -a
        # frame fails to match its neighbours' references while it matches its own.
        changes = []
        for frame in FRAMES:
            test = image_compare.load(os.path.join(work, "anim_%04d.exr" % frame))
            for other in (frame - 1, frame + 1):
                if other not in FRAMES:
                    continue
                ref_other = image_compare.load(os.path.join(references, "posed.cycles.%04d.exr" % other))
                if other == frame + 1:
                    ref_own = image_compare.load(os.path.join(references, "posed.cycles.%04d.exr" % frame))
                    changes.append(image_compare.compare(ref_own, ref_other)["blocks"])
                ours = image_compare.compare(test, ref_other)["blocks"]
                if ours <= BLOCK_TOLERANCE:
                    failures.append(f"frame {frame} matches frame {other}'s reference too (blocks {ours:.4f})")
        print("Cycles' consecutive frames differ by blocks", " ".join("%.3f" % c for c in changes))
        if min(changes) <= 1.5 * BLOCK_TOLERANCE:
            failures.append("the scene's consecutive frames are too alike to tell frames apart")
        if failures:
            sys.exit("FAIL:\n  " + "\n  ".join(failures))
        print(f"PASS: {len(renders)} frames from -f, -a and --render-frame match Cycles frame by frame")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()

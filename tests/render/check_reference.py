#!/usr/bin/python3
"""check_reference.py --veach BIN --scenes DIR --scene NAME [--spp N] [--integrator I] [--frame N]
                      [--mean-tol T] [--block-tol T] [--extra ARGS]

Renders SCENES/NAME/NAME.gltf (tests/data/scenes) at the reference's resolution and compares it
with the Cycles reference beside it (with --frame N, an animated scene's NAME.cycles.NNNN.exr,
rendered by `veach render --frame N`) in tests/tools/image_compare.py's measures: every channel's
mean within --mean-tol (relative), every lit 16x16 block mean within --block-tol, no non-finite
value; a reference with alpha (Film > Transparent) also by its alpha (image_compare.check_alpha).
The reference's json may name arguments the scene needs (veach_args: a World's --env-color).
Exit 0 pass, 1 fail."""
import argparse, json, os, subprocess, sys, tempfile

ap = argparse.ArgumentParser()
ap.add_argument("--veach", required=True)
ap.add_argument("--scenes", required=True, help="the folder of scene folders (tests/data/scenes)")
ap.add_argument("--scene", required=True)
ap.add_argument("--spp", type=int, default=256)
ap.add_argument("--integrator", default="pt")
ap.add_argument("--mean-tol", type=float, default=0.02)
ap.add_argument("--block-tol", type=float, default=0.05)
ap.add_argument("--frame", type=int, help="an animated scene's frame: its reference and `--frame N`")
ap.add_argument("--extra", default="", help="more veach arguments, space separated")
a = ap.parse_args()
# Sanitizer builds (make test-sanitize) divide sample counts and widen tolerances by sqrt of it.
divisor = max(1, int(os.environ.get("VEACH_TEST_SPP_DIVISOR", "1") or 1))
a.spp = max(1, a.spp // divisor)
a.mean_tol *= divisor ** 0.5
# At a fraction of the samples, 16x16 blocks over caustics are dominated by fireflies, which do
# not shrink like sqrt(spp): the sanitizer run checks the means and finiteness only.
check_blocks = divisor == 1

scene_dir = os.path.join(a.scenes, a.scene)
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
import image_compare as compare  # noqa: E402  (tests/tools/image_compare.py)

meta = json.load(open(os.path.join(scene_dir, a.scene + ".cycles.json")))
reference = os.path.join(scene_dir, a.scene + ".cycles.exr")
if a.frame is not None:
    if a.frame not in meta["frames"]:
        sys.exit("check_reference: %s has no reference at frame %d (frames %s)" % (a.scene, a.frame, meta["frames"]))
    reference = os.path.join(scene_dir, "%s.cycles.%04d.exr" % (a.scene, a.frame))
with tempfile.TemporaryDirectory() as tmp:
    out = os.path.join(tmp, a.scene + ".exr")
    cmd = [a.veach, "render", os.path.join(scene_dir, a.scene + ".gltf"), "-o", out,
           "--width", str(meta["width"]), "--height", str(meta["height"]), "--spp", str(a.spp),
           "--integrator", a.integrator, "--quiet", "--stats-json", os.path.join(tmp, "stats.json")]
    if a.frame is not None:
        cmd += ["--frame", str(a.frame)]
    cmd += meta.get("veach_args", []) + a.extra.split()
    subprocess.run(cmd, check=True)
    res = compare.compare(compare.load(out), compare.load(reference))
    alpha_problems = compare.check_alpha(a.scene, out, reference, a.mean_tol, a.block_tol)
    stats = json.load(open(os.path.join(tmp, "stats.json")))
print("%s%s %s %d spp: relmse %.5f mean %s blocks %.4f nonfinite %d (dropped samples %d)" % (
    a.scene, "" if a.frame is None else " frame %d" % a.frame, a.integrator, a.spp, res["relmse"], " ".join("%.4f" % m for m in res["mean"]), res["blocks"],
    res["nonfinite"], stats["nonfinite_samples"]))
ok = True
for c, m in zip("RGB", res["mean"]):
    if abs(m - 1.0) > a.mean_tol:
        print("FAIL: channel %s mean ratio %.4f is off by more than %.3f" % (c, m, a.mean_tol)); ok = False
if check_blocks and res["blocks"] > a.block_tol:
    print("FAIL: worst 16x16 block differs by %.4f > %.3f" % (res["blocks"], a.block_tol)); ok = False
for problem in alpha_problems:
    print("FAIL: " + problem); ok = False
if res["nonfinite"] or stats["nonfinite_samples"]:
    print("FAIL: non-finite values"); ok = False
sys.exit(0 if ok else 1)

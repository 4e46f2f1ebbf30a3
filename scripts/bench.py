#!/usr/bin/python3
"""bench.py --build DIR [--budgets 2,4,8] [--scenes a,b] [--no-cycles] [--markdown docs/BENCHMARKS.md]
         [--only-integrators | --only-parts | --only-animation | --only-denoise]

Time against error, measured side by side in one run on this machine:
  - for every scene in tests/data/scenes, `veach render --time T` with pt, bdpt (every strategy)
    and auto (the default: the strategies each scene needs) at each budget: relMSE against the
    Cycles reference (tests/tools/image_compare.py), efficiency 1/(relMSE x seconds), samples/s
    and rays/s; auto's efficiency over the better of pt and bdpt, and what it chose;
  - the ray-tracing limit: incoherent closest-hit rays/s that Embree alone traces through the same
    BVH on all threads (veach_ray_bench), and the renderer's rays/s as a fraction of it;
  - Cycles at equal render time when Blender is installed (the reference settings of
    scripts/blender/cycles_setup.py with a render time limit), and our efficiency over Cycles';
  - 2 threads against 1 thread (samples/s, pt, cornell);
  - farm parts' overhead: 16 parts merged against one render of all their samples (CPU time) at
    128x128 (16 x 64 spp) and 1280x720 (16 x 4 spp, and what that gives for 16 x 64), the parts
    run as they are and with OpenImageIO loaded at start (the image module preloaded: what every
    process paid before OpenImageIO was opened on first use), instructions of process start and
    of a small part (valgrind), part file bytes per pixel, and the merge time of 16 parts of a
    1920x1080 frame (--only-parts runs this alone);
  - the denoiser (--denoise; --only-denoise runs this alone): on every scene with its better
    integrator, at 16, 64 and 256 spp, relMSE of the denoised image against the undenoised one
    and Cycles' at equal CPU time and at equal spp, and the spp from which it no longer helps;
  - animation (scripts/bench_animation.py): a 120-frame sequence of ~1M static triangles and one
    moving cube against a still, and a 10,000-instance EXT_mesh_gpu_instancing forest's peak
    memory against one tree (--only-animation runs these alone; --frames N for fewer frames).
Writes the tables into the markdown file between the BENCH markers and log-log plots of relMSE
against time next to it (docs/bench/NAME.png, with gnuplot). Ratios are the headline numbers:
absolute seconds depend on the machine and its load."""
import argparse, json, math, os, shutil, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = os.path.join(ROOT, "tests", "data", "scenes")
BLENDER_SCRIPTS = os.path.join(ROOT, "scripts", "blender")
sys.path.insert(0, os.path.join(ROOT, "tests", "tools"))
import image_compare as compare  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--build", default=os.path.join(ROOT, "build"))
ap.add_argument("--budgets", default="2,4,8")
ap.add_argument("--scenes", default="cornell,textured,lights,spheres,corridor")
ap.add_argument("--integrators", default="pt,bdpt,auto")
ap.add_argument("--no-cycles", action="store_true")
ap.add_argument("--markdown", default=os.path.join(ROOT, "docs", "BENCHMARKS.md"))
ap.add_argument("--only-parts", action="store_true", help="only the farm parts' overhead section")
ap.add_argument("--only-animation", action="store_true", help="only the animation sections (sequence, forest)")
ap.add_argument("--only-integrators", action="store_true",
                help="only the time-against-error section (pt, bdpt, auto, Cycles on the scenes)")
ap.add_argument("--frames", type=int, default=120, help="frames of the animation sequence benchmark")
ap.add_argument("--only-denoise", action="store_true", help="only the denoiser's section")
args = ap.parse_args()
budgets = [float(b) for b in args.budgets.split(",")]
veach = os.path.join(args.build, "veach")
ray_bench = os.path.join(args.build, "tests", "veach_ray_bench")
tmp = tempfile.mkdtemp(prefix="veach-bench-")

CYCLES_SCRIPT = r'''
import bpy, sys, os, time
sys.path.insert(0, os.environ["VEACH_BLENDER_SCRIPTS"])
import cycles_setup
cycles_setup.lambert_materials()
scene = bpy.context.scene
cycles_setup.unbiased_cycles(scene, samples=1 << 24, seed=1, time_limit=float(os.environ["VEACH_SECONDS"]))
scene.render.filepath = os.environ["VEACH_OUT"]
t = time.time()
bpy.ops.render.render(write_still=True)
print("VEACH_CYCLES_SECONDS", time.time() - t)
'''


def run(cmd, env=None):
    return subprocess.run(cmd, check=True, capture_output=True, text=True, env=env)


def relmse(path, ref):
    return compare.compare(compare.load(path), compare.load(ref))["relmse"]


def render_veach(scene, integrator, seconds, threads=0, spp=1 << 24, sampler="sobol"):
    meta = json.load(open(os.path.join(SCENES, scene, scene + ".cycles.json")))
    out = os.path.join(tmp, "%s_%s_%g.exr" % (scene, integrator, seconds))
    stats = out + ".json"
    run([veach, "render", os.path.join(SCENES, scene, scene + ".gltf"), "-o", out, "--width",
         str(meta["width"]), "--height", str(meta["height"]), "--spp", str(spp), "--time", str(seconds),
         "--integrator", integrator, "--threads", str(threads), "--sampler", sampler, "--quiet",
         "--stats-json", stats])
    s = json.load(open(stats))
    ref = os.path.join(SCENES, scene, scene + ".cycles.exr")
    e = relmse(out, ref)
    t = s["seconds"]["render"]
    return {"seconds": t, "relmse": e, "efficiency": 1.0 / (e * t), "spp": s["spp"],
            "samples_per_second": s["samples_per_second"], "rays_per_second": s["rays_per_second"],
            "strategies": s.get("strategies", "")}


def render_cycles(scene, seconds):
    out = os.path.join(tmp, "%s_cycles_%g.exr" % (scene, seconds))
    env = dict(os.environ, VEACH_BLENDER_SCRIPTS=BLENDER_SCRIPTS, VEACH_OUT=out,
               VEACH_SECONDS=str(seconds))
    script = os.path.join(tmp, "cycles_bench.py")
    open(script, "w").write(CYCLES_SCRIPT)
    p = run(["blender", "-b", os.path.join(SCENES, scene, scene + ".blend"), "--factory-startup",
             "-P", script], env=env)
    t = float([l for l in p.stdout.splitlines() if l.startswith("VEACH_CYCLES_SECONDS")][0].split()[1])
    e = relmse(out, os.path.join(SCENES, scene, scene + ".cycles.exr"))
    return {"seconds": t, "relmse": e, "efficiency": 1.0 / (e * t)}


def ray_limit(scene):
    p = run([ray_bench, os.path.join(SCENES, scene, scene + ".gltf"), "--seconds", "2"])
    return json.loads(p.stdout)["rays_per_second"]


# Farm parts' overhead: one frame rendered as 16 parts and merged, against one render of all
# their samples on the same machine (CPU time of the child processes, user + sys: every part pays
# process start, scene load, BVH build, its film and its part file once). Measured at two sizes:
# the 16 x 64 spp at 128x128, where the fixed cost per part dominates, and 16 x 4 spp at
# 1280x720, whose measured fixed cost per part and cost per sample give the ratio for 16 x 64 spp
# at 1280x720 (that render itself would take ~20 CPU minutes) and the samples per part from which
# the parts cost at most 5% more. Then the part file's size per pixel and the merge of 16 parts
# of a 1920x1080 frame (parts of 1 spp at depth 2, since only their size matters to the merge).
#
# The parts run twice, side by side: as they are (OpenImageIO opened on first use, in the image
# module, which a part writing only a .vpart never opens) and with the image module preloaded
# (LD_PRELOAD), which makes the dynamic loader map and relocate OpenImageIO's ~260 libraries at
# start as it did when libveach linked OpenImageIO. Instruction counts (valgrind's callgrind,
# when installed: `scripts/install-deps.sh --bench`) are of process start and of one small part.
IMAGE_MODULE = os.path.join(args.build, "libveach_image_io.so")
EAGER = dict(os.environ, LD_PRELOAD=IMAGE_MODULE)


def cpu_seconds(cmds, env=None):
    # getrusage, not os.times: its microseconds resolve a process start of a few milliseconds,
    # which clock ticks (10 ms) round to zero.
    import resource
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    for c in cmds:
        run(c, env=env)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def instructions(cmd, env=None):
    """Instructions a command executes (callgrind's total), or None without valgrind."""
    if shutil.which("valgrind") is None:
        return None
    out = os.path.join(tmp, "callgrind.out")
    try:
        p = run(["valgrind", "--tool=callgrind", "--callgrind-out-file=" + out, *cmd], env=env)
    except subprocess.CalledProcessError as e:  # the table says n/a; the reason goes to the log
        print("bench.py: valgrind failed (%s):\n%s" % (e, e.stderr[-3000:]), file=sys.stderr)
        return None
    line = [l for l in p.stderr.splitlines() if "Collected :" in l][0]
    return int(line.split()[-1])


def split_frame(scene, size, spp, parts, tag):
    """CPU seconds of one `spp` render, of `parts` sample-range parts (lazy and eager OpenImageIO),
    and of their merge."""
    single = cpu_seconds([[veach, "render", scene, "-o", os.path.join(tmp, tag + ".exr"), "--spp", str(spp), *size]])
    chunk = spp // parts
    files = [os.path.join(tmp, "%s%02d.vpart" % (tag, c)) for c in range(parts)]
    cmds = [[veach, "render", scene, "-o", files[c], "--spp", str(spp), "--samples",
             "%d:%d" % (chunk * c, chunk * (c + 1)), *size] for c in range(parts)]
    # Each part run both ways in turn (which first alternates), so that the machine's load, which
    # drifts over minutes, weighs on both sums alike.
    split = split_eager = 0.0
    for c, cmd in enumerate(cmds):
        for eager in ((False, True) if c % 2 == 0 else (True, False)):
            seconds = cpu_seconds([cmd], env=EAGER if eager else None)
            if eager:
                split_eager += seconds
            else:
                split += seconds
    merge = cpu_seconds([[veach, "merge", *files, "--expect-spp", str(spp), "-o", os.path.join(tmp, tag + "_m.exr"),
                          "--quiet"]])
    return single, split, split_eager, merge, files


def parts_overhead():
    import time
    if not os.path.exists(IMAGE_MODULE):
        sys.exit("bench.py: no image module at " + IMAGE_MODULE)
    scene = os.path.join(SCENES, "cornell", "cornell.gltf")
    common = ["--integrator", "pt", "--threads", "1", "--quiet"]
    start = min(cpu_seconds([[veach, "--version"]]) for _ in range(5))
    start_eager = min(cpu_seconds([[veach, "--version"]], env=EAGER) for _ in range(5))
    small_part = [veach, "render", scene, "-o", os.path.join(tmp, "i.vpart"), "--spp", "16", "--samples", "0:1",
                  "--width", "128", "--height", "128", *common]
    ins = {mode: (instructions([veach, "--version"], env), instructions(small_part, env))
           for mode, env in (("lazy", None), ("eager", EAGER))}
    single, split, split_eager, merge, parts = split_frame(
        scene, ["--width", "128", "--height", "128", *common], 1024, 16, "p")
    small = sum(os.path.getsize(p) for p in parts) / 16 / (128 * 128)
    hd_size = ["--width", "1280", "--height", "720", *common]
    hd_single, hd_split, hd_split_eager, hd_merge, hd_parts = split_frame(scene, hd_size, 64, 16, "q")
    per_spp = (hd_single - start) / 64  # the samples' cost (an upper bound: the film and image are in it)

    # A single render of n spp costs hd_single + (n - 64) per_spp; its 16 parts 16 fixed + merge more.
    def single_of(n):
        return hd_single + (n - 64) * per_spp

    def derived(parts_seconds):
        fixed = (parts_seconds - hd_single) / 16  # what each part costs beyond its samples
        at_64 = (single_of(1024) + 16 * fixed + hd_merge) / single_of(1024)
        # 16 parts of n spp cost at most 5% more when 16 fixed + merge <= 0.05 single_of(16 n).
        threshold = ((16 * fixed + hd_merge) / 0.05 - hd_single + 64 * per_spp) / (16 * per_spp)
        return fixed, at_64, threshold

    fixed, at_64, threshold = derived(hd_split)
    fixed_eager, at_64_eager, threshold_eager = derived(hd_split_eager)
    hd_bytes = sum(os.path.getsize(p) for p in hd_parts) / 16 / (1280 * 720)
    big = [os.path.join(tmp, "hd%02d.vpart" % c) for c in range(16)]
    for c in range(16):
        run([veach, "render", scene, "-o", big[c], "--width", "1920", "--height", "1080", "--spp", "16",
             "--samples", "%d:%d" % (c, c + 1), "--integrator", "pt", "--max-depth", "2", "--quiet"])
    hd = sum(os.path.getsize(p) for p in big) / 16 / (1920 * 1080)
    t0 = time.monotonic()
    merge_exr_cpu = cpu_seconds([[veach, "merge", *big, "--expect-spp", "16", "-o", os.path.join(tmp, "hd.exr"),
                                  "--quiet"]])
    merge_exr = time.monotonic() - t0
    t0 = time.monotonic()
    run([veach, "merge", *big, "--expect-spp", "16", "-o", os.path.join(tmp, "hd.vpart"), "--quiet"])
    merge_part = time.monotonic() - t0
    bdpt = os.path.join(tmp, "bdpt.vpart")
    run([veach, "render", scene, "-o", bdpt, "--width", "1920", "--height", "1080", "--spp", "16", "--samples", "0:1",
         "--integrator", "bdpt", "--max-depth", "2", "--quiet"])
    hd_bdpt = os.path.getsize(bdpt) / (1920 * 1080)

    def millions(n):
        return "n/a (no valgrind, or it failed)" if n is None else "%.1f M" % (n / 1e6)

    lines = [
        "| measure | OpenImageIO on first use | OpenImageIO at start (as before) |",
        "|---|---|---|",
        "| CPU seconds, process start alone (`veach --version`) | %.3f | %.3f |" % (start, start_eager),
        "| instructions, process start alone (`veach --version`) | %s | %s |" % (millions(ins["lazy"][0]),
                                                                               millions(ins["eager"][0])),
        "| instructions, one 128x128 part of 1 spp (cornell, pt) | %s | %s |" % (millions(ins["lazy"][1]),
                                                                                millions(ins["eager"][1])),
        "| CPU seconds, 16 parts of 64 spp + merge (128x128) | %.2f | %.2f |" % (split + merge, split_eager + merge),
        "| parts / single, 16 x 64 spp at 128x128 | %.3f | %.3f |" % ((split + merge) / single,
                                                                      (split_eager + merge) / single),
        "| CPU seconds, 16 parts of 4 spp + merge (1280x720) | %.2f | %.2f |" % (hd_split + hd_merge,
                                                                                hd_split_eager + hd_merge),
        "| parts / single, 16 x 4 spp at 1280x720 | %.3f | %.3f |" % ((hd_split + hd_merge) / hd_single,
                                                                      (hd_split_eager + hd_merge) / hd_single),
        "| fixed CPU seconds per part at 1280x720 (beyond its samples) | %.3f | %.3f |" % (fixed, fixed_eager),
        "| parts / single, 16 x 64 spp at 1280x720 (from the fixed cost and the cost per spp) | %.3f | %.3f |"
        % (at_64, at_64_eager),
        "| spp per part from which 16 parts cost at most 5%% more (1280x720, pt) | %.1f | %.1f |"
        % (threshold, threshold_eager),
        "",
        "| measure | value |",
        "|---|---|",
        "| CPU seconds, one 1024-spp render (cornell 128x128, pt, 1 thread) | %.2f |" % single,
        "| CPU seconds, one 64-spp render (cornell 1280x720, pt, 1 thread) | %.2f |" % hd_single,
        "| CPU seconds of the merge of 16 parts of 1280x720 (into an EXR) | %.2f |" % hd_merge,
        "| part file bytes per pixel, 128x128 pt part (64 spp) | %.1f |" % small,
        "| part file bytes per pixel, 1280x720 pt part (4 spp) | %.1f |" % hd_bytes,
        "| part file bytes per pixel, 1920x1080 pt part (1 spp) | %.1f |" % hd,
        "| part file bytes per pixel, 1920x1080 bdpt part (1 spp; full-frame splats) | %.1f |" % hd_bdpt,
        "| merge 16 parts of 1920x1080 into an EXR, seconds (wall / CPU) | %.2f / %.2f |" % (merge_exr, merge_exr_cpu),
        "| merge 16 parts of 1920x1080 into a .vpart, seconds (wall) | %.2f |" % merge_part,
    ]
    return "\n".join(lines)


def write_section(begin, end, table):
    if args.markdown and os.path.exists(args.markdown):
        text = open(args.markdown).read()
        if begin in text and end in text:
            text = text[: text.index(begin) + len(begin)] + "\n" + table + "\n" + text[text.index(end):]
            open(args.markdown, "w").write(text)


# The denoiser, at equal CPU time (user + system seconds of the whole `veach render`, which a
# shared machine's load does not stretch as it does wall time) and at equal spp. For each spp,
# one render with --denoise (relMSE of its denoised image and of its Noisy pass, which is the
# undenoised image bit for bit) and one without (its CPU time). The undenoised image given the
# denoised render's CPU time would have proportionally more samples: its relMSE is the noisy one
# scaled by t_plain / t_denoised (relMSE goes as 1/samples; an estimate that flatters it once
# the reference's own noise dominates). Cycles likewise from one render of 64 samples, its CPU
# time less Blender's own start (a 1-sample render). "Stops helping": the first spp at which the
# denoised image is no closer to the reference than the undenoised one at equal spp, and at
# equal time.
DENOISE_INTEGRATOR = {"cornell": "pt", "textured": "pt", "lights": "pt", "spheres": "bdpt", "corridor": "bdpt"}


def render_denoised(scene, integrator, spp):
    """relMSE of the denoised and the noisy image of one --denoise render, the render's CPU seconds,
    its denoise seconds (wall), and the CPU seconds of the same render without --denoise."""
    import numpy as np
    import OpenImageIO as oiio
    meta = json.load(open(os.path.join(SCENES, scene, scene + ".cycles.json")))
    out = os.path.join(tmp, "%s_denoised.exr" % scene)
    stats = out + ".json"
    common = [veach, "render", os.path.join(SCENES, scene, scene + ".gltf"), "--width", str(meta["width"]),
              "--height", str(meta["height"]), "--spp", str(spp), "--integrator", integrator, "--quiet"]
    cpu = cpu_seconds([common + ["-o", out, "--denoise", "--passes", "combined,noisy", "--stats-json", stats]])
    cpu_plain = cpu_seconds([common + ["-o", os.path.join(tmp, "%s_plain.exr" % scene)]])
    image = oiio.ImageBuf(out)
    names = list(image.spec().channelnames)
    pixels = np.asarray(image.get_pixels(oiio.FLOAT), dtype=np.float64)
    ref = compare.load(os.path.join(SCENES, scene, scene + ".cycles.exr"))

    def layer(name):
        return pixels[..., [names.index("ViewLayer.%s.%s" % (name, c)) for c in "RGB"]]

    return {"denoised": compare.compare(layer("Combined"), ref)["relmse"],
            "noisy": compare.compare(layer("Noisy"), ref)["relmse"], "cpu": cpu, "cpu_plain": cpu_plain,
            "denoise": json.load(open(stats))["seconds"]["denoise"]}


CYCLES_SAMPLES_SCRIPT = r'''
import bpy, sys, os
sys.path.insert(0, os.environ["VEACH_BLENDER_SCRIPTS"])
import cycles_setup
cycles_setup.lambert_materials()
scene = bpy.context.scene
cycles_setup.unbiased_cycles(scene, samples=int(os.environ["VEACH_SAMPLES"]), seed=1, time_limit=0.0)
scene.render.filepath = os.environ["VEACH_OUT"]
bpy.ops.render.render(write_still=True)
'''


def cycles_at_samples(scene, samples):
    """Cycles' relMSE at `samples` and the CPU seconds of its render (less Blender's start)."""
    script = os.path.join(tmp, "cycles_samples.py")
    open(script, "w").write(CYCLES_SAMPLES_SCRIPT)
    seconds = {}
    for n in (1, samples):
        out = os.path.join(tmp, "%s_cycles_%d.exr" % (scene, n))
        env = dict(os.environ, VEACH_BLENDER_SCRIPTS=BLENDER_SCRIPTS, VEACH_OUT=out, VEACH_SAMPLES=str(n))
        seconds[n] = cpu_seconds([["blender", "-b", os.path.join(SCENES, scene, scene + ".blend"), "--factory-startup",
                                   "-P", script]], env=env)
    return relmse(out, os.path.join(SCENES, scene, scene + ".cycles.exr")), max(1e-3, seconds[samples] - seconds[1])


def denoise_benchmark(spps, with_cycles, cycles_samples=64):
    lines = ["| scene | integrator | spp | CPU s undenoised | CPU s denoised | denoise s (wall) | relMSE denoised | "
             "relMSE undenoised, equal spp | undenoised, equal CPU time | undenoised / denoised, equal time | "
             "Cycles, equal CPU time | Cycles / denoised |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    stop_lines = ["| scene | integrator | noisy / denoised at equal spp (" + ", ".join(str(n) for n in spps) +
                  " spp) | stops helping, equal spp | stops helping, equal time |", "|---|---|---|---|---|"]
    for scene, integ in DENOISE_INTEGRATOR.items():
        if scene not in args.scenes.split(","):
            continue
        cycles = cycles_at_samples(scene, cycles_samples) if with_cycles else None
        ratios, stop_spp, stop_time = [], None, None
        for n in spps:
            r = render_denoised(scene, integ, n)
            equal_time = r["noisy"] * r["cpu_plain"] / r["cpu"]
            c = cycles[0] * cycles[1] / r["cpu"] if cycles else None
            lines.append("| %s | %s | %d | %.2f | %.2f | %.2f | %.4g | %.4g | %.4g | %.2fx | %s | %s |" % (
                scene, integ, n, r["cpu_plain"], r["cpu"], r["denoise"], r["denoised"], r["noisy"], equal_time,
                equal_time / r["denoised"], "%.4g" % c if c else "", "%.2fx" % (c / r["denoised"]) if c else ""))
            print(lines[-1], file=sys.stderr)
            ratios.append(r["noisy"] / r["denoised"])
            if stop_spp is None and r["denoised"] >= r["noisy"]:
                stop_spp = n
            if stop_time is None and r["denoised"] >= equal_time:
                stop_time = n
        beyond = "beyond %d spp" % spps[-1]
        stop_lines.append("| %s | %s | %s | %s | %s |" % (
            scene, integ, " / ".join("%.2fx" % x for x in ratios), "%d spp" % stop_spp if stop_spp else beyond,
            "%d spp" % stop_time if stop_time else beyond))
        print(stop_lines[-1], file=sys.stderr)
    return "\n".join(lines + [""] + stop_lines)


if args.only_denoise:
    denoise_table = denoise_benchmark([16, 64, 256], not args.no_cycles and shutil.which("blender") is not None)
    print(denoise_table)
    write_section("<!-- DENOISE:BEGIN -->", "<!-- DENOISE:END -->", denoise_table)
    shutil.rmtree(tmp, ignore_errors=True)
    sys.exit(0)

# Animation (scripts/bench_animation.py): a sequence's seconds per frame against a still, and an
# EXT_mesh_gpu_instancing forest's memory against one tree.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_animation  # noqa: E402

if args.only_animation or not (args.only_parts or args.only_integrators):
    sequence_table = bench_animation.sequence_benchmark(veach, args.build, frames=args.frames)
    print(sequence_table)
    write_section("<!-- SEQUENCE:BEGIN -->", "<!-- SEQUENCE:END -->", sequence_table)
    forest_table = bench_animation.forest_benchmark(veach, args.build)
    print(forest_table)
    write_section("<!-- FOREST:BEGIN -->", "<!-- FOREST:END -->", forest_table)
    if args.only_animation:
        shutil.rmtree(tmp, ignore_errors=True)
        sys.exit(0)

if not (args.only_parts or args.only_integrators):
    denoise_table = denoise_benchmark([16, 64, 256], not args.no_cycles and shutil.which("blender") is not None)
    print(denoise_table)
    write_section("<!-- DENOISE:BEGIN -->", "<!-- DENOISE:END -->", denoise_table)

if not args.only_integrators:
    parts_table = parts_overhead()
    print(parts_table)
    write_section("<!-- PARTS:BEGIN -->", "<!-- PARTS:END -->", parts_table)
if args.only_parts:
    shutil.rmtree(tmp, ignore_errors=True)
    sys.exit(0)

have_cycles = not args.no_cycles and shutil.which("blender") is not None
results = {}
for scene in args.scenes.split(","):
    r = {"limit": ray_limit(scene), "runs": {}}
    for integ in args.integrators.split(","):
        r["runs"][integ] = [render_veach(scene, integ, b) for b in budgets]
        print(scene, integ, ["%.4g" % x["relmse"] for x in r["runs"][integ]], file=sys.stderr)
    if have_cycles:
        r["runs"]["cycles"] = [render_cycles(scene, b) for b in budgets]
        print(scene, "cycles", ["%.4g" % x["relmse"] for x in r["runs"]["cycles"]], file=sys.stderr)
    results[scene] = r

# Thread scaling: the same fixed work on 1 and 2 threads.
scaling = {}
for threads in (1, 2):
    x = render_veach("cornell", "pt", 1e9, threads=threads, spp=128)  # long enough to amortise start-up
    scaling[threads] = x["samples_per_second"]

# Low-discrepancy sampling: relMSE at equal spp, Owen-scrambled Sobol against independent numbers.
sampler_rows = []
for scene in ("cornell", "corridor"):
    for integ in ("pt", "bdpt"):
        e = {smp: render_veach(scene, integ, 1e9, spp=16, sampler=smp)["relmse"] for smp in ("random", "sobol")}
        sampler_rows.append("| %s | %s | %.4g | %.4g | %.2f |" % (scene, integ, e["random"], e["sobol"],
                                                              e["random"] / e["sobol"]))

# Skipping what a scene does not use: cornell with twenty unused 4K textures loads and renders
# in the same time as cornell (textures are decoded only when a rendered material uses them).
def unused_textures_scene():
    import numpy as np
    import OpenImageIO as oiio
    d = os.path.join(tmp, "unused")
    os.makedirs(d, exist_ok=True)
    g = json.load(open(os.path.join(SCENES, "cornell", "cornell.gltf")))
    shutil.copy(os.path.join(SCENES, "cornell", "cornell.bin"), d)
    ramp = np.tile(np.linspace(0, 1, 4096, dtype=np.float32), (4096, 1))
    px = np.stack([ramp, ramp.T, 0.5 * np.ones_like(ramp)], axis=-1)
    g.setdefault("images", [])
    g.setdefault("textures", [])
    for i in range(20):
        name = "unused%02d.png" % i
        out = oiio.ImageOutput.create(name)
        out.open(os.path.join(d, name), oiio.ImageSpec(4096, 4096, 3, oiio.UINT8))
        out.write_image(px)
        out.close()
        g["images"].append({"uri": name})
        g["textures"].append({"source": len(g["images"]) - 1})
    path = os.path.join(d, "cornell_unused.gltf")
    json.dump(g, open(path, "w"))
    return path


def load_and_render(path):
    stats = os.path.join(tmp, "lr.json")
    best = None
    for _ in range(3):
        run([veach, "render", path, "-o", os.path.join(tmp, "lr.exr"), "--width", "128", "--height", "128",
             "--spp", "16", "--integrator", "pt", "--quiet", "--stats-json", stats])
        sec = json.load(open(stats))["seconds"]
        t = (sec["load"], sec["load"] + sec["build"] + sec["render"])
        best = t if best is None or t[1] < best[1] else best
    return best


plain = load_and_render(os.path.join(SCENES, "cornell", "cornell.gltf"))
unused = load_and_render(unused_textures_scene())

lines = []
lines.append("Machine: %d cores; budgets %s s; %s." % (
    os.cpu_count(), ", ".join("%g" % b for b in budgets),
    "Cycles %s" % ("CPU, same settings as the references, render time limit" if have_cycles else "not installed")))
lines.append("")
lines.append("| scene | integrator | budget s | render s | spp | relMSE | efficiency | vs Cycles | samples/s | rays/s | of Embree limit |")
lines.append("|---|---|---|---|---|---|---|---|---|---|---|")
for scene, r in results.items():
    for integ, runs in r["runs"].items():
        for b, x in zip(budgets, runs):
            vs = ""
            if have_cycles and integ != "cycles":
                c = r["runs"]["cycles"][budgets.index(b)]
                vs = "%.2fx" % (x["efficiency"] / c["efficiency"])
            sps = "%.3g" % x["samples_per_second"] if "samples_per_second" in x else ""
            rps = "%.3g" % x["rays_per_second"] if "rays_per_second" in x else ""
            frac = "%.0f%%" % (100 * x["rays_per_second"] / r["limit"]) if "rays_per_second" in x else ""
            lines.append("| %s | %s | %g | %.2f | %s | %.4g | %.4g | %s | %s | %s | %s |" % (
                scene, integ, b, x["seconds"], x.get("spp", ""), x["relmse"], x["efficiency"], vs, sps, rps, frac))
lines.append("")
lines.append("Embree limit (incoherent rays/s, all threads): " + ", ".join(
    "%s %.3g" % (s, r["limit"]) for s, r in results.items()) + ".")
lines.append("")
summary = []
for scene, r in results.items():
    if "bdpt" in r["runs"] and "pt" in r["runs"]:
        ratio = [p["relmse"] / b["relmse"] for p, b in zip(r["runs"]["pt"], r["runs"]["bdpt"])]
        eff = [b["efficiency"] / p["efficiency"] for p, b in zip(r["runs"]["pt"], r["runs"]["bdpt"])]
        summary.append("| %s | %s | %s |" % (scene, " / ".join("%.2f" % v for v in ratio),
                                              " / ".join("%.2f" % v for v in eff)))
lines.append("| scene | relMSE pt / bdpt at equal time (per budget) | efficiency bdpt / pt |")
lines.append("|---|---|---|")
lines += summary
lines.append("")
default_rows = []
for scene, r in results.items():
    if not all(k in r["runs"] for k in ("auto", "pt", "bdpt")):
        continue
    best = [max(p["efficiency"], b["efficiency"]) for p, b in zip(r["runs"]["pt"], r["runs"]["bdpt"])]
    vs_best = [a["efficiency"] / x for a, x in zip(r["runs"]["auto"], best)]
    vs_cycles = ""
    if have_cycles:
        vs_cycles = " / ".join("%.2f" % (a["efficiency"] / c["efficiency"])
                               for a, c in zip(r["runs"]["auto"], r["runs"]["cycles"]))
    chosen = sorted(set(a["strategies"] for a in r["runs"]["auto"]))
    default_rows.append("| %s | %s | %s | %s |" % (scene, ", ".join(chosen), " / ".join("%.2f" % v for v in vs_best),
                                                   vs_cycles))
if default_rows:
    lines.append("| scene | auto chose | efficiency auto / max(pt, bdpt) (per budget) | efficiency auto / Cycles |")
    lines.append("|---|---|---|---|")
    lines += default_rows
    lines.append("")
lines.append("Thread scaling (pt, cornell, 128 spp, samples/s): 2 threads / 1 thread = %.2fx." % (scaling[2] / scaling[1]))
lines.append("")
lines.append("Cornell with twenty unused 4096x4096 textures (best of 3, load / load+render seconds): "
             "%.3f / %.3f against plain cornell %.3f / %.3f." % (unused[0], unused[1], plain[0], plain[1]))
lines.append("")
lines.append("| scene | integrator | relMSE random, 16 spp | relMSE sobol, 16 spp | random / sobol |")
lines.append("|---|---|---|---|---|")
lines += sampler_rows
table = "\n".join(lines)
print(table)

# Plots: relMSE against render time, log-log, one PNG per scene.
plot_dir = os.path.join(os.path.dirname(args.markdown), "bench")
if shutil.which("gnuplot"):
    os.makedirs(plot_dir, exist_ok=True)
    for scene, r in results.items():
        data = os.path.join(tmp, scene + ".dat")
        with open(data, "w") as f:
            for integ, runs in r["runs"].items():
                f.write("# %s\n" % integ)
                for x in runs:
                    f.write("%g %g\n" % (x["seconds"], x["relmse"]))
                f.write("\n\n")
        names = list(r["runs"].keys())
        plot = ", ".join("'%s' index %d with linespoints title '%s'" % (data, i, n) for i, n in enumerate(names))
        gp = ("set terminal png size 480,360; set output '%s'; set logscale xy; set xlabel 'render seconds'; "
              "set ylabel 'relMSE'; set title '%s'; plot %s" % (os.path.join(plot_dir, scene + ".png"), scene, plot))
        subprocess.run(["gnuplot", "-e", gp], check=False)

write_section("<!-- BENCH:BEGIN -->", "<!-- BENCH:END -->", table)
shutil.rmtree(tmp, ignore_errors=True)

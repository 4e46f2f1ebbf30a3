#!/usr/bin/python3
"""Splitting one frame into parts and merging them with `veach merge`.

What must hold (the promise is exactness, so these comparisons are exact where it says so):
- Sample-range parts (--samples A:B -o X.vpart) of a path-traced render merge into the single
  render bit for bit; bdpt and lt parts agree to the summation order of their splats (relative
  1e-6). A 2x2 tile split (--pixelbounds) likewise for each of the three (each bdpt or lt tile
  keeps its light paths' splats over the whole frame), and tiles crossed with sample ranges.
- A merge may write a .vpart again, and merging that with the rest is the same image; it writes
  any format a render writes, several at once (an EXR and a PNG equal to the single render's).
- The merged image says spp = the samples merged, complete when they are all of --spp.
- Refusals, exit 2 with one line naming the files: parts of different renders, overlapping
  sample ranges, overlapping tiles, gaps with --expect-spp (a missing sample range, a missing
  tile), a corrupt part. --samples with --noise or --time, or past --spp,
  and --samples or --pixelbounds with --transparent (parts hold no coverage) are usage errors
  (exit 1); pixel bounds outside the image are bad input (exit 2).
Exit 0 pass, 1 fail.
"""
import argparse
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
from check_report import FAILURES, check, import_numpy_oiio  # noqa: E402

np, oiio = import_numpy_oiio()

SIZE = ["--width", "64", "--height", "64"]
SPP = 16


def run(veach, *args):
    return subprocess.run([veach, *args], capture_output=True, text=True, timeout=120)


def render(veach, scene, out, *extra):
    r = run(veach, "render", scene, "-o", out, *SIZE, "--spp", str(SPP), "--threads", "2", "-q", *extra)
    if r.returncode != 0:
        raise RuntimeError(f"render {out} {extra}: exit {r.returncode}: {r.stderr.strip()}")


def merge(veach, parts, out, *extra):
    return run(veach, "merge", *parts, "-o", out, *extra)


def read(path):
    buf = oiio.ImageBuf(path)
    if buf.has_error:
        raise RuntimeError(f"{path}: {buf.geterror()}")
    return buf.spec(), buf.get_pixels(oiio.FLOAT)


def compare(single, merged, exact, what):
    _, a = read(single)
    spec, b = read(merged)
    if exact:
        same = np.array_equal(a, b)
        check(same, f"{what}: merged parts differ from the single render (max |d| {np.abs(a - b).max():.3g})")
    else:
        rel = np.abs(a - b) / np.maximum(np.abs(a), 1e-30)
        worst = float(np.where(np.abs(a - b) > 0, rel, 0).max())
        check(worst <= 1e-6, f"{what}: merged parts differ from the single render by relative {worst:.3g} > 1e-6")
        check(np.abs(a).sum() > 0, f"{what}: the image is black")
    return spec


def refused(result, names, what):
    lines = result.stderr.strip().splitlines()
    ok = check(result.returncode == 2, f"{what}: exit {result.returncode}, expected 2 ({result.stderr.strip()})")
    ok = check(len(lines) == 1, f"{what}: expected one line, got {lines}") and ok
    for n in names:
        ok = check(lines and os.path.basename(n) in lines[0], f"{what}: the message does not name {n}: {lines}") and ok
    return ok


def sample_parts(veach, scene, tmp, integrator, ranges, tag, *extra):
    parts = []
    for a, b in ranges:
        p = os.path.join(tmp, f"{tag}_{a}_{b}.vpart")
        render(veach, scene, p, "--integrator", integrator, "--samples", f"{a}:{b}", *extra)
        parts.append(p)
    return parts


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--veach", required=True)
    ap.add_argument("--scene", required=True)
    args = ap.parse_args()
    veach, scene = args.veach, args.scene
    with tempfile.TemporaryDirectory() as tmp:
        quarters = [(0, 4), (4, 8), (8, 12), (12, 16)]
        halves = [(0, 8), (8, 16)]
        tiles = [(0, 32, 0, 32), (32, 64, 0, 32), (0, 32, 32, 64), (32, 64, 32, 64)]
        # auto, the default: its strategy set is chosen from the scene, camera, film size and seed
        # alone, so every part makes the single render's choice (another choice would be another
        # estimator, its noise far past the 1e-6 of splat summation order).
        for integrator in ("pt", "bdpt", "lt", "auto"):
            single = os.path.join(tmp, f"single_{integrator}.exr")
            render(veach, scene, single, "--integrator", integrator)
            parts = sample_parts(veach, scene, tmp, integrator, quarters if integrator == "pt" else halves, integrator)
            out = os.path.join(tmp, f"merged_{integrator}.exr")
            r = merge(veach, parts, out, "--expect-spp", str(SPP))
            if check(r.returncode == 0, f"{integrator}: merge exit {r.returncode}: {r.stderr.strip()}"):
                spec = compare(single, out, integrator == "pt", f"{integrator} sample ranges")
                check(spec.getattribute("veach:spp") == SPP, f"{integrator}: merged veach:spp")
                check(spec.get_string_attribute("veach:complete") == "yes", f"{integrator}: merged not complete")
                check(spec.get_string_attribute("veach:integrator") == integrator, f"{integrator}: integrator tag")
            tile_parts = []
            for x0, x1, y0, y1 in tiles:
                p = os.path.join(tmp, f"tile_{integrator}_{x0}_{y0}.vpart")
                render(veach, scene, p, "--integrator", integrator, "--pixelbounds", f"{x0},{x1},{y0},{y1}")
                tile_parts.append(p)
            out = os.path.join(tmp, f"tiles_{integrator}.exr")
            r = merge(veach, tile_parts, out, "--expect-spp", str(SPP))
            if check(r.returncode == 0, f"{integrator} tiles: merge exit {r.returncode}: {r.stderr.strip()}"):
                compare(single, out, integrator == "pt", f"{integrator} 2x2 tiles")

        # bdpt: two tiles (left, right halves) crossed with two sample ranges.
        single = os.path.join(tmp, "single_bdpt.exr")
        crossed = []
        for x0, x1 in ((0, 32), (32, 64)):
            crossed += sample_parts(veach, scene, tmp, "bdpt", halves, f"cross_{x0}",
                                    "--pixelbounds", f"{x0},{x1},0,64")
        out = os.path.join(tmp, "crossed.exr")
        r = merge(veach, crossed, out, "--expect-spp", str(SPP))
        if check(r.returncode == 0, f"tiles x samples: merge exit {r.returncode}: {r.stderr.strip()}"):
            compare(single, out, False, "bdpt tiles x sample ranges")

        # Progressive: merge two quarters into a part, then that part with the other two.
        pt = [os.path.join(tmp, f"pt_{a}_{b}.vpart") for a, b in quarters]
        half = os.path.join(tmp, "half.vpart")
        r = merge(veach, pt[:2], half)
        if check(r.returncode == 0, f"merge to .vpart: exit {r.returncode}: {r.stderr.strip()}"):
            out = os.path.join(tmp, "progressive.exr")
            r = merge(veach, [half] + pt[2:], out, "--expect-spp", str(SPP))
            if check(r.returncode == 0, f"progressive merge: exit {r.returncode}: {r.stderr.strip()}"):
                compare(os.path.join(tmp, "single_pt.exr"), out, True, "pt merged part + parts")
        # Any format `veach render` writes, several at once: the merged PNG is the single render's
        # PNG (the same sums through the same display transform and 8-bit encoding), and says so.
        single_png = os.path.join(tmp, "single_pt.png")
        render(veach, scene, single_png, "--integrator", "pt")
        out_exr, out_png = os.path.join(tmp, "both.exr"), os.path.join(tmp, "both.png")
        r = merge(veach, pt, out_exr, "-o", out_png, "--expect-spp", str(SPP))
        if check(r.returncode == 0, f"merge to .exr and .png: exit {r.returncode}: {r.stderr.strip()}"):
            compare(os.path.join(tmp, "single_pt.exr"), out_exr, True, "pt merged into an EXR beside a PNG")
            spec = compare(single_png, out_png, True, "pt merged into a PNG")
            check(spec.get_string_attribute("veach:spp") == str(SPP), "merged PNG: veach:spp")
            check(spec.get_string_attribute("veach:complete") == "yes", "merged PNG: not marked complete")
        # Without --expect-spp a partial set merges, honestly marked.
        out = os.path.join(tmp, "partial.exr")
        r = merge(veach, pt[:3], out)
        if check(r.returncode == 0, f"partial merge: exit {r.returncode}: {r.stderr.strip()}"):
            spec, _ = read(out)
            check(spec.getattribute("veach:spp") == 12, "partial merge: veach:spp is not 12")
            check(spec.get_string_attribute("veach:complete") == "no", "partial merge: marked complete")

        # Refusals.
        other = os.path.join(tmp, "seed1.vpart")
        render(veach, scene, other, "--integrator", "pt", "--samples", "4:8", "--seed", "1")
        refused(merge(veach, [pt[0], other], os.path.join(tmp, "x.exr")), [pt[0], other], "different renders")
        overlapping = sample_parts(veach, scene, tmp, "pt", [(2, 6)], "overlap")[0]
        refused(merge(veach, [pt[0], overlapping], os.path.join(tmp, "x.exr")), [pt[0], overlapping], "overlap")
        refused(merge(veach, [pt[0], pt[2], pt[3]], os.path.join(tmp, "x.exr"), "--expect-spp", str(SPP)),
                [pt[0], pt[2]], "gap with --expect-spp")
        # Tiles: two that share pixels are refused as the sample ranges are; three of four tiles
        # with --expect-spp leave a gap (the fourth tile's pixels hold no samples).
        tile_pt = [os.path.join(tmp, f"tile_pt_{x0}_{y0}.vpart") for x0, x1, y0, y1 in tiles]
        shifted = os.path.join(tmp, "tile_shifted.vpart")
        render(veach, scene, shifted, "--integrator", "pt", "--pixelbounds", "16,48,0,32")
        refused(merge(veach, [tile_pt[0], shifted], os.path.join(tmp, "x.exr")), [tile_pt[0], shifted],
                "overlapping tiles")
        refused(merge(veach, tile_pt[:3], os.path.join(tmp, "x.exr"), "--expect-spp", str(SPP)), tile_pt[:1],
                "a missing tile with --expect-spp")
        corrupt = os.path.join(tmp, "corrupt.vpart")
        data = bytearray(open(pt[1], "rb").read())
        data[len(data) // 2] ^= 0x40
        open(corrupt, "wb").write(bytes(data))
        refused(merge(veach, [pt[0], corrupt], os.path.join(tmp, "x.exr")), [corrupt], "corrupt part")
        check(not os.path.exists(os.path.join(tmp, "x.exr")), "a refused merge wrote its output")

        for extra, what in ((["--noise", "0.01"], "--noise"), (["--time", "5"], "--time"),
                            (["--samples", "0:32"], "past --spp"), (["--transparent"], "--transparent"),
                            (["--pixelbounds", "0,8,0,8", "--transparent"], "--pixelbounds --transparent")):
            samples = [] if what in ("past --spp", "--pixelbounds --transparent") else ["--samples", "0:4"]
            r = run(veach, "render", scene, "-o", os.path.join(tmp, "y.vpart"), *SIZE, "--spp", str(SPP),
                    *samples, *extra)
            check(r.returncode == 1 and len(r.stderr.strip().splitlines()) == 1,
                  f"--samples with {what}: exit {r.returncode} ({r.stderr.strip()}), expected one usage line")
        r = run(veach, "render", scene, "-o", os.path.join(tmp, "y.vpart"), *SIZE, "--spp", "4",
                "--pixelbounds", "0,65,0,10")
        check(r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1,
              f"--pixelbounds outside the image: exit {r.returncode} ({r.stderr.strip()}), expected 2")
        check(not os.path.exists(os.path.join(tmp, "y.vpart")), "a refused render wrote its part")
    if FAILURES:
        print(f"{len(FAILURES)} failure(s)")
        return 1
    print("parts and merge: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())

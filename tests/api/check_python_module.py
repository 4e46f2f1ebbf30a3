#!/usr/bin/python3
"""The Python module `veach` (plugins/python), run from Debian's python3 with numpy:

- `cmake --install` puts it in the prefix's Python site folder (lib/python3.X/dist-packages),
  and from there, with no VEACH_LIBRARY, it finds the prefix's libveach;
- veach.render(path, width=, height=, spp=, seed=, integrator=) returns the Combined pass as an
  H x W x 4 float32 array equal bit for bit to the EXR `veach render` writes with the same options
  (path tracing: randomness keyed by pixel and sample, so any thread count gives the same bits);
- errors are exceptions with the library's one-line message: a missing file is BadInput, spp 0
  InvalidArgument ("spp must be at least 1"), an unknown option InvalidArgument naming it;
- options take the table's types (noise=0.5 is a float, spp an int) and read back;
- an asynchronous render reports progress, is cancelled from this thread (Cancelled status, fewer
  samples than asked) and its partial image is still a finite array; the depth pass with aovs=1;
- a pass is written into a caller's array (no copy): `out=` is filled in place.
A sanitizer build does not register this test: plain hosts cannot load its library.
"""
import argparse
import glob
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
from check_report import check, exit_code  # noqa: E402


CHILD = r"""
import json, os, sys, time
import numpy as np
import veach
scene, exr = sys.argv[1], sys.argv[2]
report = {"module": os.path.realpath(veach.__file__), "version": veach.version()}
image = veach.render(scene, width=48, height=40, spp=8, seed=3, integrator="pt")
np.save(sys.argv[3], image)
report["shape"], report["dtype"] = list(image.shape), str(image.dtype)
errors = {}
for what, call in (("missing", lambda: veach.render("/nonexistent/scene.gltf", width=8, spp=1)),
                   ("spp0", lambda: veach.render(scene, width=8, spp=0)),
                   ("unknown", lambda: veach.render(scene, width=8, no_such_option=1))):
    try:
        call()
        errors[what] = None
    except veach.VeachError as e:
        errors[what] = [type(e).__name__, str(e), isinstance(e, ValueError)]
report["errors"] = errors
with veach.Scene(scene) as s:
    report["cameras"] = s.cameras
    report["triangles"] = s.get("triangles")
    with veach.Render(s, width=32, height=32, spp=4, noise=0.5, aovs=1, integrator="pt") as r:
        report["noise"] = r.get("noise")
        r.render()
        depth = r.get_pass("depth")
        report["depth_finite"] = bool(np.isfinite(depth).all())
        out = np.zeros((32, 32, 4), dtype=np.float32)
        same = r.get_pass("combined", out=out)
        report["in_place"] = same is out and bool(out[..., 3].min() == 1.0)
    seen = []
    with veach.Render(s, width=96, height=96, spp=100000, integrator="pt") as r:
        r.start(progress=lambda fraction, eta: seen.append(fraction) or True)
        deadline = time.time() + 60
        while not seen and time.time() < deadline:
            time.sleep(0.01)
        r.cancel()
        status = r.wait()
        report["cancel"] = [status, r.get("result_spp"), bool(np.isfinite(r.get_pass()).all()), len(seen) > 0]
print(json.dumps(report))
"""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", required=True)
    ap.add_argument("--veach", required=True)
    ap.add_argument("--scene", required=True)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="veach_python_") as tmp:
        prefix = os.path.join(tmp, "prefix")
        subprocess.run(["cmake", "--install", args.build, "--prefix", prefix], check=True, capture_output=True)
        sites = glob.glob(os.path.join(prefix, "lib", "python3*", "dist-packages"))
        if not check(len(sites) == 1 and os.path.isfile(os.path.join(sites[0], "veach", "__init__.py")),
                     f"the module is not in the prefix's site folder: {sites}"):
            return 1
        exr = os.path.join(tmp, "cli.exr")
        subprocess.run([args.veach, "render", args.scene, "-o", exr, "--width", "48", "--height", "40", "--spp", "8",
                        "--seed", "3", "--integrator", "pt", "-q"], check=True)
        env = {k: v for k, v in os.environ.items() if k not in ("VEACH_LIBRARY", "LD_LIBRARY_PATH")}
        env["PYTHONPATH"] = sites[0]
        npy = os.path.join(tmp, "module.npy")
        p = subprocess.run(["/usr/bin/python3", "-c", CHILD, args.scene, exr, npy], env=env, capture_output=True,
                           text=True, timeout=300, cwd=tmp)
        if not check(p.returncode == 0, f"the module's run failed: {p.stderr[-3000:]}"):
            return 1
        import json
        import numpy as np
        import OpenImageIO as oiio
        report = json.loads(p.stdout.strip().splitlines()[-1])
        check(report["module"].startswith(os.path.realpath(prefix)), f"imported from {report['module']}")
        check(report["shape"] == [40, 48, 4] and report["dtype"] == "float32", f"shape {report['shape']}")
        image = np.load(npy)
        cli = oiio.ImageBuf(exr).get_pixels(oiio.FLOAT)
        check(cli.shape == image.shape and np.array_equal(cli, image),
              f"veach.render differs from the command's EXR: max |d| "
              f"{float(np.abs(cli - image).max()) if cli.shape == image.shape else cli.shape}")
        e = report["errors"]
        check(e["missing"] and e["missing"][0] == "BadInput" and "/nonexistent/scene.gltf" in e["missing"][1],
              f"missing file: {e['missing']}")
        check(e["spp0"] and e["spp0"][0] == "InvalidArgument" and e["spp0"][1] == "spp must be at least 1" and
              e["spp0"][2], f"spp 0: {e['spp0']}")
        check(e["unknown"] and e["unknown"][0] == "InvalidArgument" and "no_such_option" in e["unknown"][1],
              f"unknown option: {e['unknown']}")
        check(report["noise"] == 0.5 and report["triangles"] > 0, f"options: {report['noise']} {report['triangles']}")
        check(report["depth_finite"] and report["in_place"], "passes: depth, or out= not filled in place")
        status, spp, finite, progressed = report["cancel"]
        check(status == 3 and 0 < spp < 100000 and finite and progressed, f"cancel: {report['cancel']}")
        print(f"veach {report['version']} from the prefix's site folder: render equal to the CLI's EXR bit for bit; "
              f"errors as exceptions; cancel after {spp} spp")
    return exit_code()


if __name__ == "__main__":
    sys.exit(main())

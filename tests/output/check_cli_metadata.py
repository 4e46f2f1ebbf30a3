#!/usr/bin/env python3
"""Image metadata, read back through OpenImageIO with its types:

- numbers are numbers: veach:spp, veach:spp_requested and veach:seed are int attributes and
  veach:render_seconds a float one in an EXR; text stays text (veach:complete, veach:integrator);
- `--attrib NAME VALUE` adds the user's attributes, typed the same way (42 an int, 1.5 a float,
  anything else a string), to EXR and, as text in the description, to JPEG; a name the writer
  owns (veach:*) or a NAME with '=' is a usage error (exit 1, one line);
- with adaptive sampling (--noise) veach:spp is what every pixel reached, beside veach:spp_mean
  and veach:spp_max, and these are the minimum, mean and maximum of the Sample Count pass
  (`--passes combined,samples`, Blender's "Sample Count" layer); --skip-existing takes such a
  complete image as done.
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np
import OpenImageIO as oiio

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
from check_report import check, exit_code  # noqa: E402


def render(veach, scene, out, *extra):
    return subprocess.run([veach, "render", scene, "-o", out, "--width", "32", "--spp", "16", "--integrator", "pt",
                           "-q", *extra], capture_output=True, text=True, timeout=300)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--veach", required=True)
    ap.add_argument("--scene", required=True)
    args = ap.parse_args()
    v, scene = args.veach, args.scene
    with tempfile.TemporaryDirectory(prefix="veach_metadata_") as tmp:
        exr, jpg = os.path.join(tmp, "a.exr"), os.path.join(tmp, "a.jpg")
        r = render(v, scene, exr, "-o", jpg, "--seed", "7", "--attrib", "shot", "42", "--attrib", "gain", "1.5",
                   "--attrib", "artist", "Ada Lovelace")
        check(r.returncode == 0, f"render with --attrib: {r.returncode} {r.stderr}")
        spec = oiio.ImageInput.open(exr).spec()
        types = {p.name: (str(p.type), p.value) for p in spec.extra_attribs}
        for name, want in (("veach:spp", ("int", 16)), ("veach:spp_requested", ("int", 16)), ("veach:seed", ("int", 7)),
                           ("shot", ("int", 42)), ("gain", ("float", 1.5)), ("artist", ("string", "Ada Lovelace")),
                           ("veach:complete", ("string", "yes")), ("veach:integrator", ("string", "pt"))):
            check(types.get(name) == want, f"{name}: {types.get(name)}, expected {want}")
        check(types.get("veach:render_seconds", ("",))[0] == "float", f"render_seconds: {types.get('veach:render_seconds')}")
        description = oiio.ImageInput.open(jpg).spec().get_string_attribute("ImageDescription")
        check("shot=42" in description and "artist=Ada Lovelace" in description, f"JPEG description: {description!r}")
        for bad in (["--attrib", "veach:spp", "3"], ["--attrib", "a=b", "3"]):
            r = render(v, scene, exr, *bad)
            check(r.returncode == 1 and "--attrib" in r.stderr and r.stderr.count("\n") == 1,
                  f"{' '.join(bad)}: {r.returncode} {r.stderr!r}")

        adaptive = os.path.join(tmp, "adaptive.exr")
        extra = ["--noise", "0.3", "--spp", "64", "--passes", "combined,samples"]
        r = render(v, scene, adaptive, *extra)
        check(r.returncode == 0, f"adaptive render: {r.returncode} {r.stderr}")
        inp = oiio.ImageInput.open(adaptive)
        spec = inp.spec()
        names = list(spec.channelnames)
        check("ViewLayer.Sample Count.X" in names, f"no Sample Count pass: {names}")
        pixels = inp.read_image(oiio.FLOAT)
        counts = pixels[..., names.index("ViewLayer.Sample Count.X")]
        lo, mean, hi = int(spec.getattribute("veach:spp")), float(spec.getattribute("veach:spp_mean")), \
            int(spec.getattribute("veach:spp_max"))
        check(lo == int(counts.min()) and hi == int(counts.max()) and abs(mean - float(counts.mean())) < 1e-3 * mean,
              f"veach:spp {lo}/{mean}/{hi} vs the Sample Count pass {counts.min()}/{counts.mean()}/{counts.max()}")
        check(lo < 64 and spec.getattribute("veach:spp_requested") == 64,
              f"adaptive sampling stopped no pixel early: veach:spp {lo}")
        r = subprocess.run([v, "render", scene, "-o", adaptive, "--width", "32", "--integrator", "pt",
                            "--skip-existing", *extra], capture_output=True, text=True, timeout=300)
        check(r.returncode == 0 and "skipped" in r.stderr, f"--skip-existing on a complete adaptive image: {r.stderr!r}")
    return exit_code("metadata: numbers as numbers, --attrib, veach:spp with --noise from the Sample Count pass")


if __name__ == "__main__":
    sys.exit(main())

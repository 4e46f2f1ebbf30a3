#!/usr/bin/python3
"""The installed tree works for a host: `cmake --install` into a temporary prefix, then
- libveach's SONAME carries the major version and it exports only the C API (veach* symbols);
- OpenImageIO is not linked into libveach but into the image module installed beside it:
  without the module a part file still renders and an image output fails before rendering;
- the installed `veach` command runs from the moved prefix and is a client of libveach through
  veach* symbols only (none of the renderer's libraries linked into it);
- examples/host-c (C11, through pkg-config) and examples/cmake-consumer (C++, through
  find_package(veach CONFIG)) build against the prefix alone and run;
- their PNGs are not black and their means agree with the `veach` command's PNG of the same
  render settings (the same library underneath: within 2%, a margin for 8-bit rounding only);
- a missing scene makes the C example exit 2 with the error message, not crash.
A sanitizer build does not register this test: plain hosts cannot load its library.
Usage: check_install.py --build BUILD_DIR --source SOURCE_DIR --veach VEACH_CLI
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile


def run(cmd, env=None, cwd=None, expect=0):
    p = subprocess.run(cmd, env=env, cwd=cwd, capture_output=True, text=True, timeout=300)
    if expect is not None and p.returncode != expect:
        sys.exit(f"FAIL: {' '.join(cmd)} exited {p.returncode} (expected {expect})\n{p.stdout}\n{p.stderr}")
    return p


def png_mean(path):
    import OpenImageIO as oiio
    buf = oiio.ImageBuf(path)
    if buf.has_error:
        sys.exit(f"FAIL: cannot read {path}: {buf.geterror()}")
    stats = oiio.ImageBufAlgo.computePixelStats(buf)
    return sum(stats.avg[:3]) / 3.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", required=True)
    ap.add_argument("--source", required=True)
    ap.add_argument("--veach", required=True)
    args = ap.parse_args()
    scene = os.path.join(args.source, "examples", "cornell", "cornell.gltf")
    width, spp = "64", "16"

    tmp = tempfile.mkdtemp(prefix="veach_install_")
    try:
        prefix = os.path.join(tmp, "prefix")
        run(["cmake", "--install", args.build, "--prefix", prefix])
        pcs = [os.path.join(d, f) for d, _, fs in os.walk(prefix) for f in fs if f == "veach.pc"]
        libs = [os.path.join(d, f) for d, _, fs in os.walk(prefix) for f in fs if f.startswith("libveach.so.")]
        for required in ("include/veach/veach.h", "include/veach/veach.hpp"):
            if not os.path.isfile(os.path.join(prefix, required)):
                sys.exit(f"FAIL: {required} not installed")
        if len(pcs) != 1 or not libs:
            sys.exit(f"FAIL: expected one veach.pc and libveach.so.* under {prefix}: {pcs} {libs}")
        libdir = os.path.dirname(libs[0])
        if "libasan" in run(["objdump", "-p", libs[0]]).stdout:
            # A sanitizer build's library needs the ASan runtime loaded first: a host built
            # without -fsanitize cannot load it. The gtest suite covers the API in that build.
            sys.exit("FAIL: libveach is built with AddressSanitizer (VEACH_SANITIZE); plain hosts cannot load it")

        soname = run(["objdump", "-p", libs[0]]).stdout
        if "SONAME               libveach.so.0" not in soname:
            sys.exit("FAIL: libveach's SONAME is not libveach.so.<major>")
        # OpenImageIO is opened on first use from the image module beside the library, never
        # linked: a process that reads and writes no image must not load its ~260 libraries.
        lib_needed = [l.split()[-1] for l in soname.splitlines() if "NEEDED" in l]
        if any(n.startswith("libOpenImageIO") for n in lib_needed):
            sys.exit(f"FAIL: libveach links OpenImageIO (it belongs in the image module): {lib_needed}")
        module = os.path.join(libdir, "libveach_image_io.so")
        if not os.path.isfile(module):
            sys.exit(f"FAIL: the image module is not installed beside libveach: {module}")
        exported = [l.split()[-1] for l in run(["nm", "-D", "--defined-only", libs[0]]).stdout.splitlines()
                    if l.split()[1:2] == ["T"]]
        leaked = [s for s in exported if not s.startswith("veach")]
        if leaked or len(exported) < 20:
            sys.exit(f"FAIL: libveach exports {len(exported)} functions, not only the C API: {leaked[:5]}")

        env = dict(os.environ, PKG_CONFIG_PATH=os.path.dirname(pcs[0]), LD_LIBRARY_PATH=libdir)
        flags = run(["pkg-config", "--cflags", "--libs", "veach"], env=env).stdout.split()
        host_c = os.path.join(tmp, "host-c")
        run(["cc", "-std=c11", "-Wall", "-Wextra", "-Werror", os.path.join(args.source, "examples/host-c/render.c"),
             *flags, "-o", host_c], env=env)
        consumer_build = os.path.join(tmp, "consumer")
        run(["cmake", "-S", os.path.join(args.source, "examples/cmake-consumer"), "-B", consumer_build,
             f"-DCMAKE_PREFIX_PATH={prefix}", "-DCMAKE_BUILD_TYPE=Release"], env=env)
        run(["cmake", "--build", consumer_build], env=env)

        outputs = {}
        outputs["host-c"] = os.path.join(tmp, "host_c.png")
        run([host_c, scene, outputs["host-c"], width, spp], env=env)
        outputs["cmake-consumer"] = os.path.join(tmp, "consumer.png")
        run([os.path.join(consumer_build, "veach_consumer"), scene, outputs["cmake-consumer"], width, spp], env=env)
        # The installed command is a client of libveach like the examples: it needs the library
        # (found through its relative RPATH, no LD_LIBRARY_PATH) and none of the renderer's own
        # dependencies, which live inside libveach.
        cli = os.path.join(prefix, "bin", "veach")
        needed = [l.split()[-1] for l in run(["objdump", "-p", cli]).stdout.splitlines() if "NEEDED" in l]
        if "libveach.so.0" not in needed or any(n.startswith(("libembree", "libOpenImageIO", "libOpenColorIO", "libtbb"))
                                                 for n in needed):
            sys.exit(f"FAIL: bin/veach should need libveach.so.0 and not the renderer's libraries: {needed}")
        undefined = [l.split()[-1].split("@")[0] for l in run(["nm", "-D", "--undefined-only", cli]).stdout.splitlines()]
        from_lib = [u for u in undefined if u.startswith("veach")]
        clean_env = {k: v for k, v in os.environ.items() if k != "LD_LIBRARY_PATH"}
        if len(from_lib) < 10 or any("veach" in u and not u.startswith("veach") for u in undefined):
            sys.exit(f"FAIL: bin/veach should use libveach through veach* symbols only: {undefined}")
        versions = {run([c, "--version"], env=clean_env).stdout.strip() for c in (cli, args.veach)}
        if len(versions) != 1:
            sys.exit(f"FAIL: the installed and the build tree's veach report different versions: {versions}")
        outputs["veach command"] = os.path.join(tmp, "cli.png")
        run([cli, "render", scene, "-o", outputs["veach command"], "--width", width, "--spp", spp,
             "--integrator", "pt", "--quiet"], env=clean_env)
        # Without the image module: a part (.vpart) still renders, since it needs no image
        # library; an image output fails with one line naming the module (checked before rendering).
        hidden = module + ".hidden"
        os.rename(module, hidden)
        try:
            run([cli, "render", scene, "-o", os.path.join(tmp, "part.vpart"), "--width", width, "--spp", spp,
                 "--samples", "0:2", "--quiet"], env=clean_env)
            p = run([cli, "render", scene, "-o", os.path.join(tmp, "nomodule.png"), "--width", width, "--spp", spp,
                     "--quiet"], env=clean_env, expect=None)
        finally:
            os.rename(hidden, module)
        lines = p.stderr.strip().splitlines()
        if p.returncode == 0 or len(lines) != 1 or "libveach_image_io.so" not in lines[0]:
            sys.exit(f"FAIL: a PNG without the image module should fail with one line naming it: "
                     f"exit {p.returncode}, {p.stderr!r}")
        if os.path.exists(os.path.join(tmp, "nomodule.png")):
            sys.exit("FAIL: a PNG was written without the image module")
        missing = run([host_c, os.path.join(tmp, "missing.gltf"), os.path.join(tmp, "x.png")], env=env, expect=2)
        if "missing.gltf" not in missing.stderr:
            sys.exit(f"FAIL: the error for a missing scene does not name it: {missing.stderr}")

        means = {k: png_mean(v) for k, v in outputs.items()}
        print("PNG means:", ", ".join(f"{k} {v:.4f}" for k, v in means.items()))
        reference = means["veach command"]
        if not 0.05 < reference < 0.95:
            sys.exit(f"FAIL: the CLI's Cornell PNG mean {reference:.4f} is not a lit, unsaturated box")
        for k, v in means.items():
            if abs(v - reference) > 0.02 * reference:
                sys.exit(f"FAIL: {k} PNG mean {v:.4f} differs from the CLI's {reference:.4f} by more than 2%")
        print("PASS: installed tree, both examples and the CLI agree")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()

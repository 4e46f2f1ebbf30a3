#!/usr/bin/python3
"""The `veach` command under interruption, and its output files.

What must hold:
- SIGTERM, SIGINT and SIGHUP stop sampling: exit 130, the image written as it stands, its
  veach:spp the samples per pixel every pixel completed (fewer than asked, at least one), and
  no file under the final name while the render runs.
- A render killed with SIGKILL after a checkpoint and resumed with --resume equals the
  uninterrupted render bit for bit (path tracing, and the default integrator, which chooses its
  strategies again on resuming), passes and filter included; the checkpoint is
  removed once the image is written.
- --skip-existing leaves a complete output of the same spp alone.
- Every format is read back through OpenImageIO with its metadata; a multi-layer EXR holds
  Blender's channel names.
- Every flag goes through the C API (the command links only libveach): bad values are still one
  usage line (exit 1) or, when only the scene can judge them, one bad-input line (exit 2);
  --noise reaches the integrator (fewer rays, the same mean); `veach color` lists the config.
Exit 0 pass, 1 fail (also when the OpenImageIO Python module is missing: install-deps.sh installs it).
"""
import argparse
import json
import os
import signal
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
from check_report import FAILURES, check, import_numpy_oiio  # noqa: E402

np, oiio = import_numpy_oiio()


def read(path):
    buf = oiio.ImageBuf(path)
    if buf.has_error:
        raise RuntimeError(f"{path}: {buf.geterror()}")
    return buf.spec(), buf.get_pixels(oiio.FLOAT)


def wait_for(predicate, timeout, proc=None):
    end = time.time() + timeout
    while time.time() < end:
        if predicate():
            return True
        if proc is not None and proc.poll() is not None:
            return predicate()
        time.sleep(0.02)
    return False


def checkpoint_spp(path):
    """The spp a checkpoint holds (its header: magic, version, width, height, aovs, spp), -1 if none."""
    try:
        with open(path, "rb") as f:
            header = f.read(40)
    except OSError:
        return -1
    if len(header) < 40 or header[:8] != b"VEACHCK3":
        return -1
    return int.from_bytes(header[36:40], sys.byteorder, signed=True)


def interrupted_by(veach, scene, folder, sig):
    """Starts a long render, sends `sig` once a pass has completed, checks the image."""
    out = os.path.join(folder, f"sig{int(sig)}.exr")
    requested = 100000
    proc = subprocess.Popen([veach, "render", scene, "-o", out, "--width", "40", "--spp", str(requested),
                             "--integrator", "pt", "--threads", "2"],
                            stderr=subprocess.PIPE, text=True)
    # Non-terminal progress prints a line as the render starts ("ETA -": no pass yet), then one per
    # finished pass: the first with an ETA means spp >= 1.
    line = proc.stderr.readline()
    while line.startswith("Progress:") and line.rstrip().endswith("ETA -"):
        line = proc.stderr.readline()
    check(line.startswith("Progress:"), f"{sig.name}: expected a progress line, got {line!r}")
    time.sleep(0.2)
    check(not os.path.exists(out), f"{sig.name}: {out} exists before the render finished")
    proc.send_signal(sig)
    try:
        _, err = proc.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        proc.kill()
        check(False, f"{sig.name}: the render did not stop within 30 s")
        return
    check(proc.returncode == 130, f"{sig.name}: exit code {proc.returncode}, expected 130 ({err.strip()})")
    if not check(os.path.exists(out), f"{sig.name}: no image written after the signal"):
        return
    spec, pixels = read(out)
    spp = spec.getattribute("veach:spp") or -1  # an int attribute in EXR
    check(1 <= spp < requested, f"{sig.name}: veach:spp {spp} should be in [1, {requested})")
    check(spec.get_string_attribute("veach:complete") == "no", f"{sig.name}: veach:complete should be 'no'")
    check(np.isfinite(pixels).all() and pixels[..., :3].mean() > 0, f"{sig.name}: the image is not a render")
    leftovers = [n for n in os.listdir(folder) if n.startswith(".")]
    check(not leftovers, f"{sig.name}: temporary files left behind: {leftovers}")
    print(f"{sig.name}: exit 130, {spp} of {requested} spp written")


def checkpoint_kill_resume(veach, scene, folder, integrator="pt"):
    common = ["--width", "32", "--spp", "64", "--integrator", integrator, "--seed", "3", "--filter", "blackman-harris",
              "--passes", "combined,depth,normal,albedo,variance", "-q"]
    ref = os.path.join(folder, "ref.exr")
    subprocess.run([veach, "render", scene, "-o", ref, "--threads", "2"] + common, check=True)
    out = os.path.join(folder, "killed.exr")
    state = out + ".checkpoint"
    proc = subprocess.Popen([veach, "render", scene, "-o", out, "--threads", "1", "--checkpoint", "0"] + common)
    # Kill once the checkpoint holds 7 spp or more (passes of 1, 2, 4, 8, 16...: resuming then
    # starts inside the pass schedule, not at its beginning).
    appeared = wait_for(lambda: checkpoint_spp(state) >= 7, 30, proc)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    if not check(appeared and proc.returncode == -signal.SIGKILL,
                 f"checkpoint: expected a checkpoint before SIGKILL (rc {proc.returncode})"):
        return
    check(not os.path.exists(out), "checkpoint: the killed render left an image under the final name")
    r = subprocess.run([veach, "render", scene, "-o", out, "--threads", "2", "--checkpoint", "0", "--resume"] + common,
                       stderr=subprocess.PIPE, text=True)
    if not check(r.returncode == 0, f"checkpoint: resume failed ({r.returncode}): {r.stderr.strip()}"):
        return
    spec_ref, a = read(ref)
    spec, b = read(out)
    resumed = spec.getattribute("veach:resumed_spp") or 0
    check(resumed >= 7, f"checkpoint: the resumed render started from {resumed} spp, not the checkpoint's")
    check(spec.getattribute("veach:spp") == 64, "checkpoint: the resumed render should reach 64 spp")
    check(list(spec.channelnames) == list(spec_ref.channelnames), "checkpoint: different channels")
    check(a.shape == b.shape and np.array_equal(a, b),
          f"checkpoint: resumed render differs from the uninterrupted one "
          f"(max |diff| {np.abs(a - b).max() if a.shape == b.shape else 'shape'})")
    check(not os.path.exists(state), "checkpoint: the state file should be removed after the image is written")
    print(f"checkpoint + SIGKILL + resume from {resumed} spp: bit-identical to the uninterrupted render")

    # A damaged checkpoint is refused: exit 2, one line naming it.
    with open(state, "wb") as f:
        f.write(b"VEACHCK1 but not really")
    r = subprocess.run([veach, "render", scene, "-o", out, "--resume"] + common, stderr=subprocess.PIPE, text=True)
    check(r.returncode == 2 and state in r.stderr and r.stderr.count("\n") == 1,
          f"checkpoint: a corrupt checkpoint should give exit 2 and one line naming it, got {r.returncode}: {r.stderr!r}")
    os.remove(state)


def skip_existing(veach, scene, folder):
    out = os.path.join(folder, "ref.exr")
    before = os.stat(out).st_mtime_ns
    # ref.exr is complete at --spp 64 (checkpoint_kill_resume): the same spp is skipped (what a
    # complete output is, and what is rendered again, is tests/farm/check_farm_safe.py's).
    r = subprocess.run([veach, "render", scene, "-o", out, "--width", "8", "--spp", "64", "--skip-existing"],
                       stderr=subprocess.PIPE, text=True)
    check(r.returncode == 0 and "skipped" in r.stderr, f"--skip-existing: {r.returncode} {r.stderr!r}")
    check(os.stat(out).st_mtime_ns == before, "--skip-existing rewrote the output")
    fresh = os.path.join(folder, "fresh.png")
    r = subprocess.run([veach, "render", scene, "-o", fresh, "--width", "8", "--spp", "1", "--skip-existing", "-q"])
    check(r.returncode == 0 and os.path.exists(fresh), "--skip-existing must still render missing outputs")


def formats_and_metadata(veach, scene, folder):
    outs = [os.path.join(folder, "m." + e) for e in ("exr", "png", "jpg", "tif", "hdr")]
    cmd = [veach, "render", scene, "--width", "24", "--spp", "2", "--integrator", "pt", "--seed", "9", "-q",
           "--exr-codec", "piz"]
    for o in outs:
        cmd += ["-o", o]
    subprocess.run(cmd, check=True)
    expected = {"veach:spp": "2", "veach:seed": "9", "veach:integrator": "pt", "veach:camera": "Camera",
                "veach:scene": scene, "veach:spp_requested": "2", "veach:complete": "yes", "veach:filter": "box 1"}
    for o in outs:
        spec, pixels = read(o)
        check(pixels.shape[:2] == (24, 24), f"{o}: size {pixels.shape}")
        software = spec.get_string_attribute("Software")
        if o.endswith(".hdr"):
            # Radiance RGBE headers as OpenImageIO reads them carry no attributes: checked as text.
            with open(o, "rb") as f:
                header = f.read(4096).split(b"\n\n")[0].decode("latin-1")
            for k, v in expected.items():
                check(f"{k}={v}" in header, f"{o}: header lacks {k}={v}")
            continue
        check(software.startswith("veach "), f"{o}: Software {software!r}")
        keys = spec.get_string_attribute("ImageDescription") if o[-3:] in ("jpg", "tif") else None
        for k, v in expected.items():
            got = spec.getattribute(k)  # EXR: numbers as int attributes; PNG: text
            got = "" if got is None else str(got)
            if keys is not None:
                check(f"{k}={v}" in keys, f"{o}: ImageDescription lacks {k}={v}")
            else:
                check(got == v, f"{o}: {k} = {got!r}, expected {v!r}")
        seconds = spec.getattribute("veach:render_seconds") if keys is None else keys
        check(bool(seconds) and "render_seconds" in (keys or "veach:render_seconds"), f"{o}: no render seconds")
    spec, _ = read(outs[0])
    check(spec.get_string_attribute("compression") == "piz", "EXR: --exr-codec piz not applied")

    # Multi-layer EXR: Blender's names, one pass each.
    ml = os.path.join(folder, "layers.exr")
    subprocess.run([veach, "render", scene, "-o", ml, "--width", "16", "--spp", "2", "-q", "--half",
                    "--passes", "combined,depth,normal,albedo,variance"], check=True)
    spec, px = read(ml)
    want = {"ViewLayer.Combined." + c for c in "RGBA"} | {"ViewLayer.Depth.Z"} | \
           {"ViewLayer.Normal." + c for c in "XYZ"} | {"ViewLayer.Albedo." + c for c in "RGB"} | \
           {"ViewLayer.Variance." + c for c in "RGB"}
    check(set(spec.channelnames) == want, f"multi-layer EXR channels {list(spec.channelnames)}")
    names = list(spec.channelnames)
    z = px[..., names.index("ViewLayer.Depth.Z")]
    check(spec.channelformat(names.index("ViewLayer.Depth.Z")) == oiio.FLOAT, "Depth should stay float with --half")
    check(((z > 0) & (z < 100)).any() and (z == 1e10).any() | ((z > 0) & (z < 100)).all(), "Depth values")
    alpha = px[..., names.index("ViewLayer.Combined.A")]
    check(np.all(alpha == 1.0), "Combined alpha should be 1")
    print("formats: exr png jpg tif hdr read back with metadata; multi-layer EXR channel names as Blender's")


def flags_through_the_api(veach, scene, folder):
    """The command is a client of the C API: every value is checked by the library (on a probe
    render), yet a bad one is still the command's usage error (exit 1, one line naming the flag),
    and a value only the scene can judge is bad input (exit 2, one line)."""
    def run(*extra):
        return subprocess.run([veach, "render", scene, "-o", os.path.join(folder, "f.exr"), "--width", "16",
                               "--spp", "1", "-q", *extra], stderr=subprocess.PIPE, text=True)
    for extra, rc, words in [(["--filter", "lanczos"], 1, "--filter expects box, gaussian or blackman-harris"),
                             (["--exr-codec", "zip:10"], 1, "--exr-codec expects"),
                             (["--passes", "combined,glossy"], 1, "unknown pass 'glossy'"),
                             (["--sampler", "halton"], 1, "--sampler expects sobol or random"),
                             (["--spot-falloff", "cone"], 1, "--spot-falloff expects auto, blender or gltf"),
                             (["--integrator", "magic"], 1, "unknown integrator 'magic'"),
                             (["--noise", "-1"], 1, "--noise expects a number"),
                             (["--env-color", "1,2"], 1, "--env-color expects R,G,B"),
                             (["--camera", "nope"], 2, "no camera 'nope'"),
                             (["--variant", "nope"], 2, "no material variant 'nope'"),
                             (["--env", os.path.join(folder, "missing.hdr")], 2, "missing.hdr")]:
        r = run(*extra)
        check(r.returncode == rc and words in r.stderr and r.stderr.count("\n") == 1,
              f"{' '.join(extra)}: expected exit {rc} and one line with {words!r}, got {r.returncode}: {r.stderr!r}")

    # --noise reaches the integrator: with a loose target most pixels stop after the pilot, so
    # the render traces fewer rays than the same render without it, and stays unbiased (the
    # image means agree within 5%, about 5 standard errors of the 32x32 mean at these counts).
    rays, means = {}, {}
    for name, extra in (("plain", []), ("adaptive", ["--noise", "0.5"])):
        out, stats = os.path.join(folder, name + ".exr"), os.path.join(folder, name + ".json")
        subprocess.run([veach, "render", scene, "-o", out, "--width", "32", "--spp", "64", "--integrator", "pt",
                        "-q", "--stats-json", stats, *extra], check=True)
        rays[name] = json.load(open(stats))["rays"]
        means[name] = float(read(out)[1][..., :3].mean())
    check(rays["adaptive"] < 0.8 * rays["plain"], f"--noise 0.5 should save rays: {rays}")
    check(abs(means["adaptive"] - means["plain"]) < 0.05 * means["plain"], f"--noise changed the mean: {means}")

    r = subprocess.run([veach, "color"], stdout=subprocess.PIPE, text=True)
    check(r.returncode == 0 and r.stdout.startswith("config: ") and "views:" in r.stdout,
          f"veach color: {r.returncode} {r.stdout!r}")
    print(f"flags: usage errors from the library's checks; --noise rays {rays['adaptive']} vs {rays['plain']}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--veach", required=True)
    ap.add_argument("--scene", required=True)
    args = ap.parse_args()
    scene = os.path.abspath(args.scene)
    with tempfile.TemporaryDirectory(prefix="veach_cli_output_") as folder:
        for sig in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP):
            interrupted_by(args.veach, scene, folder, sig)
        t = time.time()
        checkpoint_kill_resume(args.veach, scene, folder)
        # The default integrator chooses its strategies again when it resumes: the same choice.
        auto_folder = os.path.join(folder, "auto")
        os.makedirs(auto_folder)
        checkpoint_kill_resume(args.veach, scene, auto_folder, "auto")
        skip_existing(args.veach, scene, folder)
        formats_and_metadata(args.veach, scene, folder)
        flags_through_the_api(args.veach, scene, folder)
        print(f"({time.time() - t:.1f} s for checkpoints and formats)")
    if FAILURES:
        print(f"{len(FAILURES)} failure(s)")
        return 1
    print("all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())

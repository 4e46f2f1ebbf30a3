#!/usr/bin/env python3
"""The `veach` command's flags are the library's options table (tests/api's
test_option_table_api.cpp holds the API's side):

- every option with a flag round-trips: without the flag the library holds the table's default
  (read back through the C API by `veach render ... --dry-run`); the range's ends given as
  `--flag=VALUE` and `--flag VALUE` read back exactly; one step beyond either end is a usage
  error (exit 1, one line naming the flag); every name of a fixed list is taken, another is
  refused; a switch sets 1;
- README's option reference is `veach options --markdown`, character for character;
- CLI11 behaviours: `-h`/`--help` and `--version` after any subcommand, a suggestion for a
  mistyped flag and command, pbrt-v4's `--nthreads` and `--outfile`, `--config` presets in TOML
  and INI (the command line's own flags win), an unreadable config is bad input (exit 2);
- every JSON the command writes parses with python's json (`veach options --json`, `--dry-run`,
  `--stats-json`); the stats carry version, complete, spp and spp_requested, the outputs written
  and the threads the render ran on, and a scene whose file name holds a quote, a backslash, a
  newline and a byte that is not UTF-8 is still valid JSON (the name kept, the byte replaced).
"""
import shutil
import argparse
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
from check_report import check, exit_code  # noqa: E402


def run(veach, *args):
    return subprocess.run([veach, *args], capture_output=True, text=True, timeout=60)


def dry_run(veach, scene, out, *extra):
    r = run(veach, "render", scene, "-o", out, "--dry-run", *extra)
    if not check(r.returncode == 0, f"--dry-run {' '.join(extra)}: exit {r.returncode}: {r.stderr.strip()}"):
        return None
    return json.loads(r.stdout)


def text(value):
    """A number as a flag would be given it (exactly: repr round-trips a double)."""
    return str(value) if isinstance(value, int) else repr(float(value))


def round_trip(veach, scene, out, table):
    defaults = dry_run(veach, scene, out)
    checked = 0
    for row in table:
        if not row["flag"]:
            continue
        name, flag, obj = row["name"], row["flag"], row["object"]
        held = defaults[obj][name]
        check(held == row["default"], f"{flag}: default {held!r}, the table says {row['default']!r}")
        if row["switch"]:
            got = dry_run(veach, scene, out, flag)
            check(got is not None and got[obj][name] == 1, f"{flag}: the switch should set 1")
            checked += 1
            continue
        if row["type"] in ("int", "float"):
            lo, hi = row["min"], row["max"]
            for end, form in ((lo, "="), (hi, " ")):
                args = [f"{flag}={text(end)}"] if form == "=" else [flag, text(end)]
                got = dry_run(veach, scene, out, *args)
                if got is None:
                    continue
                value = got[obj][name]
                if row["type"] == "int":
                    check(value == end, f"{' '.join(args)}: read back {value!r}")
                else:  # stored as a float or a double
                    check(abs(value - end) <= abs(end) * 1e-7, f"{' '.join(args)}: read back {value!r}")
            step = 1 if row["type"] == "int" else max(1e-3, abs(hi) * 1e-3)
            for beyond in (lo - (1 if row["type"] == "int" else max(1e-3, abs(lo) * 1e-3)), hi + step):
                r = run(veach, "render", scene, "-o", out, "--dry-run", f"{flag}={text(beyond)}")
                check(r.returncode == 1 and flag in r.stderr and r.stderr.count("\n") == 1,
                      f"{flag}={text(beyond)}: expected exit 1 and one line naming {flag}, got "
                      f"{r.returncode}: {r.stderr!r}")
        elif "choices" in row:
            for choice in row["choices"]:
                got = dry_run(veach, scene, out, flag, choice)
                check(got is not None and got[obj][name] == choice, f"{flag} {choice}: not read back")
            r = run(veach, "render", scene, "-o", out, "--dry-run", flag, "no-such-name")
            check(r.returncode == 1 and flag in r.stderr and r.stderr.count("\n") == 1,
                  f"{flag} no-such-name: exit {r.returncode}: {r.stderr!r}")
        checked += 1
    check(checked >= 30, f"only {checked} flags checked")
    print(f"round trip: {checked} flags, defaults and ranges as the table's")


def readme_reference(veach, readme):
    r = run(veach, "options", "--markdown")
    content = open(readme, encoding="utf-8").read()
    begin, end = "<!-- options:begin -->\n", "<!-- options:end -->"
    if not check(begin in content and end in content, "README has no option reference markers"):
        return
    held = content[content.index(begin) + len(begin):content.index(end)]
    check(held == r.stdout, "README's option reference is not `veach options --markdown`; regenerate it:\n" +
          r.stdout)
    print("README's option reference is the table's")


def cli11_behaviours(veach, scene, out, folder):
    version = run(veach, "--version").stdout.strip()
    check(version.startswith("veach "), f"--version: {version!r}")
    for sub in ("render", "merge", "color", "options"):
        r = run(veach, sub, "--version")
        check(r.returncode == 0 and r.stdout.strip() == version, f"{sub} --version: {r.returncode} {r.stdout!r}")
    for args in (["render", "-h"], ["render", "--help"], ["render", scene, "--spp", "4", "--help"]):
        r = run(veach, *args)
        check(r.returncode == 0 and "--spp" in r.stdout and "--max-depth" in r.stdout,
              f"{' '.join(args)}: {r.returncode} {r.stdout[:200]!r}")
    r = run(veach, "merge", "-h")
    check(r.returncode == 0 and "--expect-spp" in r.stdout, f"merge -h: {r.returncode}")
    r = run(veach, "render", scene, "-o", out, "--sp", "16")
    check(r.returncode == 1 and "did you mean '--spp'" in r.stderr and r.stderr.count("\n") == 1,
          f"--sp: {r.returncode} {r.stderr!r}")
    r = run(veach, "rendr", scene)
    check(r.returncode == 1 and "did you mean 'render'" in r.stderr, f"rendr: {r.returncode} {r.stderr!r}")
    r = run(veach)
    check(r.returncode == 1 and "usage" in r.stderr, f"no arguments: {r.returncode} {r.stderr!r}")
    a = dry_run(veach, scene, out, "--spp=16", "--nthreads", "3")
    b = dry_run(veach, scene, out, "--spp", "16", "--threads=3")
    check(a == b and a["render"]["spp"] == 16 and a["render"]["threads"] == 3, f"--spp=16 / --nthreads: {a} {b}")
    # A flag given twice takes its last value, the command's own flags too (a farm template appends
    # the user's flags after its own: veach-part.sbatch's --checkpoint 60 before the user's --checkpoint 0).
    got = dry_run(veach, scene, out, "--spp", "4", "--checkpoint", "60", "--resume", "--checkpoint", "0",
                  "--frame", "1", "--frame", "2", "-q", "-q", "--spp", "8")
    check(got is not None and got["render"]["spp"] == 8, f"a flag given twice: {got and got['render']['spp']}")
    c = run(veach, "render", scene, "--outfile", out, "--dry-run")
    check(c.returncode == 0 and json.loads(c.stdout)["outputs"] == [out], f"--outfile: {c.returncode} {c.stderr}")
    # Presets for farms: a TOML and an INI file; the command line's own flags win.
    toml = os.path.join(folder, "preset.toml")
    with open(toml, "w") as f:
        f.write('spp = 32\nintegrator = "pt"\nmax_depth = 5\ntransparent = true\n')
    ini = os.path.join(folder, "preset.ini")
    with open(ini, "w") as f:
        f.write("[render]\nspp=24\nfilter=gaussian\n")
    got = dry_run(veach, scene, out, "--config", toml, "--spp", "8")
    check(got is not None and got["render"]["spp"] == 8 and got["render"]["integrator"] == "pt" and
          got["render"]["max_depth"] == 5 and got["render"]["transparent"] == 1, f"TOML preset: {got}")
    got = dry_run(veach, scene, out, f"--config={ini}")
    check(got is not None and got["render"]["spp"] == 24 and got["render"]["filter"] == "gaussian" and
          got["render"]["filter_width"] == 1.5, f"INI preset: {got}")
    bad = os.path.join(folder, "typo.toml")
    with open(bad, "w") as f:
        f.write("sppp = 3\n")
    r = run(veach, "render", scene, "-o", out, "--config", bad)
    check(r.returncode == 1 and "did you mean '--spp'" in r.stderr, f"config typo: {r.returncode} {r.stderr!r}")
    r = run(veach, "render", scene, "-o", out, "--config", os.path.join(folder, "missing.toml"))
    check(r.returncode == 2 and "missing.toml" in r.stderr and r.stderr.count("\n") == 1,
          f"missing config: {r.returncode} {r.stderr!r}")
    print("CLI11: --opt=value, -h and --version after subcommands, suggestions, aliases, TOML and INI presets")


def stats_json(veach, scene, folder):
    odd = os.path.join(folder.encode(), b'odd "name" \\ \n \xff.gltf')
    shutil.copy(scene, odd)
    for name in ("cornell.bin",):
        src = os.path.join(os.path.dirname(scene), name)
        if os.path.exists(src):
            shutil.copy(src, os.path.join(folder, name))
    stats, out = os.path.join(folder, "stats.json"), os.path.join(folder, "stats.exr")
    r = subprocess.run([veach.encode(), b"render", odd, b"-o", out.encode(), b"--width", b"16", b"--spp", b"2",
                        b"--threads", b"2", b"-q", b"--stats-json", stats.encode()], capture_output=True, timeout=120)
    if not check(r.returncode == 0, f"odd file name: exit {r.returncode}: {r.stderr!r}"):
        return
    s = json.load(open(stats, encoding="utf-8"))
    check(s["input"] == odd.decode("utf-8", errors="replace"), f"input {s['input']!r}")
    check(s["version"] == run(veach, "--version").stdout.split()[1], f"version {s['version']!r}")
    check(s["complete"] is True and s["spp"] == 2 and s["spp_requested"] == 2, f"complete/spp: {s}")
    check(s["outputs"] == [out] and s["threads"] == 2 and s["width"] == 16, f"outputs/threads/width: {s}")
    check(isinstance(s["seconds"]["total"], float) and isinstance(s["features"], list), f"types: {s}")
    # A render stopped short of its samples by the time limit says so.
    r = subprocess.run([veach, "render", scene, "-o", out, "--width", "16", "--spp", "1000000", "--time", "0.5", "-q",
                        "--stats-json", stats], capture_output=True, text=True, timeout=120)
    s = json.load(open(stats))
    check(r.returncode == 0 and s["complete"] is False and s["spp"] < s["spp_requested"] == 1000000,
          f"time-limited stats: {r.returncode} {s}")
    print("stats JSON: escaped names, complete, spp_requested, outputs, version, threads")


def preview_every(veach, scene, folder):
    """--preview-every 0 FILE: the film so far written while rendering, an ordinary image tagged
    incomplete; the final output is written as ever."""
    import OpenImageIO as oiio
    import numpy as np
    preview, out = os.path.join(folder, "preview.exr"), os.path.join(folder, "final.exr")
    r = run(veach, "render", scene, "-o", out, "--width", "48", "--spp", "512", "--integrator", "pt", "-q",
            "--preview-every", "0", preview)
    if not check(r.returncode == 0 and os.path.exists(preview), f"--preview-every: exit {r.returncode} "
                 f"{r.stderr!r}, preview written: {os.path.exists(preview)}"):
        return
    buf = oiio.ImageBuf(preview)
    spec = buf.spec()
    spp = spec.getattribute("veach:spp")  # an int attribute
    check(spec.get_string_attribute("veach:complete") == "no" and isinstance(spp, int) and 0 < spp <= 512,
          f"preview metadata: complete {spec.get_string_attribute('veach:complete')!r}, spp {spp}")
    check(bool(np.isfinite(buf.get_pixels(oiio.FLOAT)).all()), "preview pixels not finite")
    check(not [f for f in os.listdir(folder) if f.startswith(".preview") or ".tmp" in f], "temporary files left")
    r = run(veach, "render", scene, "-o", out, "--preview-every", "1", os.path.join(folder, "p.vpart"))
    check(r.returncode == 1 and "--preview-every" in r.stderr, f"--preview-every to a .vpart: {r.returncode}")
    print(f"--preview-every: the film so far at {spp} spp, tagged incomplete")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--veach", required=True)
    ap.add_argument("--scene", required=True)
    ap.add_argument("--readme", required=True)
    args = ap.parse_args()
    r = run(args.veach, "options", "--json")
    check(r.returncode == 0, f"veach options --json: exit {r.returncode}")
    table = json.loads(r.stdout)
    with tempfile.TemporaryDirectory(prefix="veach_cli_options_") as folder:
        out = os.path.join(folder, "out.exr")
        round_trip(args.veach, args.scene, out, table)
        readme_reference(args.veach, args.readme)
        cli11_behaviours(args.veach, args.scene, out, folder)
        stats_json(args.veach, args.scene, folder)
        preview_every(args.veach, args.scene, folder)
    return exit_code("all passed")


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""The default thread count under a real cgroup CPU quota, as a farm node's share sets it.

What must hold: `veach render` started inside a cgroup whose CPU quota allows half a CPU runs
on one thread (a quota rounds up to whole threads, at least one), also when the quota is set on
the parent and the process sits in a child without one (a parent's quota bounds its children);
with a quota of one and a half CPUs it runs on two (or on the affinity mask's CPUs, if fewer).
The thread count is what --stats-json reports the render ran on.

The cgroups are made for the test under the process's own cgroup, in whichever hierarchy holds
the cpu controller: cgroup v2 (cpu.max) where the cpu controller is on the unified hierarchy,
else cgroup v1 (cpu.cfs_quota_us / cpu.cfs_period_us); they are removed afterwards. It needs
root and a writable cgroup filesystem: without them it exits 77 (CTest: skipped) saying why.
Exit 0 pass, 1 fail.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
from check_report import FAILURES, check  # noqa: E402

SKIP = 77


def own_path(v2):
    """This process's cgroup path: the v2 line, or the v1 line whose controllers include cpu."""
    for line in open("/proc/self/cgroup"):
        ident, controllers, path = line.rstrip("\n").split(":", 2)
        if (v2 and ident == "0" and controllers == "") or (not v2 and "cpu" in controllers.split(",")):
            return path
    return None


def find_hierarchy():
    """(kind, folder of this process's cgroup) for the hierarchy with the cpu controller, or
    (None, reason)."""
    for mount in ("/sys/fs/cgroup", "/sys/fs/cgroup/unified"):
        controllers = os.path.join(mount, "cgroup.controllers")
        if os.path.exists(controllers) and "cpu" in open(controllers).read().split():
            path = own_path(True)
            if path is not None:
                return "v2", mount + (path if path != "/" else "")
    for mount in ("/sys/fs/cgroup/cpu", "/sys/fs/cgroup/cpu,cpuacct"):
        if os.path.exists(os.path.join(mount, "cpu.cfs_quota_us")):
            path = own_path(False)
            folder = mount + (path if path and path != "/" else "")
            if os.path.exists(os.path.join(folder, "cpu.cfs_quota_us")):
                return "v1", folder
            return "v1", mount
    return None, "no cgroup hierarchy with the cpu controller is mounted"


def write(path, text):
    with open(path, "w") as f:
        f.write(text)


def set_quota(kind, folder, cpus):
    period = 100000
    if kind == "v2":
        write(os.path.join(folder, "cpu.max"), f"{int(cpus * period)} {period}")
    else:
        write(os.path.join(folder, "cpu.cfs_period_us"), str(period))
        write(os.path.join(folder, "cpu.cfs_quota_us"), str(int(cpus * period)))


def threads_inside(veach, scene, folder, tmp):
    """The threads a default render reports when started as a member of cgroup `folder`."""
    stats = os.path.join(tmp, "stats.json")
    if os.path.exists(stats):
        os.remove(stats)

    def join():
        write(os.path.join(folder, "cgroup.procs"), str(os.getpid()))

    r = subprocess.run([veach, "render", scene, "-o", os.path.join(tmp, "t.exr"), "--width", "16", "--height", "16",
                        "--spp", "1", "--integrator", "pt", "-q", "--stats-json", stats],
                       capture_output=True, text=True, timeout=120, preexec_fn=join)
    if not check(r.returncode == 0, f"render in {folder}: exit {r.returncode} ({r.stderr.strip()})"):
        return None
    return json.load(open(stats))["threads"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--veach", required=True)
    ap.add_argument("--scene", required=True)
    args = ap.parse_args()
    if os.geteuid() != 0:
        print("SKIP: creating cgroups needs root")
        return SKIP
    kind, base = find_hierarchy()
    if kind is None:
        print(f"SKIP: {base}")
        return SKIP
    outer = os.path.join(base, f"veach-test-{os.getpid()}")
    inner = os.path.join(outer, "task")
    made = []
    try:
        try:
            os.mkdir(outer)
            made.append(outer)
            if kind == "v2":  # children get the cpu controller from their parent's subtree_control
                write(os.path.join(outer, "cgroup.subtree_control"), "+cpu")
            os.mkdir(inner)
            made.append(inner)
        except OSError as e:
            print(f"SKIP: cannot create a cgroup under {base} ({e})")
            return SKIP
        print(f"cgroup {kind}: {outer}")
        allowed = len(os.sched_getaffinity(0))
        with tempfile.TemporaryDirectory() as tmp:
            set_quota(kind, outer, 0.5)
            got = threads_inside(args.veach, args.scene, outer, tmp)
            check(got == 1, f"quota of 0.5 CPU: the render ran on {got} threads, not 1")
            got = threads_inside(args.veach, args.scene, inner, tmp)
            check(got == 1, f"quota of 0.5 CPU on the parent: the render in its child ran on {got} threads, not 1")
            set_quota(kind, outer, 1.5)
            got = threads_inside(args.veach, args.scene, outer, tmp)
            check(got == min(2, allowed), f"quota of 1.5 CPUs: the render ran on {got} threads, not {min(2, allowed)}")
        print(f"threads under quotas of 0.5 (own, parent's) and 1.5 CPUs with {allowed} CPUs in the mask: checked")
    finally:
        for folder in reversed(made):
            try:
                os.rmdir(folder)
            except OSError as e:
                check(False, f"cannot remove {folder}: {e}")
    if FAILURES:
        print(f"{len(FAILURES)} failure(s)")
        return 1
    print("cgroup CPU quota: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""Veach on a real single-node Slurm cluster, started here as root in a private folder.

munged runs with its own key and socket, slurmctld and slurmd with a generated slurm.conf
(localhost with this machine's CPUs and memory, proctrack/linuxproc, task/none, no accounting,
MailProg=/bin/true; PID 1 is not systemd, so the daemons are started by hand, in the foreground,
and the node name is given to slurmd). Then plugins/slurm/veach-slurm submits:
- an array of 4 sample-range parts of cornell and a dependent merge: the merged image equals a
  single render bit for bit with pt, and to relative 1e-6 with bdpt (splat summation order);
- a 2x2 tile split likewise: pt bit for bit, bdpt to relative 1e-6;
- a sequence, frames 7-8 of an animated scene x 2 sample chunks in one array ($SLURM_ARRAY_TASK_ID
  decoded to frame and chunk) and a merge per frame: each merged frame, written through a
  {frame} and a #### output, is bit for bit that frame rendered alone (`veach render SCENE
  --frame N`); --frames with an output that has no frame pattern is refused before submitting;
- a render whose parts fail: the merge job ends CANCELLED (--kill-on-invalid-dep=yes), it is not
  left PENDING;
- a part preempted mid-render (`scontrol requeue` once its first checkpoint exists) runs again,
  continues from its checkpoint (its second run's first progress line is past 0%), and the merge
  is the single render bit for bit.
The daemons are stopped by their PIDs and every wait is bounded.
Exit 0 pass, 1 fail (also when Slurm or munge is missing: scripts/install-deps.sh installs them).
"""
import argparse
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
from check_report import FAILURES, check, import_numpy_oiio  # noqa: E402

np, oiio = import_numpy_oiio()

PROGRAMS = ["munged", "mungekey", "slurmctld", "slurmd", "sbatch", "scontrol", "sinfo"]


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_for(predicate, timeout, what):
    end = time.time() + timeout
    while time.time() < end:
        if predicate():
            return True
        time.sleep(0.25)
    raise RuntimeError(f"timed out after {timeout}s waiting for {what}")


def memory_mb():
    with open("/proc/meminfo") as f:
        for line in f:
            if line.startswith("MemTotal:"):
                return int(line.split()[1]) // 1024
    return 1024


class Cluster:
    def __init__(self, root):
        self.root = root
        self.procs = []
        self.env = dict(os.environ, SLURM_CONF=os.path.join(root, "slurm.conf"))

    def start(self):
        r = self.root
        for d in ("munge", "state", "spool", "log"):
            os.makedirs(os.path.join(r, d), mode=0o700, exist_ok=True)
        key = os.path.join(r, "munge", "munge.key")
        subprocess.run(["mungekey", "--create", "--keyfile", key], check=True, timeout=30)
        os.chmod(key, 0o400)
        self.munge_socket = os.path.join(r, "munge", "munge.socket")
        self.spawn(["munged", "--foreground", "--force", f"--key-file={key}", f"--socket={self.munge_socket}",
                    f"--pid-file={r}/munge/munged.pid", f"--log-file={r}/log/munged.log",
                    f"--seed-file={r}/munge/munged.seed"], "munged")
        wait_for(lambda: os.path.exists(self.munge_socket), 20, "munged's socket")
        cpus = len(os.sched_getaffinity(0))
        conf = f"""ClusterName=veachci
SlurmctldHost=localhost(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket={self.munge_socket}
CredType=cred/munge
SlurmctldPort={free_port()}
SlurmdPort={free_port()}
StateSaveLocation={r}/state
SlurmdSpoolDir={r}/spool
SlurmctldPidFile={r}/slurmctld.pid
SlurmdPidFile={r}/slurmd.pid
SlurmctldLogFile={r}/log/slurmctld.log
SlurmdLogFile={r}/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MailProg=/bin/true
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MinJobAge=600
SlurmdTimeout=30
InactiveLimit=0
KillWait=5
NodeName=localhost NodeAddr=127.0.0.1 CPUs={cpus} RealMemory={max(1, memory_mb() - 512)} State=UNKNOWN
PartitionName=ci Nodes=localhost Default=YES MaxTime=INFINITE State=UP
"""
        with open(self.env["SLURM_CONF"], "w") as f:
            f.write(conf)
        self.spawn(["slurmctld", "-D", "-i", "-f", self.env["SLURM_CONF"]], "slurmctld")
        self.spawn(["slurmd", "-D", "-N", "localhost", "-f", self.env["SLURM_CONF"]], "slurmd")
        wait_for(lambda: self.node_state() in ("idle", "mixed", "allocated"), 60, "the node to be idle")

    def spawn(self, argv, name):
        log = open(os.path.join(self.root, "log", f"{name}.out"), "w")
        self.procs.append((name, subprocess.Popen(argv, stdout=log, stderr=subprocess.STDOUT, env=self.env)))

    def node_state(self):
        for name, p in self.procs:
            if p.poll() is not None:
                raise RuntimeError(f"{name} exited with {p.returncode} (logs in {self.root}/log)")
        r = subprocess.run(["sinfo", "-h", "-N", "-o", "%T"], capture_output=True, text=True, env=self.env, timeout=20)
        return r.stdout.strip().rstrip("*~#")

    def job_state(self, job):
        r = subprocess.run(["scontrol", "show", "job", "-o", str(job)], capture_output=True, text=True, env=self.env,
                           timeout=20)
        states = [w.split("=", 1)[1] for line in r.stdout.splitlines() for w in line.split() if
                  w.startswith("JobState=")]
        return states

    def wait_job(self, job, timeout):
        """The final state of a job (of every task of an array): COMPLETED, FAILED, CANCELLED..."""
        final = ("COMPLETED", "FAILED", "CANCELLED", "TIMEOUT", "NODE_FAIL", "OUT_OF_MEMORY", "BOOT_FAIL",
                 "DEADLINE", "PREEMPTED")
        end = time.time() + timeout
        while time.time() < end:
            states = self.job_state(job)
            if states and all(s in final for s in states):
                return states
            time.sleep(0.5)
        return self.job_state(job) + ["(timed out)"]

    def stop(self):
        for name, p in reversed(self.procs):
            if p.poll() is None:
                p.terminate()
                try:
                    p.wait(timeout=15)
                except subprocess.TimeoutExpired:
                    p.kill()
                    p.wait(timeout=5)


def read(path):
    buf = oiio.ImageBuf(path)
    if buf.has_error:
        raise RuntimeError(f"{path}: {buf.geterror()}")
    return buf.get_pixels(oiio.FLOAT)


def compare(single, merged, exact, what):
    if not check(os.path.exists(merged), f"{what}: the merge wrote no {merged}"):
        return
    a, b = read(single), read(merged)
    if exact:
        check(np.array_equal(a, b), f"{what}: merged image differs from the single render")
    else:
        rel = np.where(a != b, np.abs(a - b) / np.maximum(np.abs(a), 1e-30), 0)
        check(float(rel.max()) <= 1e-6, f"{what}: merged image differs by relative {float(rel.max()):.3g}")


def check_requeue(cluster, submit, veach, scene, tmp):
    """A task preempted mid-render (`scontrol requeue`, as a preempting partition does) runs again
    and continues from its checkpoint (--requeue, --checkpoint/--resume in veach-part.sbatch): its
    log shows the second run starting past 0%, and the merge is, bit for bit, the single render."""
    size = ["--width", "32", "--height", "32"]
    # About 2 s on one idle CPU, far longer than its first pass (1 spp); the sanitizer build's
    # rays are ~10x dearer and VEACH_TEST_SPP_DIVISOR=8 there keeps the time about the same.
    spp = str(2048 // max(1, int(os.environ.get("VEACH_TEST_SPP_DIVISOR", "1"))))
    out = os.path.join(tmp, "requeue", "merged.exr")
    os.makedirs(os.path.dirname(out))
    # --checkpoint 0 (every pass) after the template's 60 s, so a checkpoint exists at once.
    array, merge = submit(out, "--spp", spp, *size, render=["--integrator", "pt", "--checkpoint", "0"])
    parts = os.path.join(tmp, "requeue", "parts")
    checkpoint = os.path.join(parts, "c0_t0.vpart.checkpoint")
    wait_for(lambda: os.path.exists(checkpoint), 120, "the part's first checkpoint")
    r = subprocess.run(["scontrol", "requeue", f"{array}_0"], capture_output=True, text=True, env=cluster.env,
                       timeout=20)
    if not check(r.returncode == 0, f"scontrol requeue: exit {r.returncode}: {r.stderr.strip()} (the part finished "
                                    "before it could be preempted?)"):
        return
    single = os.path.join(tmp, "single_requeue.exr")
    subprocess.run([veach, "render", scene, "-o", single, *size, "--spp", spp, "--integrator", "pt", "-q"], check=True,
                   timeout=300)
    state = cluster.wait_job(array, 240)
    check(state == ["COMPLETED"], f"the requeued part ended {state}")
    state = cluster.wait_job(merge, 90)
    check(state == ["COMPLETED"], f"the merge after a requeued part ended {state}")
    log = open(os.path.join(parts, f"slurm-{array}_0.log")).read()
    runs = log.split("DUE TO JOB REQUEUE")
    if check(len(runs) == 2, f"the part's log does not show one requeue: {log[-2000:]}"):
        first = [line for line in runs[1].splitlines() if line.startswith("Progress:")]
        percent = int(first[0].split()[1].rstrip("%")) if first else 0
        check(percent > 0, f"the requeued part started again from 0% instead of its checkpoint: {first[:3]}")
    compare(single, out, True, "pt, a part requeued mid-render on Slurm")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--veach", required=True)
    ap.add_argument("--scene", required=True)
    ap.add_argument("--animated-scene", required=True, help="an animated glTF for the frames x chunks array")
    ap.add_argument("--submit", required=True, help="plugins/slurm/veach-slurm")
    args = ap.parse_args()
    missing = [p for p in PROGRAMS if shutil.which(p) is None]
    if missing:
        print(f"FAIL: missing {', '.join(missing)} (scripts/install-deps.sh installs slurm-wlm and munge)")
        return 1
    if os.geteuid() != 0:
        print("FAIL: the cluster test starts munged, slurmctld and slurmd and must run as root")
        return 1
    veach = os.path.abspath(args.veach)
    size = ["--width", "48", "--height", "48"]
    tmp = tempfile.mkdtemp(prefix="veach-slurm-")
    os.chmod(tmp, 0o700)
    cluster = Cluster(tmp)
    try:
        cluster.start()

        def submit(out, *extra, render=()):
            r = subprocess.run([args.submit, args.scene, "-o", out, "--veach", veach, *extra, "--", *render],
                               capture_output=True, text=True, env=cluster.env, timeout=30)
            if r.returncode != 0:
                raise RuntimeError(f"veach-slurm: exit {r.returncode}: {r.stderr.strip()}")
            return r.stdout.split()

        jobs = {}
        for integrator in ("pt", "bdpt"):
            out = os.path.join(tmp, integrator, "merged.exr")
            os.makedirs(os.path.dirname(out))
            jobs[integrator] = (out, submit(out, "--spp", "16", "--chunks", "4", *size,
                                            render=["--integrator", integrator, "-q"]))
        for integrator in ("pt", "bdpt"):
            tiles = os.path.join(tmp, f"tiles_{integrator}", "merged.exr")
            os.makedirs(os.path.dirname(tiles))
            jobs[f"tiles_{integrator}"] = (tiles, submit(tiles, "--spp", "16", "--tiles", "2x2", *size,
                                                         render=["--integrator", integrator, "-q"]))
        # A sequence: frames x sample chunks of the animated scene, one merge per frame.
        # Each merge writes its frame's files: {frame} and #### as `veach render --frames` takes them.
        frames = os.path.join(tmp, "frames", "frame_{frame}.exr")
        padded = os.path.join(tmp, "frames", "padded_####.exr")
        os.makedirs(os.path.dirname(frames))
        sequence = subprocess.run([args.submit, args.animated_scene, "-o", frames, "-o", padded, "--veach", veach,
                                   "--spp", "16", "--chunks", "2", "--frames", "7-8", *size, "--", "--integrator",
                                   "pt", "-q"], capture_output=True, text=True, env=cluster.env, timeout=30)
        if sequence.returncode != 0:
            raise RuntimeError(f"veach-slurm --frames: exit {sequence.returncode}: {sequence.stderr.strip()}")
        sequence_jobs = sequence.stdout.split()
        broken = os.path.join(tmp, "broken", "merged.exr")
        os.makedirs(os.path.dirname(broken))
        broken_jobs = submit(broken, "--spp", "16", "--chunks", "2", *size, render=["--no-such-flag"])

        # The single renders to compare with, here, while the cluster works.
        singles = {}
        for integrator in ("pt", "bdpt"):
            singles[integrator] = os.path.join(tmp, f"single_{integrator}.exr")
            subprocess.run([veach, "render", args.scene, "-o", singles[integrator], *size, "--spp", "16",
                            "--integrator", integrator, "-q"], check=True, timeout=120)

        for frame in (7, 8):
            singles[frame] = os.path.join(tmp, f"single_frame{frame}.exr")
            subprocess.run([veach, "render", args.animated_scene, "--frame", str(frame), "-o", singles[frame], *size,
                            "--spp", "16", "--integrator", "pt", "-q"], check=True, timeout=120)

        for what, (out, ids) in jobs.items():
            array, merge = ids[0], ids[1]
            parts = cluster.wait_job(array, 150)
            check(all(s == "COMPLETED" for s in parts), f"{what}: array tasks ended {parts}")
            state = cluster.wait_job(merge, 90)
            check(state == ["COMPLETED"], f"{what}: merge job ended {state}")
        compare(singles["pt"], jobs["pt"][0], True, "pt, 4 sample chunks on Slurm")
        compare(singles["bdpt"], jobs["bdpt"][0], False, "bdpt, 4 sample chunks on Slurm")
        compare(singles["pt"], jobs["tiles_pt"][0], True, "pt, 2x2 tiles on Slurm")
        compare(singles["bdpt"], jobs["tiles_bdpt"][0], False, "bdpt, 2x2 tiles on Slurm")
        check(len(sequence_jobs) == 3, f"veach-slurm --frames 7-8 printed {sequence_jobs}: an array and two merges")
        parts = cluster.wait_job(sequence_jobs[0], 150)
        check(len(parts) == 4 and all(s == "COMPLETED" for s in parts), f"frames x chunks: array tasks ended {parts}")
        for frame, merge in zip((7, 8), sequence_jobs[1:]):
            state = cluster.wait_job(merge, 90)
            check(state == ["COMPLETED"], f"frame {frame}: merge job ended {state}")
            compare(singles[frame], frames.replace("{frame}", str(frame)), True,
                    f"pt, frame {frame} of --frames 7-8 in 2 chunks on Slurm")
            compare(singles[frame], padded.replace("####", "%04d" % frame), True,
                    f"pt, frame {frame} of --frames 7-8 through a #### output")
        # Several frames into one file name would overwrite each other: refused before submitting.
        r = subprocess.run([args.submit, args.animated_scene, "-o", os.path.join(tmp, "frames", "same.exr"), "--veach",
                            veach, "--spp", "16", "--frames", "7-8"], capture_output=True, text=True, env=cluster.env,
                           timeout=30)
        check(r.returncode == 1 and not r.stdout.strip() and "{frame}" in r.stderr,
              f"veach-slurm --frames with an output without a frame pattern: exit {r.returncode}, printed "
              f"{r.stdout.strip()!r}, {r.stderr.strip()!r} (expected 1, nothing submitted)")

        parts = cluster.wait_job(broken_jobs[0], 60)
        check(all(s == "FAILED" for s in parts), f"failing parts ended {parts}, expected FAILED")
        state = cluster.wait_job(broken_jobs[1], 30)
        check(state == ["CANCELLED"], f"the merge of failed parts ended {state}, expected CANCELLED (not PENDING)")
        check(not os.path.exists(broken), "the merge of failed parts wrote an image")

        check_requeue(cluster, submit, veach, args.scene, tmp)
    except (RuntimeError, subprocess.SubprocessError) as e:
        check(False, str(e))
        for log in ("slurmctld.log", "slurmd.log", "munged.log"):
            path = os.path.join(tmp, "log", log)
            if os.path.exists(path):
                print(f"--- {log} (last lines)")
                print("".join(open(path).readlines()[-15:]))
    finally:
        cluster.stop()
        if not FAILURES:
            shutil.rmtree(tmp, ignore_errors=True)
    if FAILURES:
        print(f"{len(FAILURES)} failure(s); cluster files in {tmp}")
        return 1
    print("slurm cluster: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())

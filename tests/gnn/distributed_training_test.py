#!/usr/bin/env python3
"""spill-train as one process per rank (c10d Gloo over loopback) trains as one process does.

Usage: distributed_training_test.py SPILL_SIM SPILL_TRAIN SOURCE_DIR

On a three-trajectory dataset of a small tank and a small GNS (configs/training/gns_smoke.json,
batch of 4 windows, 20 steps):
  - one process is the reference run;
  - two ranks started with the launch variables torchrun sets (RANK, WORLD_SIZE, MASTER_ADDR,
    MASTER_PORT) give the same training and validation losses at every logged step (within
    1e-4 relative: the same windows and noise, the gradients summed in another order), and only
    rank 0 writes the run folder; the same with Slurm's variables (SLURM_PROCID, SLURM_NTASKS),
    as srun sets them;
  - under PyTorch's own launcher (python3 -m torch.distributed.run, Debian's python3-torch), the
    same, and after 5 steps of a global batch of 2 GNS's weights equal one process's to 1e-5
    relative; skipped with the reason when that launcher is not installed;
  - two ranks as two hosts, each in a network namespace of its own joined by a veth pair (the
    store and Gloo over that interface): the same losses; skipped with the reason where network
    namespaces cannot be made (they need root);
  - a run of two ranks to step 10, resumed by one process to step 20, ends as the reference
    (within 1e-3 relative): the checkpoint holds every rank's streams;
  - a launch without MASTER_ADDR exits 2 naming it; a rank whose peer never starts gives up
    within its --collective-timeout, without a C++ backtrace; a rank killed mid-run makes the
    other stop within its --collective-timeout with an error naming its rank and the dead one
    (not killed silently by SIGPIPE, which ranks ignore), leaving no temporary file and a last
    checkpoint that one process resumes.
"""

import csv
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

TANK = {
    "name": "tank", "particle_radius": 0.02, "end_time": 0.3, "output": {"frame_dt": 0.02},
    "boxes": [{"min": [0, 0, 0], "max": [0.4, 0.4, 0.4]}],
    "fluid_blocks": [{"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]}],
}
SETTINGS = ["--set", "/batch_size=4", "--set", "/log_every=2", "--set", "/validate_every=10",
            "--set", "/checkpoint_every=10"]

failures = []


def check(condition, what):
    if not condition:
        failures.append(what)
        print("FAIL:", what, file=sys.stderr)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def plain_env():
    env = dict(os.environ, OMP_NUM_THREADS="1")
    for k in ["RANK", "WORLD_SIZE", "LOCAL_RANK", "MASTER_ADDR", "MASTER_PORT",
              "TORCHELASTIC_USE_AGENT_STORE", "SLURM_NTASKS", "SLURM_PROCID"]:
        env.pop(k, None)
    return env


def ignores_sigpipe(pid):
    """Whether process `pid` ignores SIGPIPE (13), from its SigIgn mask in /proc."""
    with open(f"/proc/{pid}/status") as f:
        mask = next(line.split()[1] for line in f if line.startswith("SigIgn:"))
    return bool(int(mask, 16) & (1 << (signal.SIGPIPE - 1)))


def read_log(run):
    with open(os.path.join(run, "log.csv")) as f:
        return list(csv.DictReader(f))


def same_losses(a, b, tolerance, what):
    check(len(a) == len(b), f"{what}: {len(b)} log rows against {len(a)}")
    for ra, rb in zip(a, b):
        for key in ("loss", "valid_one_step_loss", "valid_rollout_mse"):
            if not ra[key]:
                check(not rb[key], f"{what}: step {ra['step']} {key} only in one log")
                continue
            x, y = float(ra[key]), float(rb[key])
            check(abs(x - y) <= tolerance * abs(x),
                  f"{what}: step {ra['step']} {key} {y} against {x}")


def two_hosts():
    """Two network namespaces joined by a veth pair: [(namespace, interface, address)] x 2, or
    None where namespaces cannot be made."""
    tag = str(os.getpid() % 100000)
    hosts = [(f"spill_a{tag}", f"spa{tag}", "10.77.0.1"), (f"spill_b{tag}", f"spb{tag}",
                                                          "10.77.0.2")]
    def ip(*a):
        return subprocess.run(["ip", *a], capture_output=True).returncode == 0
    if not shutil.which("ip") or not ip("netns", "add", hosts[0][0]):
        return None
    ok = ip("netns", "add", hosts[1][0]) and ip("link", "add", hosts[0][1], "type", "veth",
                                                "peer", "name", hosts[1][1])
    for namespace, interface, address in hosts:
        ok = ok and ip("link", "set", interface, "netns", namespace)
        ok = ok and ip("-n", namespace, "addr", "add", address + "/24", "dev", interface)
        ok = ok and ip("-n", namespace, "link", "set", interface, "up")
        ok = ok and ip("-n", namespace, "link", "set", "lo", "up")
    if not ok:
        for namespace, _, _ in hosts:
            ip("netns", "delete", namespace)
        return None
    return hosts


def weights_differ(python, a, b):
    """The largest difference of a weight between two checkpoints, relative to the model's
    largest weight (read with Debian's PyTorch: a checkpoint is a TorchScript archive, the
    parameters under "param:..."). Relative to the model's scale, not each tensor's: a layer
    norm's bias starts at 0 and is 5e-3 after 5 steps, where the sum's rounding (5e-8) is
    1.2e-5 of it."""
    script = (
        "import sys, torch\n"
        "a = dict(torch.jit.load(sys.argv[1]).named_parameters())\n"
        "b = dict(torch.jit.load(sys.argv[2]).named_parameters())\n"
        "keys = [k for k in a if k.startswith('param:')]\n"
        "assert keys and sorted(keys) == sorted(k for k in b if k.startswith('param:'))\n"
        "scale = max(float(a[k].abs().max()) for k in keys)\n"
        "print(max(float((a[k] - b[k]).abs().max()) for k in keys) / scale)\n")
    p = subprocess.run([python, "-c", script, a, b], capture_output=True, text=True)
    if p.returncode != 0:
        failures.append("reading the checkpoints: " + p.stderr[-1000:])
        return float("inf")
    return float(p.stdout)


def launch_ranks(train, args, world, extra_env=None, port=None):
    """Starts `world` processes as torchrun would, without it; returns them."""
    port = port or free_port()
    procs = []
    for rank in range(world):
        env = dict(plain_env(), RANK=str(rank), WORLD_SIZE=str(world), LOCAL_RANK=str(rank),
                   MASTER_ADDR="127.0.0.1", MASTER_PORT=str(port), **(extra_env or {}))
        procs.append(subprocess.Popen([train, *args], env=env, stdout=subprocess.PIPE,
                                      stderr=subprocess.PIPE, text=True))
    return procs


def wait_all(procs, what, timeout=600):
    outputs = []
    for p in procs:
        out, err = p.communicate(timeout=timeout)
        outputs.append((p.returncode, out, err))
        check(p.returncode == 0, f"{what}: a rank exited {p.returncode}: {err[-2000:]}")
    return outputs


def main():
    sim, train, source = (os.path.abspath(a) for a in sys.argv[1:4])
    config = os.path.join(source, "configs", "training", "gns_smoke.json")
    work = tempfile.mkdtemp(prefix="spill_distributed_")
    try:
        with open(os.path.join(work, "tank.json"), "w") as f:
            json.dump(TANK, f)
        data = os.path.join(work, "data")
        subprocess.run([sim, "generate", "--scene", os.path.join(work, "tank.json"),
                        "--trajectories", "3", "--split", "0.34/0.33/0.33", "--frames", "12",
                        "--out", data, "--threads", "1"], check=True, env=plain_env(),
                       capture_output=True)

        def args(run, steps=20, *more):
            return ["--config", config, "--data", data, "--out", run, "--threads", "1",
                    "--set", f"/steps={steps}", *SETTINGS, *more]

        reference = os.path.join(work, "one")
        subprocess.run([train, *args(reference)], check=True, env=plain_env(),
                       capture_output=True)
        expected = read_log(reference)

        # Two ranks with the launch variables.
        two = os.path.join(work, "two")
        outputs = wait_all(launch_ranks(train, args(two), 2), "two ranks")
        same_losses(expected, read_log(two), 1e-4, "two ranks")
        check("trained to step 20" in outputs[0][1] and outputs[1][1] == "",
              "only rank 0 reports: " + repr([o[1] for o in outputs]))

        # As srun starts them: Slurm's SLURM_PROCID and SLURM_NTASKS, the address given.
        slurm = os.path.join(work, "slurm")
        port = free_port()
        procs = [subprocess.Popen([train, *args(slurm)], env=dict(
            plain_env(), SLURM_PROCID=str(rank), SLURM_NTASKS="2", SLURM_LOCALID=str(rank),
            MASTER_ADDR="127.0.0.1", MASTER_PORT=str(port)), stdout=subprocess.PIPE,
            stderr=subprocess.PIPE, text=True) for rank in range(2)]
        wait_all(procs, "two Slurm tasks")
        same_losses(expected, read_log(slurm), 1e-4, "two Slurm tasks")

        # Under torchrun (Debian's PyTorch 1.13). On Python 3.11 its default --redirects/--tee
        # of 0 fail to parse (an enum change); 2 (stderr, tee'd to the console) works.
        python = "/usr/bin/python3"
        has_torchrun = subprocess.run([python, "-c", "import torch.distributed.run"],
                                      capture_output=True).returncode == 0
        if has_torchrun:
            launched = os.path.join(work, "torchrun")
            p = subprocess.run([python, "-m", "torch.distributed.run", "--no_python",
                                "--nproc_per_node", "2", "--master_port", str(free_port()),
                                "--redirects", "2", "--tee", "2", train, *args(launched)],
                               env=plain_env(), capture_output=True, text=True, timeout=600)
            check(p.returncode == 0, f"torchrun: exit {p.returncode}: {p.stderr[-2000:]}")
            if p.returncode == 0:
                same_losses(expected, read_log(launched), 1e-4, "torchrun")
            # GNS's weights after 5 steps of a global batch of 2: two ranks under torchrun
            # against one process.
            five = ["--set", "/steps=5", "--set", "/batch_size=2", "--set", "/checkpoint_every=5"]
            alone, shared = os.path.join(work, "five_one"), os.path.join(work, "five_two")
            subprocess.run([train, *args(alone), *five], check=True, env=plain_env(),
                           capture_output=True)
            p = subprocess.run([python, "-m", "torch.distributed.run", "--no_python",
                                "--nproc_per_node", "2", "--master_port", str(free_port()),
                                "--redirects", "2", "--tee", "2", train, *args(shared), *five],
                               env=plain_env(), capture_output=True, text=True, timeout=600)
            check(p.returncode == 0, f"torchrun, 5 steps: exit {p.returncode}: {p.stderr[-2000:]}")
            if p.returncode == 0:
                worst = weights_differ(python, os.path.join(alone, "last.pt"),
                                       os.path.join(shared, "last.pt"))
                check(worst <= 1e-5, f"weights after 5 steps differ by {worst} (relative)")
        else:
            print("skipped: torchrun (python3-torch is not installed)")

        # Two hosts: each rank in a network namespace of its own, joined by a veth pair, so the
        # store and Gloo go over a real interface (GLOO_SOCKET_IFNAME), not loopback.
        hosts = two_hosts()
        if hosts is None:
            print("skipped: two ranks as two hosts (no network namespaces here: needs root and "
                  "ip netns)")
        else:
            try:
                apart = os.path.join(work, "apart")
                procs = []
                for rank, (namespace, interface, address) in enumerate(hosts):
                    env = dict(plain_env(), RANK=str(rank), WORLD_SIZE="2",
                               MASTER_ADDR=hosts[0][2], MASTER_PORT="29400",
                               GLOO_SOCKET_IFNAME=interface)
                    procs.append(subprocess.Popen(
                        ["ip", "netns", "exec", namespace, train, *args(apart)], env=env,
                        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True))
                wait_all(procs, "two hosts")
                same_losses(expected, read_log(apart), 1e-4, "two hosts")
            finally:
                for namespace, _, _ in hosts:
                    subprocess.run(["ip", "netns", "delete", namespace], capture_output=True)

        # Two ranks to step 10, then one process to 20.
        cut = os.path.join(work, "cut")
        wait_all(launch_ranks(train, args(cut, 10), 2), "two ranks to step 10")
        subprocess.run([train, *args(cut, 20, "--resume")], check=True, env=plain_env(),
                       capture_output=True)
        same_losses(expected, read_log(cut), 1e-3, "two ranks, resumed by one")

        # No MASTER_ADDR.
        env = dict(plain_env(), RANK="0", WORLD_SIZE="2", MASTER_PORT="29999")
        p = subprocess.run([train, *args(os.path.join(work, "bad"))], env=env,
                           capture_output=True, text=True)
        check(p.returncode == 2 and "MASTER_ADDR" in p.stderr,
              f"no MASTER_ADDR: exit {p.returncode}: {p.stderr}")
        check(not os.path.exists(os.path.join(work, "bad")), "a refused launch left a folder")

        # A rank that never starts: the other gives up within its --collective-timeout (it
        # waited twice as long), with a message and no C++ backtrace.
        env = dict(plain_env(), RANK="0", WORLD_SIZE="2", MASTER_ADDR="127.0.0.1",
                   MASTER_PORT=str(free_port()))
        start = time.time()
        p = subprocess.run([train, *args(os.path.join(work, "alone"), 20, "--collective-timeout",
                                         "5")], env=env, capture_output=True, text=True)
        waited = time.time() - start
        check(p.returncode == 1 and "rank 0 of 2: cannot join" in p.stderr,
              f"a rank alone: exit {p.returncode}: {p.stderr[-1000:]}")
        check(waited < 8, f"a rank alone gave up after {waited:.1f} s for a 5 s timeout")
        check("frame #" not in p.stderr and "Exception raised from" not in p.stderr,
              f"a C++ backtrace follows the message: {p.stderr[-1000:]}")

        # A rank that dies: the other stops within its timeout, naming its rank and the dead one.
        dying = os.path.join(work, "dying")
        procs = launch_ranks(train, args(dying, 100000, "--collective-timeout", "20"), 2)
        deadline = time.time() + 120
        while time.time() < deadline and not (os.path.exists(os.path.join(dying, "last.pt"))
                                              and len(read_log(dying)) >= 7):
            time.sleep(0.2)
        # Whether rank 0 dies silently of SIGPIPE depends on whether it is writing to rank 1 at
        # the kill (rare): that it ignores SIGPIPE is checked every time, in its signal mask.
        check(ignores_sigpipe(procs[0].pid), "rank 0 does not ignore SIGPIPE")
        procs[1].send_signal(signal.SIGKILL)
        start = time.time()
        try:
            _, err = procs[0].communicate(timeout=60)
        except subprocess.TimeoutExpired:
            procs[0].kill()
            _, err = procs[0].communicate()
            check(False, "rank 0 went on more than 60 s after rank 1 died")
        procs[1].communicate()
        check(procs[0].returncode not in (0, None), f"rank 0 exited {procs[0].returncode}")
        # A signal (negative code) is a death, not an error: SIGPIPE (-13) from Gloo's write to
        # the dead peer's socket killed rank 0 before it could say anything.
        check(procs[0].returncode > 0, f"rank 0 was killed by signal {-procs[0].returncode}")
        check("rank 0 of 2" in err, f"the error does not name the rank: {err[-1000:]}")
        check("rank 1 did not answer" in err, f"the survivor does not name the dead rank: {err[-1000:]}")
        check("frame #" not in err, f"a C++ backtrace follows the message: {err[-1000:]}")
        check(time.time() - start < 45, f"rank 0 took {time.time() - start:.0f} s to stop")
        left = [n for n in os.listdir(dying) if "tmp" in n] if os.path.exists(dying) else []
        check(not left, f"temporary files left: {left}")
        # Its last checkpoint loads: one process resumes it for two more steps.
        kept = max(int(r["step"]) for r in read_log(dying) if int(r["step"]) % 10 == 0)
        p = subprocess.run([train, *args(dying, kept + 2, "--resume")], env=plain_env(),
                           capture_output=True, text=True)
        check(p.returncode == 0 and f"trained to step {kept + 2}" in p.stdout,
              f"the dead run's checkpoint (step {kept}) did not resume: {p.stderr[-1000:]}")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    if failures:
        print(f"{len(failures)} failure(s)", file=sys.stderr)
        return 1
    print("distributed training: two ranks train as one process")
    return 0


if __name__ == "__main__":
    sys.exit(main())

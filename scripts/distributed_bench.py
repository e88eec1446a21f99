#!/usr/bin/env python3
"""Data-parallel training measured: steps per second of spill-train on 1 process and on 2 ranks
(one thread each, c10d Gloo over loopback), for GNS and the PAGATNet student on river_small
frames, the gradient allreduce's time a step, and a projection to N machines. Prints JSON.

  python3 scripts/distributed_bench.py --sim build/sim/spill-sim --train build/train/spill-train \
      --data data/river_small_bench --steps 100 --repeats 3 --out docs/results/distributed_bench.json

The global batch is the config's /batch_size (here 2 windows): one process takes both, each of
two ranks one, so the speed-up is steps/s on 2 ranks over steps/s on 1 and the efficiency half
of that; each is the median of --repeats runs, one-process and two-rank runs alternating. The two ranks are launched with the variables torchrun sets (RANK, WORLD_SIZE,
MASTER_ADDR, MASTER_PORT), each with --threads 1.

The projection (weak scaling: one window a machine, so the global batch is the number of
machines): a step on N machines takes one window's compute time, measured (half the one-process
step of two windows), plus a ring allreduce of the gradient, 2 (N - 1) / N x its bytes over the
link's bandwidth (10 Gbit/s) plus 2 (N - 1) messages of a latency (50 us, an assumed figure for
10 Gbit/s Ethernet through one switch); efficiency = compute / step time. It assumes windows of
equal cost (ours vary with the particles in them, and a step waits for the slowest), and no
overlap of the allreduce with the backward (ours runs after it).
"""

import argparse
import csv
import json
import os
import re
import socket
import statistics
import subprocess
import sys
import tempfile

MODELS = {
    "gns": "configs/training/gns_river_small.json",
    "pagat_student": "configs/training/pagat_student_river_small.json",
}
LINK_BYTES_PER_S = 10e9 / 8
LATENCY_S = 50e-6


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def clean_env():
    env = dict(os.environ, OMP_NUM_THREADS="1")
    for k in ["RANK", "WORLD_SIZE", "LOCAL_RANK", "MASTER_ADDR", "MASTER_PORT",
              "TORCHELASTIC_USE_AGENT_STORE", "SLURM_NTASKS", "SLURM_PROCID"]:
        env.pop(k, None)
    return env


def steps_per_s(run):
    """The mean steps/s of the logged windows after the first (start-up)."""
    with open(os.path.join(run, "log.csv")) as f:
        rows = list(csv.DictReader(f))
    values = [float(r["steps_per_s"]) for r in rows[1:]]
    return sum(values) / len(values)


def train(args, config, run, world):
    command = [args.train, "--config", config, "--data", args.data, "--out", run, "--threads",
               "1", "--set", f"/steps={args.steps}", "--set", "/batch_size=2", "--set",
               "/log_every=5", "--set", f"/validate_every={args.steps}", "--set",
               f"/checkpoint_every={args.steps}"]
    if world == 1:
        subprocess.run(command, check=True, env=clean_env(), capture_output=True)
        return None
    port = free_port()
    procs = [subprocess.Popen(command, env=dict(clean_env(), RANK=str(r), WORLD_SIZE=str(world),
                                                 MASTER_ADDR="127.0.0.1", MASTER_PORT=str(port)),
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for r in range(world)]
    outputs = [p.communicate() for p in procs]
    for p, (_, err) in zip(procs, outputs):
        if p.returncode != 0:
            sys.exit(f"rank exited {p.returncode}: {err[-2000:]}")
    m = re.search(r"gradient allreduce of (\d+) floats over \d+ ranks: ([0-9.e+-]+) ms a step "
                  r"over \d+ steps, waiting included; ([0-9.e+-]+) ms alone", outputs[0][1])
    return {"floats": int(m.group(1)), "collective_ms_per_step": float(m.group(2)),
            "allreduce_ms": float(m.group(3))}


def projection(compute_s, floats, machines):
    """Weak scaling: each machine computes its share (compute_s a step), then the ring
    allreduce of the gradient over the link."""
    out = []
    for n in machines:
        ring = 2 * (n - 1) / n * 4 * floats / LINK_BYTES_PER_S + 2 * (n - 1) * LATENCY_S
        out.append({"machines": n, "allreduce_ms": 1e3 * ring,
                    "efficiency": compute_s / (compute_s + ring)})
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--sim", required=True)
    p.add_argument("--train", required=True)
    p.add_argument("--data", required=True, help="river_small dataset (made if missing)")
    p.add_argument("--steps", type=int, default=100)
    p.add_argument("--repeats", type=int, default=3, help="runs of each, alternating")
    p.add_argument("--out", help="also write the JSON here")
    args = p.parse_args()
    source = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    if not os.path.exists(os.path.join(args.data, "metadata.json")):
        subprocess.run([args.sim, "generate", "--scene",
                        os.path.join(source, "configs/scenes/river_small.json"),
                        "--trajectories", "4", "--frames", "20", "--split", "0.5/0.25/0.25",
                        "--out", args.data, "--threads", "1"], check=True, env=clean_env())
    report = {"command": " ".join(["python3"] + sys.argv), "global_batch": 2,
              "threads_per_rank": 1, "steps": args.steps, "repeats": args.repeats,
              "projection_assumes": {"link_gbit_s": 10, "latency_us": 1e6 * LATENCY_S,
                                     "scaling": "weak: one window a machine, the global "
                                                "batch growing with the machines"},
              "models": {}}
    with tempfile.TemporaryDirectory(prefix="spill_dist_bench_") as work:
        for name, config in MODELS.items():
            # Alternating, repeated, medians: a slower spell of the machine (timings here vary
            # by 15-30 %) falls on both sides.
            ones, twos, alone, waited = [], [], [], []
            for k in range(args.repeats):
                one = os.path.join(work, f"{name}_1_{k}")
                two = os.path.join(work, f"{name}_2_{k}")
                train(args, os.path.join(source, config), one, 1)
                measured = train(args, os.path.join(source, config), two, 2)
                ones.append(steps_per_s(one))
                twos.append(steps_per_s(two))
                alone.append(measured["allreduce_ms"])
                waited.append(measured["collective_ms_per_step"])
            sps1, sps2 = statistics.median(ones), statistics.median(twos)
            measured["allreduce_ms"] = statistics.median(alone)
            measured["collective_ms_per_step"] = statistics.median(waited)
            report["models"][name] = {
                "steps_per_s_1_process": sps1,
                "steps_per_s_2_ranks": sps2,
                "steps_per_s_1_process_runs": ones,
                "steps_per_s_2_ranks_runs": twos,
                "speed_up": sps2 / sps1,
                "parallel_efficiency": sps2 / sps1 / 2,
                "gradient_floats": measured["floats"],
                "allreduce_ms_loopback": measured["allreduce_ms"],
                "collective_ms_per_step_waiting_included": measured["collective_ms_per_step"],
                # One window a machine: half the one-process step of two windows.
                "projected": projection(0.5 / sps1, measured["floats"], [2, 4, 8, 16, 32, 64]),
            }
    text = json.dumps(report, indent=2)
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text + "\n")


if __name__ == "__main__":
    main()

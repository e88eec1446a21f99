"""What the whole-process speed benchmarks (predict_bench.py, ensemble_speed_bench.py) share:
timing a program run to its exit, and reading the end state a run folder's stats.json records."""
import argparse
import json
import os
import subprocess
import sys
import time


def timed(command):
    """Wall seconds of `command` from start to exit; a failure ends the benchmark with its
    stderr."""
    start = time.monotonic()
    done = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    wall = time.monotonic() - start
    if done.returncode != 0:
        sys.exit("failed (exit %d): %s\n%s" % (done.returncode, " ".join(command), done.stderr))
    return wall


def summary_of(folder):
    with open(os.path.join(folder, "stats.json")) as f:
        return json.load(f)["summary"]


def end_state(summary):
    """Active particles at the end and inflow layers skipped: a forecast that drains the river
    does less work and would flatter its time."""
    return {"active_at_end": summary["fluid_particles"],
            "skipped_inflow_layers": summary.get("flow", {}).get("skipped_inflow_layers", 0)}


def argument_parser(description, root):
    """The options both benchmarks take: the scene, the checkpoints, scene overrides for both
    sides, the threads and the build folder holding spill-sim and spill-infer."""
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--scene", required=True)
    p.add_argument("--checkpoints", nargs="+", required=True)
    p.add_argument("--set", nargs="*", default=[], help="scene overrides for both sides")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--build", default=os.path.join(root, "build"))
    return p


def programs(build):
    """The paths of spill-sim and spill-infer in a build folder."""
    return os.path.join(build, "sim", "spill-sim"), os.path.join(build, "infer", "spill-infer")

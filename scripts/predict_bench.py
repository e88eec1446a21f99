#!/usr/bin/env python3
"""Whole-scene speed of a learned forecast against the simulator, in one run, alternating.

For each repeat: `spill-sim run` of the scene, then `spill-infer predict` of the same scene with
each checkpoint (emitters, graph building and writing included), all on the same threads.
Prints JSON: each side's wall time per repeat (the process, start to exit), its mean, and each
model's mean over the simulator's (below 1/3 is the issue's bar for a forecast worth running).

  python3 scripts/predict_bench.py --scene configs/scenes/river_small.json \
      --checkpoints docs/results/baselines/dpi.pt docs/results/baselines/gns.pt --repeats 3
"""
import json
import os
import platform
import shutil
import sys
import tempfile

from bench_runs import argument_parser, end_state, programs, summary_of, timed


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    p = argument_parser(__doc__.split("\n")[0], root)
    p.add_argument("--repeats", type=int, default=3)
    a = p.parse_args()
    sim, infer = programs(a.build)
    work = tempfile.mkdtemp(prefix="predict_bench_")
    overrides = ["--set"] + a.set if a.set else []
    walls = {"spill-sim run": []}
    for c in a.checkpoints:
        walls["predict " + c] = []
    ends = {}  # each side's end state (bench_runs.end_state)

    try:
        for r in range(a.repeats):
            out = os.path.join(work, "sim%d" % r)
            walls["spill-sim run"].append(timed([sim, "run", "--scene", a.scene, "--out", out,
                                                 "--threads", str(a.threads)] + overrides))
            ends["spill-sim run"] = end_state(summary_of(out))
            for k, c in enumerate(a.checkpoints):
                out = os.path.join(work, "predict%d_%d" % (r, k))
                walls["predict " + c].append(
                    timed([infer, "predict", "--checkpoint", c, "--scene", a.scene, "--out", out,
                           "--threads", str(a.threads)] + overrides))
                ends["predict " + c] = end_state(summary_of(out))
    finally:
        shutil.rmtree(work, ignore_errors=True)
    mean = {k: sum(v) / len(v) for k, v in walls.items()}
    sph = mean["spill-sim run"]
    print(json.dumps({
        "scene": a.scene,
        "overrides": a.set,
        "threads": a.threads,
        "repeats": a.repeats,
        "machine": platform.processor() or platform.machine(),
        "wall_s": walls,
        "mean_wall_s": mean,
        "over_simulator": {k: v / sph for k, v in mean.items() if k != "spill-sim run"},
        "end_of_last_repeat": ends,
        "note": "wall time of each whole process (start, scene, sources, model or solver, "
                "trajectory and spill metrics written), sides alternating in every repeat",
    }, indent=2))


if __name__ == "__main__":
    main()

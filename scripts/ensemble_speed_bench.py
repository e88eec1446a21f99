#!/usr/bin/env python3
"""An ensemble forecast's speed against the simulator's: K `spill-sim run`s against one
`spill-infer predict --members K` per checkpoint, on the same scene and threads, in one run.

The simulator's K runs are split in two halves with the learned ensembles between them, so that a
drift of the machine's speed during the run falls on both sides. Prints JSON: every process's
wall time; for each ensemble its in-process start-up (scene and model loaded, once), its members'
frame time, the rest of the process (loading LibTorch, writing the ensemble's outputs), and the
cost per learned frame; each side's end state (active particles, skipped inflow layers), so that
a forecast that drains the river and does less work is seen; and each ensemble's time over the
simulator's (the issue's bar for a forecast worth running is at most a third).

  python3 scripts/ensemble_speed_bench.py --scene configs/scenes/river_case1.json \\
      --set /output/frame_dt=0.2 --checkpoints docs/results/crossover_runs/dpi_f40.pt --members 8
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
    p.add_argument("--members", type=int, default=8)
    a = p.parse_args()
    if a.members < 2:
        sys.exit("--members must be at least 2")
    sim, infer = programs(a.build)
    overrides = ["--set"] + a.set if a.set else []
    work = tempfile.mkdtemp(prefix="ensemble_speed_")
    sim_walls, sim_end = [], None
    ensembles = {}

    def simulate(k):
        nonlocal sim_end
        out = os.path.join(work, "sim%d" % k)
        sim_walls.append(timed([sim, "run", "--scene", a.scene, "--out", out,
                                "--threads", str(a.threads)] + overrides))
        sim_end = end_state(summary_of(out))
        shutil.rmtree(out, ignore_errors=True)
        print("spill-sim run %d/%d: %.1f s" % (k + 1, a.members, sim_walls[-1]), file=sys.stderr)

    try:
        half = a.members // 2
        for k in range(half):
            simulate(k)
        for c in a.checkpoints:
            out = os.path.join(work, "predict_" + os.path.basename(c))
            wall = timed([infer, "predict", "--checkpoint", c, "--scene", a.scene, "--out", out,
                          "--members", str(a.members), "--threads", str(a.threads)] + overrides)
            s = summary_of(out)
            members = s["members"]["wall_s"]
            frames = s["frames"] * a.members
            ensembles[c] = {
                "model": s["model"],
                "process_wall_s": wall,
                "start_up_s": s["start_up_s"],
                "members_wall_s": members,
                "members_total_s": sum(members),
                "rest_of_process_s": wall - s["start_up_s"] - sum(members),
                "learned_frames": frames,
                "s_per_learned_frame": sum(members) / frames,
                "end_of_first_member": end_state(s),
            }
            print("predict --members %d %s: %.1f s" % (a.members, c, wall), file=sys.stderr)
            shutil.rmtree(out, ignore_errors=True)
        for k in range(half, a.members):
            simulate(k)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    sim_total = sum(sim_walls)
    for e in ensembles.values():
        e["over_simulator"] = e["process_wall_s"] / sim_total
        e["bar_at_most_a_third"] = e["over_simulator"] <= 1.0 / 3.0
    print(json.dumps({
        "scene": a.scene,
        "overrides": a.set,
        "threads": a.threads,
        "members": a.members,
        "machine": platform.processor() or platform.machine(),
        "simulator": {"runs_wall_s": sim_walls, "total_s": sim_total,
                      "mean_s": sim_total / len(sim_walls), "end_of_last_run": sim_end},
        "ensembles": ensembles,
        "note": "wall time of whole processes (start, scene, sources, model or solver, outputs "
                "written); the simulator's runs in two halves around the learned ensembles; "
                "over_simulator: one ensemble process over the simulator's K runs",
    }, indent=2))


if __name__ == "__main__":
    main()

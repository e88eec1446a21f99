#!/usr/bin/env python3
"""Long learned forecasts against the simulator's run of the same scene: did each finish, does
it keep the river's water and close its oil budget.

Reads run folders of `spill-sim run` (--sph) and `spill-infer predict` (NAME=DIR ...), each with
stats.json (per frame `active`) and spill.json, and prints a Markdown table and, with --json, the
same figures as JSON.

  python3 scripts/long_rollouts.py --sph runs/long/sph gns=runs/long/gns_r0 dpi=runs/long/dpi_r0
"""
import argparse
import json
import os
import sys


def load(folder, name):
    try:
        with open(os.path.join(folder, name)) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        sys.exit("%s: %s" % (os.path.join(folder, name), e))


def figures(folder, sph_active):
    stats, spill = load(folder, "stats.json"), load(folder, "spill.json")
    frames = stats["frames"]
    active = [f["active"] for f in frames]
    if len(active) != len(sph_active):
        sys.exit("%s: %d frames, the simulator's run has %d" % (folder, len(active), len(sph_active)))
    deviation = [abs(a - s) / s for a, s in zip(active, sph_active)]
    summary = stats["summary"]
    last = spill["frames"][-1]
    released, in_reach = last["oil_released_m3"], last["oil_in_reach_m3"]
    left = summary.get("flow", {}).get("oil_left_m3", 0.0)
    return {
        "simulated_s": frames[-1]["t"] - frames[0]["t"],
        "active_at_end": active[-1],
        "active_deviation_max": max(deviation),
        "active_deviation_end": deviation[-1],
        "skipped_inflow_layers": summary.get("flow", {}).get("skipped_inflow_layers", 0),
        "left_domain": summary.get("left_domain", 0),
        "oil_released_m3": released,
        "oil_budget_residual_m3": released - in_reach - left,
    }


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--sph", required=True, help="the simulator's run folder")
    p.add_argument("runs", nargs="+", help="NAME=DIR of each learned forecast")
    p.add_argument("--json", help="also write the figures here")
    a = p.parse_args()
    sph_active = [f["active"] for f in load(a.sph, "stats.json")["frames"]]
    rows = {"spill-sim run": figures(a.sph, sph_active)}
    for run in a.runs:
        name, _, folder = run.partition("=")
        if not folder:
            sys.exit("%s: give NAME=DIR" % run)
        rows[name] = figures(folder, sph_active)
    print("| run | simulated s | active at end | active count off SPH's: largest, at end | "
          "skipped inflow layers | left domain | oil budget residual (m³) |")
    print("|---|---|---|---|---|---|---|")
    for name, r in rows.items():
        print("| %s | %.1f | %d | %.1f %%, %.1f %% | %d | %d | %.1e |" % (
            name, r["simulated_s"], r["active_at_end"], 100 * r["active_deviation_max"],
            100 * r["active_deviation_end"], r["skipped_inflow_layers"], r["left_domain"],
            r["oil_budget_residual_m3"]))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=2)


if __name__ == "__main__":
    main()

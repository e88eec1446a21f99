#!/usr/bin/env python3
"""Where each model of a `spill-infer compare --constant-velocity --ceiling D` run stands
between the constant-velocity floor (0) and the ceiling, the data's own solver restarted from a
jittered frame (1), per figure and per seed group, as a Markdown table on stdout.

usage: scripts/ceiling_table.py COMPARISON_JSON [SECONDS ...]   (default seconds: 1 2 4)

Seed groups: rows whose names differ only by a trailing _f40 / _sN (gns_f40, gns_s2, gns_s3)
are averaged, with their spread over seeds. A figure at a time t is the mean over trajectories
of the frame round(t / frame_dt) after the start (comparison.json's by_frame)."""
import json
import re
import statistics
import sys


def position(value, floor, ceiling):
    return (value - floor) / (ceiling - floor) if ceiling != floor else float("nan")


def main():
    data = json.load(open(sys.argv[1]))
    seconds = [float(s) for s in sys.argv[2:]] or [1.0, 2.0, 4.0]
    dt = data["frame_dt"]
    rows = {m["name"]: m for m in data["models"]}
    floor, ceiling = rows["constant_velocity"], rows["sph_ceiling"]

    def at(model, series, t):
        values = model["by_frame"][series]
        k = int(round(t / dt))
        return values[k - 1] if 0 < k <= len(values) else float("nan")

    groups = {}
    for name, model in rows.items():
        if name in ("constant_velocity", "sph_ceiling"):
            continue
        groups.setdefault(re.sub(r"_(f\d+|s\d+)$", "", name), []).append(model)

    def cell(values):
        if len(values) < 2:
            return "%.3g" % values[0]
        return "%.3g ± %.2g" % (statistics.mean(values), statistics.stdev(values))

    head = ["model (seeds)"]
    for t in seconds:
        head += ["MSE @%gs (m²)" % t, "oil IoU @%gs" % t]
    head += ["slick area error", "front error (m)"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for label, models in [("constant velocity (floor)", [floor]),
                          ("SPH restarted, jittered (ceiling)", [ceiling])] + \
            [("%s (%d)" % (g, len(ms)), ms) for g, ms in groups.items()]:
        line = [label]
        for t in seconds:
            line.append(cell([at(m, "rollout_mse", t) for m in models]))
            line.append(cell([at(m, "oil_iou", t) for m in models]))
        line.append(cell([m["slick_area_error"] for m in models]))
        line.append(cell([m["front_distance_error_m"] for m in models]))
        print("| " + " | ".join(line) + " |")
    print()
    print("Between the floor (0) and the ceiling (1), mean over seeds (higher is better):")
    print()
    head = ["model"] + ["MSE @%gs" % t for t in seconds] + ["IoU @%gs" % t for t in seconds] + \
        ["slick area error", "front error"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for g, models in groups.items():
        line = [g]
        for series in ("rollout_mse", "oil_iou"):
            for t in seconds:
                v = statistics.mean(at(m, series, t) for m in models)
                line.append("%.2f" % position(v, at(floor, series, t), at(ceiling, series, t)))
        for key in ("slick_area_error", "front_distance_error_m"):
            v = statistics.mean(m[key] for m in models)
            line.append("%.2f" % position(v, floor[key], ceiling[key]))
        print("| " + " | ".join(line) + " |")


if __name__ == "__main__":
    main()

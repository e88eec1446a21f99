#!/usr/bin/env python3
"""Where each model of a `spill-infer compare --constant-velocity --ceiling D` run stands
between the constant-velocity floor (0) and the ceiling, the data's own solver restarted from a
jittered frame (1), per figure and per seed group, as Markdown tables on stdout: the position
MSE and oil IoU at the given times, the responder's errors (slick area and leading edge at those
times and over all frames, bank contact and watch-point arrival), then each figure's place
between floor and ceiling (with the oil cloud's Sinkhorn divergence and the footprint's FSS at
20 cm for runs that have them; the raw value, marked, wherever the ceiling is not better than
the floor, instead of a placing that would invert).

usage: scripts/ceiling_table.py COMPARISON_JSON [MORE_JSON ...] [SECONDS ...]   (default seconds: 1 2 4)

The floor and the ceiling come from the first file. Further files (runs of the same data and
start, for example with `--relax 3`) add their learned models, named with a `+relaxK` suffix
where their rollouts were relaxed, so that every model is scored against the unrelaxed floor.

Seed groups: rows whose names differ only by a trailing _f40 / _sN (gns_f40, gns_s2, gns_s3)
are averaged, with their spread over seeds. A figure at a time t is the mean over trajectories
of the frame round(t / frame_dt) after the start (comparison.json's by_frame)."""
import json
import math
import re
import statistics
import sys


# Figures where a higher value is the better forecast; every other one is an error.
HIGHER_IS_BETTER = ("oil_iou", "fss_5cm", "fss_10cm", "fss_20cm", "fss_40cm")


def placed(value, floor, ceiling, series):
    """The value's place between floor (0) and ceiling (1); where the ceiling is not better than
    the floor (a chaotic flow's per-particle error after a few seconds), the placing would invert,
    so the raw value is given, marked with a dagger."""
    if any(math.isnan(v) for v in (value, floor, ceiling)):
        return "-"
    better = ceiling > floor if series in HIGHER_IS_BETTER else ceiling < floor
    if not better:
        return "%.3g†" % value
    return "%.2f" % ((value - floor) / (ceiling - floor))


def main():
    files = [sys.argv[1]] + [a for a in sys.argv[2:] if a.endswith(".json")]
    seconds = [float(a) for a in sys.argv[2:] if not a.endswith(".json")] or [1.0, 2.0, 4.0]
    data = json.load(open(files[0]))
    dt = data["frame_dt"]
    rows = {m["name"]: m for m in data["models"]}
    floor, ceiling = rows["constant_velocity"], rows["sph_ceiling"]
    for path in files[1:]:
        more = json.load(open(path))
        if (more["frame_dt"], more["from_frame"], more["data"]) != (dt, data["from_frame"], data["data"]):
            sys.exit("%s: another dataset, frame interval or start than %s" % (path, files[0]))
        relax = more.get("relax_iterations", 0)
        for m in more["models"]:
            if m["name"] not in ("constant_velocity", "sph_ceiling"):
                rows[m["name"] + ("+relax%d" % relax if relax else "")] = m

    def at(model, series, t):
        values = model["by_frame"].get(series, [])
        k = int(round(t / dt))
        value = values[k - 1] if 0 < k <= len(values) else None
        return float("nan") if value is None else value

    def whole(model, key):
        return float("nan") if model.get(key) is None else model[key]

    groups = {}
    for name, model in rows.items():
        if name in ("constant_velocity", "sph_ceiling"):
            continue
        groups.setdefault(re.sub(r"_(f\d+|s\d+)(?=$|\+)", "", name), []).append(model)

    def cell(values):
        if any(math.isnan(v) for v in values):
            return "-"
        if len(values) < 2:
            return "%.3g" % values[0]
        return "%.3g ± %.2g" % (statistics.mean(values), statistics.stdev(values))

    labelled = [("constant velocity (floor)", [floor]),
                ("SPH restarted, jittered (ceiling)", [ceiling])] + \
        [("%s (%d)" % (g, len(ms)), ms) for g, ms in groups.items()]

    def table(columns):
        """columns: (heading, value of a model) pairs; one row per labelled group."""
        print("| model (seeds) | " + " | ".join(h for h, _ in columns) + " |")
        print("|" + "---|" * (len(columns) + 1))
        for label, models in labelled:
            print("| " + " | ".join([label] + [cell([f(m) for m in models])
                                               for _, f in columns]) + " |")
        print()

    def series_at(series, t):
        return lambda m: at(m, series, t)

    table([c for t in seconds for c in (("MSE @%gs (m²)" % t, series_at("rollout_mse", t)),
                                         ("oil IoU @%gs" % t, series_at("oil_iou", t)))])
    table([("slick area error @%gs" % t, series_at("slick_area_error", t)) for t in seconds] +
          [("slick area error, all frames", lambda m: whole(m, "slick_area_error"))] +
          [("front error @%gs (m)" % t, series_at("front_distance_error_m", t))
           for t in seconds] +
          [("front error, all frames (m)", lambda m: whole(m, "front_distance_error_m")),
           ("bank contact error (s)", lambda m: whole(m, "bank_contact_time_error_s")),
           ("watch-point arrival error (s)", lambda m: whole(m, "watch_arrival_time_error_s"))])
    print("Between the floor (0) and the ceiling (1), mean over seeds (higher is better):")
    print()
    by_time = [("MSE", "rollout_mse"), ("IoU", "oil_iou"), ("area", "slick_area_error"),
               ("front", "front_distance_error_m")]
    if "sinkhorn_oil" in floor["by_frame"]:  # runs since issue 48's scores
        by_time += [("oil Sinkhorn", "sinkhorn_oil"), ("FSS 20 cm", "fss_20cm")]
    whole_keys = [("area, all", "slick_area_error"), ("front, all", "front_distance_error_m"),
                  ("bank", "bank_contact_time_error_s"), ("watch", "watch_arrival_time_error_s")]
    head = ["model"] + ["%s @%gs" % (name, t) for name, _ in by_time for t in seconds] + \
        [name for name, _ in whole_keys]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for g, models in groups.items():
        line = [g]
        for _, series in by_time:
            for t in seconds:
                v = statistics.mean(at(m, series, t) for m in models)
                line.append(placed(v, at(floor, series, t), at(ceiling, series, t), series))
        for _, key in whole_keys:
            v = statistics.mean(whole(m, key) for m in models)
            line.append(placed(v, whole(floor, key), whole(ceiling, key), key))
        print("| " + " | ".join(line) + " |")
    print()
    print("†: the ceiling is not better than the floor on this figure (per-particle error of a "
          "flow that has decorrelated): the model's raw value, not a placing.")
    print()
    print("First time each model's position MSE (mean over seeds) is above the floor's:")
    print()
    frames = len(floor["by_frame"]["rollout_mse"])
    for g, models in groups.items():
        above = [k for k in range(1, frames + 1)
                 if statistics.mean(at(m, "rollout_mse", k * dt) for m in models) >
                 at(floor, "rollout_mse", k * dt)]
        print("- %s: %s" % (g, "%.1f s" % (above[0] * dt) if above else "never, to %.1f s" % (frames * dt)))


if __name__ == "__main__":
    main()

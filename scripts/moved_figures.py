#!/usr/bin/env python3
"""Which figures of a `spill-infer compare` run moved when it was run again, and by how much: one
Markdown row per model present in both comparison.json files, each cell 'before -> after', for
the inflow layers skipped (summed over trajectories), the position MSE, oil IoU, slick area
error and leading-edge error at the given times after the start (comparison.json's by_frame,
frame round(t / frame_dt)), and the whole-run slick area, front, bank contact and watch-point
arrival errors. The active-particle deviation exists only in the newer file.

usage: scripts/moved_figures.py BEFORE_JSON AFTER_JSON [SECONDS ...]   (default seconds: 1 2)"""
import json
import sys


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    before, after = (json.load(open(p)) for p in sys.argv[1:3])
    seconds = [float(a) for a in sys.argv[3:]] or [1.0, 2.0]
    if before["frame_dt"] != after["frame_dt"] or before["from_frame"] != after["from_frame"]:
        sys.exit("the two comparisons differ in frame interval or start")
    dt = after["frame_dt"]
    old = {m["name"]: m for m in before["models"]}

    def at(model, series, t):
        values = model["by_frame"].get(series, [])
        k = int(round(t / dt))
        return values[k - 1] if 0 < k <= len(values) else None

    def text(v):
        return "-" if v is None else "%.3g" % v

    columns = [("skipped layers", lambda m: m.get("skipped_inflow_layers"))]
    for label, series in (("MSE", "rollout_mse"), ("IoU", "oil_iou"), ("area", "slick_area_error"),
                          ("front (m)", "front_distance_error_m")):
        for t in seconds:
            columns.append(("%s @%gs" % (label, t), lambda m, s=series, t=t: at(m, s, t)))
    for label, key in (("area, all", "slick_area_error"), ("front, all (m)", "front_distance_error_m"),
                       ("bank (s)", "bank_contact_time_error_s"),
                       ("watch (s)", "watch_arrival_time_error_s")):
        columns.append((label, lambda m, k=key: m.get(k)))
    print("| model | active off by (max) | " + " | ".join(h for h, _ in columns) + " |")
    print("|" + "---|" * (len(columns) + 2))
    for m in after["models"]:
        if m["name"] not in old:
            continue
        deviation = m.get("active_deviation_max")
        cells = [m["name"], "-" if deviation is None else "%.2g %%" % (100 * deviation)]
        for _, value in columns:
            cells.append("%s → %s" % (text(value(old[m["name"]])), text(value(m))))
        print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()

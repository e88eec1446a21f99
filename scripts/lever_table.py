#!/usr/bin/env python3
"""One table of chosen figures of models from several `spill-infer compare` runs: each lever's
effect side by side (issue 48, section 4).

Each row is LABEL=COMPARISON_JSON:MODEL_NAME; each cell is the figure's mean over trajectories
with its 90 % bootstrap interval, as comparison.json holds them.

  python3 scripts/lever_table.py --figures sinkhorn_oil_2s,fss_20cm_2s \\
      "noise 0.001=runs/noise/valid/comparison.json:dpi_n0.001"

With --between FLOOR,CEILING (two of the rows' labels) a second table places every other row
from the floor (0) to the ceiling (1) on each figure: (x - floor) / (ceiling - floor), whichever
way better lies (lower for errors and divergences, higher for FSS).
"""
import argparse
import json
import sys


def heading(figure):
    """A figure's key as a column heading: sinkhorn_oil_2s -> oil Sinkhorn @2 s."""
    names = {"sinkhorn_oil": "oil Sinkhorn", "sinkhorn_fluid": "fluid Sinkhorn",
             "fss_20cm": "FSS 20 cm", "crps_front_m": "CRPS front (m)",
             "crps_slick_area_m2": "CRPS slick area (m²)", "mmd": "MMD",
             "kinetic_energy_error": "kinetic-energy error", "compression_mean": "compression",
             "slick_area_error": "slick area error, all frames"}
    for key, name in names.items():
        if figure == key:
            return name
        if figure.startswith(key + "_"):
            at = figure[len(key) + 1:]
            return name + " @" + ("leak end" if at == "leak_end" else at.replace("s", " s"))
    return figure


def cell(model, figure):
    value = model.get(figure)
    if value is None:
        return "-"
    interval = model.get("interval90", {}).get(figure)
    text = "%.3g" % value
    if interval and None not in interval:
        text += " [%.3g, %.3g]" % tuple(interval)
    return text


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--figures", required=True, help="comma-separated comparison.json keys")
    p.add_argument("rows", nargs="+", help="LABEL=COMPARISON_JSON:MODEL_NAME")
    p.add_argument("--between", help="FLOOR,CEILING: labels of two rows to place the others by")
    a = p.parse_args()
    figures = a.figures.split(",")
    print("| run | " + " | ".join(heading(f) for f in figures) + " |")
    print("|---" * (len(figures) + 1) + "|")
    found_rows = {}
    for row in a.rows:
        label, _, where = row.partition("=")
        path, _, name = where.rpartition(":")
        if not path or not name:
            sys.exit("%s: give LABEL=COMPARISON_JSON:MODEL_NAME" % row)
        try:
            with open(path) as f:
                models = json.load(f)["models"]
        except (OSError, ValueError, KeyError) as e:
            sys.exit("%s: %s" % (path, e))
        found = [m for m in models if m.get("name") == name]
        if not found:
            sys.exit("%s: no model %r (it has %s)" % (path, name, [m.get("name") for m in models]))
        found_rows[label] = found[0]
        print("| %s | " % label + " | ".join(cell(found[0], f) for f in figures) + " |")
    if a.between:
        floor_label, _, ceiling_label = a.between.partition(",")
        if floor_label not in found_rows or ceiling_label not in found_rows:
            sys.exit("--between %s: name two of the rows' labels" % a.between)
        floor, ceiling = found_rows[floor_label], found_rows[ceiling_label]
        print()
        print("| placed from %s (0) to %s (1) | " % (floor_label, ceiling_label) +
              " | ".join(heading(f) for f in figures) + " |")
        print("|---" * (len(figures) + 1) + "|")
        for label, model in found_rows.items():
            if label in (floor_label, ceiling_label):
                continue
            cells = []
            for f in figures:
                x, lo, hi = model.get(f), floor.get(f), ceiling.get(f)
                if None in (x, lo, hi) or lo == hi:
                    cells.append("-")
                else:
                    cells.append("%.2f" % ((x - lo) / (hi - lo)))
            print("| %s | " % label + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()

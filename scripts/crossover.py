#!/usr/bin/env python3
"""Where learning pays: assembles docs/results/crossover.{md,json,svg} from `spill-infer compare`
outputs at several frame intervals and the simulator's own speed on the same scene and threads.

Usage:
  scripts/crossover.py [--sph-metadata DATA/metadata.json] [--timing COMPARISON.json ...] \
      --out docs/results/crossover STEPS:COMPARISON.json [STEPS:COMPARISON.json ...]

STEPS is the number of solver steps per frame of that dataset (10, 20, 40); each comparison may
come with or without --relax (its relax_iterations says which); rows are kept apart by it.
For each interval, model and relaxation the table gives the rollout position error and the oil
IoU 1 s and 2 s of simulated time after the rollout's start (the frame nearest to that time;
from the comparison's by_frame series), the mean compression of the predicted frames, and the
seconds of wall time per simulated second against MTDF-SPH's: by default the comparisons' own
figure (the simulator's time for the same recorded frames when the datasets were generated,
averaged over the comparisons), or with --sph-metadata the metadata.json of a dataset generated
for timing (its sph_seconds_per_frame over dt). Likewise each model's time per frame comes from
its own comparison unless --timing gives comparisons run for timing (on a quiet machine, on the
threads to report): a learned frame costs the same whatever the interval it spans (the same
particles and graph), so seconds per simulated second = seconds per frame / frame_dt. Needs only
the Python standard library.
"""
import argparse
import json
import math
import sys


def at_time(series, frame_dt, seconds):
    """Value of a by_frame series (index k - 1 for frame k) at the frame nearest `seconds`."""
    k = int(round(seconds / frame_dt))
    if k < 1 or k > len(series):
        return None
    return series[k - 1]


def svg_plot(rows, sph_rate, path):
    """Seconds per simulated second against solver steps per frame, log-log, one line per
    model and relaxation, the SPH as a horizontal line."""
    width, height, margin = 640, 420, 60
    lines = {}
    for r in rows:
        lines.setdefault(r["label"], []).append((r["steps_per_frame"], r["seconds_per_simulated_second"]))
    values = [v for pts in lines.values() for _, v in pts if v] + [sph_rate]
    steps = sorted({r["steps_per_frame"] for r in rows})
    lo, hi = math.log10(min(values) / 1.5), math.log10(max(values) * 1.5)
    xlo, xhi = math.log2(min(steps)) - 0.3, math.log2(max(steps)) + 0.3

    def xy(s, v):
        x = margin + (math.log2(s) - xlo) / (xhi - xlo) * (width - 2 * margin)
        y = height - margin - (math.log10(v) - lo) / (hi - lo) * (height - 2 * margin)
        return x, y

    colours = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2"]
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
           f'font-family="sans-serif" font-size="12">',
           f'<rect width="{width}" height="{height}" fill="white"/>',
           f'<text x="{width / 2}" y="20" text-anchor="middle" font-size="14">Wall time per '
           f'simulated second: learned simulators against MTDF-SPH</text>']
    for s in steps:
        x, _ = xy(s, 10 ** lo)
        out.append(f'<line x1="{x}" y1="{margin}" x2="{x}" y2="{height - margin}" stroke="#ddd"/>')
        out.append(f'<text x="{x}" y="{height - margin + 16}" text-anchor="middle">{s}</text>')
    for e in range(math.floor(lo), math.ceil(hi) + 1):
        if lo <= e <= hi:
            _, y = xy(2 ** xlo, 10 ** e)
            out.append(f'<line x1="{margin}" y1="{y}" x2="{width - margin}" y2="{y}" stroke="#ddd"/>')
            out.append(f'<text x="{margin - 6}" y="{y + 4}" text-anchor="end">1e{e}</text>')
    out.append(f'<text x="{width / 2}" y="{height - 15}" text-anchor="middle">solver steps per '
               f'learned frame</text>')
    out.append(f'<text x="15" y="{height / 2}" text-anchor="middle" transform="rotate(-90 15 '
               f'{height / 2})">seconds per simulated second</text>')
    _, y = xy(2 ** xlo, sph_rate)
    out.append(f'<line x1="{margin}" y1="{y}" x2="{width - margin}" y2="{y}" stroke="black" '
               f'stroke-dasharray="6 4"/>')
    out.append(f'<text x="{width - margin}" y="{y - 6}" text-anchor="end">MTDF-SPH</text>')
    for i, (label, pts) in enumerate(sorted(lines.items())):
        c = colours[i % len(colours)]
        pts = sorted(p for p in pts if p[1])
        coords = " ".join(f"{x:.1f},{y:.1f}" for x, y in (xy(s, v) for s, v in pts))
        out.append(f'<polyline points="{coords}" fill="none" stroke="{c}" stroke-width="2"/>')
        lx, ly = margin + 10, margin + 16 * (i + 1)
        out.append(f'<text x="{lx}" y="{ly}" fill="{c}">{label}</text>')
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def fmt(v, digits=3):
    return "-" if v is None else f"{v:.{digits}g}"


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--sph-metadata", help="metadata.json of a dataset generated for timing "
                   "(default: the comparisons' sph figure)")
    p.add_argument("--sph-metadata-more", nargs="*", default=[],
                   help="further timing datasets' metadata.json, averaged with the first")
    p.add_argument("--timing", nargs="*", default=[], help="comparison.json files run for timing")
    p.add_argument("--out", required=True, help="output path without extension")
    p.add_argument("comparisons", nargs="+", help="STEPS:comparison.json")
    a = p.parse_args(argv)
    sph_rates = []
    rows = []
    for item in a.comparisons:
        steps, path = item.split(":", 1)
        with open(path) as f:
            c = json.load(f)
        relax = c.get("relax_iterations", 0)
        if c["sph"].get("seconds_per_simulated_second"):
            sph_rates.append(c["sph"]["seconds_per_simulated_second"])
        for m in c["models"]:
            by = m["by_frame"]
            label = m["model"] + (f" + relax {relax}" if relax else "")
            rows.append({
                "steps_per_frame": int(steps), "frame_dt": c["frame_dt"], "model": m["model"],
                "name": m["name"], "relax_iterations": relax, "label": label,
                "rollout_mse_1s": at_time(by["rollout_mse"], c["frame_dt"], 1.0),
                "rollout_mse_2s": at_time(by["rollout_mse"], c["frame_dt"], 2.0),
                "oil_iou_1s": at_time(by["oil_iou"], c["frame_dt"], 1.0),
                "oil_iou_2s": at_time(by["oil_iou"], c["frame_dt"], 2.0),
                "compression_mean": m.get("compression_mean"),
                "seconds_per_simulated_second": m["seconds_per_simulated_second"],
                "trajectories": len(c["trajectories"]), "threads": c.get("threads"),
                "source": path})
    timing = {}  # (model, relax) -> seconds per frame, the mean over the timing runs
    timing_threads = None
    for path in a.timing:
        with open(path) as f:
            c = json.load(f)
        timing_threads = c.get("threads")
        for m in c["models"]:
            timing.setdefault((m["model"], c.get("relax_iterations", 0)), []).append(
                m["seconds_per_frame"])
    timing = {k: sum(v) / len(v) for k, v in timing.items()}
    for r in rows:
        key = (r["model"], r["relax_iterations"])
        if key in timing:
            r["seconds_per_simulated_second"] = timing[key] / r["frame_dt"]
            r["threads"] = timing_threads
    if a.sph_metadata:
        with open(a.sph_metadata) as f:
            meta = json.load(f)
        per_frame = [t["sph_seconds_per_frame"] for t in meta["trajectories"]
                     if t.get("sph_seconds_per_frame")]
        for extra in a.sph_metadata_more:
            with open(extra) as f:
                per_frame += [t["sph_seconds_per_frame"] for t in json.load(f)["trajectories"]
                              if t.get("sph_seconds_per_frame")]
        sph_rate = sum(per_frame) / len(per_frame) / meta["dt"]
        sph_source = a.sph_metadata
        sph_threads = meta.get("generation", {}).get("threads")
    else:
        if not sph_rates:
            sys.exit("crossover.py: no comparison records the SPH's time; give --sph-stats")
        sph_rate, sph_source = sum(sph_rates) / len(sph_rates), "the datasets' generation"
        sph_threads = "as generated"
    for r in rows:
        r["speed_vs_sph"] = (sph_rate / r["seconds_per_simulated_second"]
                             if r["seconds_per_simulated_second"] else None)
    rows.sort(key=lambda r: (r["steps_per_frame"], r["model"], r["relax_iterations"]))
    result = {"sph": {"seconds_per_simulated_second": sph_rate, "source": sph_source,
                      "threads": sph_threads},
              "rows": rows,
              "units": "rollout_mse: squared position error (m^2); oil_iou: top-view IoU of "
                       "oil cells; compression_mean: mean max(rho/rho0 - 1, 0) of predicted "
                       "frames; speed_vs_sph > 1: the learned simulator is faster than MTDF-SPH"}
    with open(a.out + ".json", "w") as f:
        json.dump(result, f, indent=2)
    md = ["# Where learning pays", "",
          f"MTDF-SPH: {sph_rate:.3g} s of wall time per simulated second "
          f"(threads: {sph_threads}; from {sph_source}). Learned simulators on "
          f"{rows[0]['threads'] if rows else '?'} threads. Speed: MTDF-SPH's time over the "
          f"model's (> 1: the learned simulator is faster).", "",
          "| solver steps per frame | model | rollout MSE at 1 s (m²) | at 2 s | oil IoU at 1 s "
          "| at 2 s | compression | s per simulated s | speed vs MTDF-SPH |",
          "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        md.append(f"| {r['steps_per_frame']} | {r['label']} | {fmt(r['rollout_mse_1s'])} | "
                  f"{fmt(r['rollout_mse_2s'])} | {fmt(r['oil_iou_1s'])} | {fmt(r['oil_iou_2s'])} | "
                  f"{fmt(r['compression_mean'])} | {fmt(r['seconds_per_simulated_second'])} | "
                  f"{fmt(r['speed_vs_sph'])} |")
    with open(a.out + ".md", "w") as f:
        f.write("\n".join(md) + "\n")
    svg_plot(rows, sph_rate, a.out + ".svg")


if __name__ == "__main__":
    main(sys.argv[1:])

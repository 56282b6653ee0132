#!/usr/bin/env python3
"""The depth findings' table and figure (docs/findings/depth.md) from a run of
results/experiments/depth.toml: per method and depth mode, over both fields and distances, the
mean of depth_err_mean and depth_bias_mean (tiles), depth_toward_frac, and cut_flip_frac per cut,
for theta <= 60 and theta >= 70; and a figure of depth_err_mean and cut_flip_frac (the cut nearest 0.5)
against theta (CPU float rows).

    /usr/bin/python3 scripts/depth_table.py RESULTS_DIR [--figure OUT_STEM --width single|double]
"""
import argparse
import csv
import statistics
import sys
from collections import defaultdict

# figure_style.py, beside this file (on sys.path as the script's folder), never compiled
# into a __pycache__ in the source tree.
sys.dont_write_bytecode = True
import figure_style  # noqa: E402


def load(folder):
    with open(f"{folder}/results.csv", newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["status"] == "ok" and r["backend"] == "cpu"]
    if not rows:
        sys.exit(f"{folder}/results.csv: no ok CPU rows")
    return rows


def table(rows):
    order = []
    cells = defaultdict(list)
    for r in rows:
        key = (r["method"], r["depth"])
        if key not in order:
            order.append(key)
        band = "low" if float(r["theta_deg"]) <= 60 else "high"
        cells[key + (band, r["cut"])].append(r)
    cuts = sorted({r["cut"] for r in rows}, key=float)
    head = ["method", "depth", "θ", "depth_err_mean", "depth_bias_mean", "toward"]
    head += [f"flip c={c}" for c in cuts]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for key in order:
        for band, label in (("low", "≤ 60°"), ("high", "70–80°")):
            first = cells[key + (band, cuts[0])]
            mean = lambda col, rs: statistics.fmean(float(r[col]) for r in rs)
            line = [key[0], key[1], label, f"{mean('depth_err_mean', first):.4f}",
                    f"{mean('depth_bias_mean', first):+.4f}",
                    f"{mean('depth_toward_frac', first):.3f}"]
            line += [f"{mean('cut_flip_frac', cells[key + (band, c)]):.3f}" for c in cuts]
            print("| " + " | ".join(line) + " |")


def figure(rows, stem, width):
    fig, axes = figure_style.two_panels(width, {"double": 3.0, "single": 5.4})
    series = defaultdict(lambda: defaultdict(list))
    flips = defaultdict(lambda: defaultdict(list))
    cuts = sorted({r["cut"] for r in rows}, key=float)
    first_cut = cuts[0]  # depth errors do not depend on the cut: one cut's rows
    mid_cut = min(cuts, key=lambda c: abs(float(c) - 0.5))  # the flips of the cut nearest 0.5
    for r in rows:
        key = f"{r['method']} {r['depth']}"
        t = float(r["theta_deg"])
        if r["cut"] == first_cut:
            series[key][t].append(float(r["depth_err_mean"]))
        if r["cut"] == mid_cut and r["cut_flip_frac"] != "":
            flips[key][t].append(float(r["cut_flip_frac"]))
    # base writes the polygon whatever the method: one curve for all of them.
    shown = ["pom base"] + [f"{m} hit" for m in ("parallax", "pom", "hdrp_pom", "o3de_pom",
                                                  "maxmip")]
    shown += ["hdrp_pom engine", "o3de_pom engine"]
    colours = {"parallax": "C0", "pom": "C1", "hdrp_pom": "C2", "o3de_pom": "C3", "maxmip": "C4"}
    styles = {"hit": "-", "engine": "--"}
    for k in shown:
        method, mode = k.split()
        label = "every method, base" if mode == "base" else k
        colour = "0.4" if mode == "base" else colours[method]
        style = ":" if mode == "base" else styles[mode]
        ts = sorted(series[k])
        for ax, data in ((axes[0], series[k]), (axes[1], flips[k])):
            ax.plot(ts, [statistics.fmean(data[t]) for t in ts], style, marker="o", ms=2.5,
                    lw=1, color=colour, label=label if ax is axes[0] else None)
    axes[0].set_yscale("log")
    axes[0].set_xlabel("θ (degrees)")
    axes[0].set_ylabel("depth_err_mean (tiles)")
    axes[1].set_xlabel("θ (degrees)")
    axes[1].set_ylabel(f"cut_flip_frac at c = {mid_cut}")
    figure_style.finish(fig, stem, width,
                        ("Written depth vs the true surface",
                         "(bricks, luxembourg; distance 1.5 and 3)"),
                        bottom={"double": 0.17, "single": 0.12},
                        top={"double": 0.95, "single": 0.93})


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results")
    figure_style.add_options(ap)
    a = ap.parse_args()
    rows = load(a.results)
    table(rows)
    if a.figure:
        figure(rows, a.figure, a.width)


if __name__ == "__main__":
    main()

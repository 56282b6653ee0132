#!/usr/bin/python3
"""The table and figure of docs/findings/curved.md from a run of results/experiments/curved.toml:
per method family, base and s / R, the mean over both fields and the θ band of err_mean, err_p95
(texels), cover_extra_frac and cover_missing_frac (CPU float rows); the figure plots err_mean and
cover_extra_frac against s / R at θ <= 40°, cylinder solid, sphere dashed.
    /usr/bin/python3 scripts/curved_table.py RESULTS_DIR [--figure OUT_STEM --width single|double]"""
import argparse
import csv
import statistics
import sys
from collections import defaultdict

# figure_style.py, beside this file (on sys.path as the script's folder), never compiled
# into a __pycache__ in the source tree.
sys.dont_write_bytecode = True
import figure_style  # noqa: E402

FAMILY = {"parallax": "single step", "parallax_limited": "single step", "steep": "layered search",
          "pom": "layered search", "relief": "layered search", "hdrp_pom": "engine presets",
          "o3de_pom": "engine presets", "maxmip": "exact on flat (maxmip)",
          "curved_relief": "curved relief (Oliveira, Policarpo)",
          "silhouette_pom": "silhouette POM (three.js PR 33953)"}


def table(rows):
    cells = defaultdict(list)
    for r in rows:
        if r["backend"] != "cpu" or r["status"] != "ok":
            continue
        t = float(r["theta_deg"])
        band = "≤ 40°" if t <= 40 else "60–80°"
        base = r["base"] or "plane"  # empty on the plane
        s_over_r = 0.0 if base == "plane" else float(r["scale"]) / float(r["radius"])
        cells[(FAMILY.get(r["method"], r["method"]), base, s_over_r, band)].append(r)
    print("| family | base | s / R | θ | err_mean | err_p95 | cover_extra | cover_missing |")
    print("|---|---|---|---|---|---|---|---|")
    order = list(dict.fromkeys(list(FAMILY.values()) + [k[0] for k in cells]))
    for key in sorted(cells, key=lambda k: (order.index(k[0]), k[1] != "plane", k[1], k[2], k[3] != "≤ 40°")):
        rs = cells[key]

        def mean(c):
            v = [float(r[c]) for r in rs if r[c] != ""]
            return sum(v) / len(v) if v else float("nan")
        fam, base, sr, band = key
        cov = (f"{mean('cover_extra_frac'):.3f} | {mean('cover_missing_frac'):.3f}"
               if base != "plane" else "– | –")
        print(f"| {fam} | {base} | {sr:g} | {band} | {mean('err_mean'):.3f} | "
              f"{mean('err_p95'):.2f} | {cov} |")



def figure(rows, stem, width):
    fig, axes = figure_style.two_panels(width, {"double": 3.1, "single": 5.6})
    shown = ["maxmip", "pom", "parallax", "curved_relief", "silhouette_pom"]
    colours = dict(zip(shown, ("C4", "C1", "C0", "C3", "C2")))
    data = defaultdict(lambda: defaultdict(list))
    for r in rows:
        if r["backend"] != "cpu" or r["status"] != "ok" or float(r["theta_deg"]) > 40:
            continue
        if r["method"] not in shown:
            continue
        base = r["base"] or "plane"
        sr = 0.0 if base == "plane" else float(r["scale"]) / float(r["radius"])
        for b in ((base,) if base != "plane" else ("cylinder", "sphere")):
            data[(r["method"], b)][sr].append(r)
    for (m, b), by in sorted(data.items()):
        xs = sorted(by)
        style = "-" if b == "cylinder" else "--"
        for ax, col in ((axes[0], "err_mean"), (axes[1], "cover_extra_frac")):
            ys = [statistics.fmean(float(r[col]) if r[col] != "" else 0.0 for r in by[x])
                  for x in xs]
            ax.plot(xs, ys, style, marker="o", ms=2.5, lw=1, color=colours[m],
                    label=(f"{m}" if b == "cylinder" else None) if ax is axes[0] else None)
    axes[0].set_xlabel("s / R")
    axes[0].set_ylabel("err_mean (texels)")
    axes[1].set_xlabel("s / R")
    axes[1].set_ylabel("cover_extra_frac")
    axes[0].plot([], [], "k-", lw=1, label="cylinder")
    axes[0].plot([], [], "k--", lw=1, label="sphere")
    figure_style.finish(fig, stem, width,
                        ("Flat and silhouette-aware methods on curved bases, θ ≤ 40°",
                         "(bricks, luxembourg; s = 0.05, b = 1; s / R = 0: the plane)"),
                        bottom={"double": 0.15, "single": 0.11},
                        top={"double": 0.92, "single": 0.94})


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results")
    figure_style.add_options(ap)
    a = ap.parse_args()
    rows = list(csv.DictReader(open(a.results + "/results.csv")))
    table(rows)
    if a.figure:
        figure(rows, a.figure, a.width)


if __name__ == "__main__":
    main()

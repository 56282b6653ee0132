#!/usr/bin/python3
"""The table of docs/findings/curved.md from a run of results/experiments/curved.toml: per method
family, base and s / R, the mean over both fields and the θ band of err_mean, err_p95 (texels),
cover_extra_frac and cover_missing_frac (CPU float rows).
    /usr/bin/python3 scripts/curved_table.py RESULTS_DIR"""
import csv
import sys
from collections import defaultdict

FAMILY = {"parallax": "single step", "parallax_limited": "single step", "steep": "layered search",
          "pom": "layered search", "relief": "layered search", "hdrp_pom": "engine presets",
          "o3de_pom": "engine presets", "maxmip": "exact on flat (maxmip)",
          "curved_relief": "curved relief (Oliveira, Policarpo)",
          "silhouette_pom": "silhouette POM (three.js PR 33953)"}


def main():
    rows = list(csv.DictReader(open(sys.argv[1] + "/results.csv")))
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


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""The tables of docs/findings/flip.md from a run of results/experiments/flip.toml.

  scripts/flip_table.py RUN_DIR

Per height field and eye distance, every method setting's mean flip_mean and mean err_mean
(texels) and err_px_mean (pixels) over theta 45/70/80, and its rank by each; then Spearman's
rank correlation of the flip ranking with the texel ranking per field and distance. Reads only
RUN_DIR/results.csv (ok rows).
"""
import csv
import sys
from collections import defaultdict


def ranks(values):
    order = sorted(range(len(values)), key=lambda i: values[i])
    r = [0] * len(values)
    for pos, i in enumerate(order):
        r[i] = pos + 1
    return r


def spearman(a, b):
    ra, rb = ranks(a), ranks(b)
    n = len(a)
    d2 = sum((x - y) ** 2 for x, y in zip(ra, rb))
    return 1 - 6 * d2 / (n * (n * n - 1)) if n > 1 else float("nan")


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    rows = [r for r in csv.DictReader(open(sys.argv[1] + "/results.csv")) if r["status"] == "ok"]
    acc = defaultdict(lambda: defaultdict(list))
    for r in rows:
        setting = r["method"] + (" " + r["params"] if r["params"] else "")
        if r["lod"] != "base":
            setting += " lod=" + r["lod"]
        key = (r["heightfield"], float(r["distance"]))
        for c in ("flip_mean", "err_mean", "err_px_mean"):
            acc[key][(setting, c)].append(float(r[c]))
    for key in sorted(acc):
        settings = sorted({s for s, _ in acc[key]})
        mean = {(s, c): sum(v) / len(v) for (s, c), v in acc[key].items()}
        flips = [mean[(s, "flip_mean")] for s in settings]
        texels = [mean[(s, "err_mean")] for s in settings]
        rf, rt = ranks(flips), ranks(texels)
        print(f"\n### {key[0]}, distance {key[1]:g} (Spearman flip vs texel: "
              f"{spearman(flips, texels):.2f})\n")
        print("| setting | flip_mean | rank | err_mean (texels) | rank | err_px_mean |")
        print("|---|---:|---:|---:|---:|---:|")
        for i in sorted(range(len(settings)), key=lambda i: flips[i]):
            s = settings[i]
            print(f"| {s} | {flips[i]:.4f} | {rf[i]} | {texels[i]:.2f} | {rt[i]} | "
                  f"{mean[(s, 'err_px_mean')]:.2f} |")


if __name__ == "__main__":
    main()

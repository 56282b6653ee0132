#!/usr/bin/env python3
"""The table of docs/findings/engines.md from a run of
results/experiments/engines.toml and its `pxh report` (report/data/cost_vs_error.csv).

    engines_table.py RUN_DIR [--backend cpu|glsl]

Per preset (CPU float rows by default; both fields pooled): its engine-default s and b, the
mean and p95 texel error averaged over the views of each theta band, mean fetches per sample,
sliding and shimmering averaged over 60 <= theta <= 85, and whether the preset lies on the
error-vs-fetches Pareto front of `pxh report` (mean error against mean fetches)."""
import csv
import math
import sys
from collections import defaultdict

BANDS = [(0, 30), (30, 60), (60, 75), (75, 85.0001)]


def num(s):
    try:
        v = float(s)
        return v if math.isfinite(v) else None
    except (TypeError, ValueError):  # an empty or missing cell
        return None


def mean(xs):
    xs = [x for x in xs if x is not None]
    return sum(xs) / len(xs) if xs else None


def fmt(v, p=3):
    return "-" if v is None else f"{v:.{p}f}"


def main():
    args = sys.argv[1:]
    if not args or args[0] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if args else 2
    run = args[0]
    backend = args[args.index("--backend") + 1] if "--backend" in args else "cpu"
    rows = [r for r in csv.DictReader(open(f"{run}/results.csv")) if r["backend"] == backend]
    front = {}
    for r in csv.DictReader(open(f"{run}/report/data/cost_vs_error.csv")):
        if r["backend"] == backend:
            front[r["method"]] = r["pareto_fetches"] == "1"
    by = defaultdict(list)
    order = []
    for r in rows:
        if r["status"] != "ok":
            continue
        if r["method"] not in by:
            order.append(r["method"])
        by[r["method"]].append(r)
    head = ["preset", "s", "b"] + [f"{lo:g}-{min(hi, 85):g}° mean / p95" for lo, hi in BANDS] + \
        ["fetches", "sliding 60-85", "shimmering 60-85", "front"]
    print("| " + " | ".join(head) + " |")
    print("|---|---:|---:|" + "---:|" * (len(BANDS) + 3) + ":---:|")
    for m in order:
        rs = by[m]
        cells = [f"`{m}`", f"{float(rs[0]['scale']):g}", f"{float(rs[0]['bias']):g}"]
        for lo, hi in BANDS:
            band = [r for r in rs if lo <= float(r["theta_deg"]) < hi]
            cells.append(fmt(mean(num(r["err_mean"]) for r in band)) + " / " +
                         fmt(mean(num(r["err_p95"]) for r in band)))
        cells.append(fmt(mean(num(r["fetches_mean"]) for r in rs), 1))
        late = [r for r in rs if 60 <= float(r["theta_deg"]) <= 85]
        cells.append(fmt(mean(num(r["sliding"]) for r in late), 4))
        cells.append(fmt(mean(num(r["shimmering"]) for r in late), 4))
        cells.append("yes" if front.get(m) else "")
        print("| " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""The tables of docs/findings/methods.md from a run of results/experiments/methods.toml
and one of results/experiments/precompute.toml.

    methods_table.py METHODS_RUN_DIR [PRECOMPUTE_RUN_DIR ...]

Table 1, per method setting (method and its parameters as results.csv's `params` writes them):
the mean and p95 texel error averaged over the views of each theta band (CPU float rows, the
fields every setting ran on pooled), the mean fetches per sample, ns/sample (CPU float: the
median over the setting's rows of each row's time), ms/frame (GLSL: the median over its rows),
and, from the precompute runs, the median precompute_ms and the aux_bytes of its maps at 256^2
and 1024^2 (fbm).

The per-field tables of docs/findings/methods.md come from `pxh report` (report/fields.md: one table per
height field), not from here.

Table 2 (with precompute runs), per method with precomputed textures (and per slice count for
distance: every other setting of a method shares its maps): precompute_ms (the median
over the runs given, and its range) and aux_bytes at every field size, and the exponent a of
t ~ N^a fitted by least squares on log-log over the sizes >= 256 (a = 2: linear in the texel
count)."""
import csv
import math
import statistics
import sys
from collections import defaultdict

from engines_table import BANDS, fmt, mean, num  # the same bands and cell rules as the engines table

PRE_SIZES = (256, 1024)  # the field sizes (precompute runs) whose map cost table 1 shows


def time_in(r, unit):
    """A row's time if it is in `unit` (results.csv's time and time_unit; a file written before
    them has ns_per_sample on CPU rows and ms_per_frame on GLSL rows), else None."""
    if "time" in r:
        return num(r["time"]) if r.get("time_unit") == unit else None
    return num(r.get({"ns/sample": "ns_per_sample", "ms/frame": "ms_per_frame"}[unit], ""))


def median(xs):
    xs = [x for x in xs if x is not None]
    return statistics.median(xs) if xs else None


def fmt_bytes(b):
    if b is None:
        return "-"
    if b == 0:
        return "0"
    for unit, k in (("GiB", 1 << 30), ("MiB", 1 << 20), ("KiB", 1 << 10)):
        if b >= k:
            return f"{b / k:.1f} {unit}"
    return f"{b:.0f} B"


def key(r):
    return (r["method"], r["params"])


def label(k):
    m, p = k
    return f"`{m}`" + (f" {p.replace(';', ', ')}" if p else "")


def read_rows(run):
    with open(f"{run}/results.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    bad = [r for r in rows if r["status"] != "ok"]
    if bad:
        print(f"note: {len(bad)} rows of {run}/results.csv failed; left out", file=sys.stderr)
    return [r for r in rows if r["status"] == "ok"]


def field_size(r):
    return int(r["width"]), int(r["height"])


def resource_key(r):
    """What a method's maps depend on: the method, and `slices` for distance (the only map
    parameter; every other setting of a method shares its maps)."""
    p = dict(kv.split("=", 1) for kv in r["params"].split(";") if "=" in kv)
    return (r["method"], f"slices={p['slices']}" if "slices" in p else "")


def precompute_by_size(runs):
    """{setting: {N: (ms, bytes, ms_min, ms_max)}} from the CPU rows of one or more precompute
    runs: ms is the median over the runs (each run measures a build once per field and copies the
    figure to each row of the field), ms_min / ms_max their range."""
    out = defaultdict(dict)
    acc = defaultdict(list)
    for pre_rows in runs:
        seen = set()
        for r in pre_rows:
            w, _ = field_size(r)
            if r["backend"] != "cpu" or (resource_key(r), w) in seen:
                continue
            seen.add((resource_key(r), w))
            acc[(resource_key(r), w)].append((num(r.get("precompute_ms")), num(r.get("aux_bytes"))))
    for (k, n), vals in acc.items():
        ms = [v[0] for v in vals if v[0] is not None]
        out[k][n] = (median(ms), median(v[1] for v in vals), min(ms, default=None),
                     max(ms, default=None))
    return out


def common_fields(rows):
    """The fields every method setting ran on (a setting can be limited to some fields with
    [[methods]] heightfields = [...]); the pooled table uses only these, so that its rows
    compare like with like."""
    by = defaultdict(set)
    for r in rows:
        by[key(r)].add(r["heightfield"])
    sets = list(by.values())
    common = set.intersection(*sets) if sets else set()
    return [f for f in dict.fromkeys(r["heightfield"] for r in rows) if f in common]


def table_methods(rows, pre):
    fields = common_fields(rows)
    print("Pooled over " + ", ".join(f"`{f}`" for f in fields) + " (the fields every setting ran on).")
    print()
    rows = [r for r in rows if r["heightfield"] in fields]
    order, cpu, gl = [], defaultdict(list), defaultdict(list)
    for r in rows:
        k = key(r)
        if k not in cpu and k not in gl:
            order.append(k)
        if r["backend"] == "cpu" and r["precision"] == "float":
            cpu[k].append(r)
        elif r["backend"] == "glsl":
            gl[k].append(r)
    head = ["method"] + [f"{lo:g}-{min(hi, 85):g}° mean / p95" for lo, hi in BANDS]
    sizes = " / ".join(f"{n}²" for n in PRE_SIZES)
    head += ["fetches", "ns/sample", "ms/frame", f"precompute {sizes}", f"memory {sizes}"]
    print("| " + " | ".join(head) + " |")
    print("|---|" + "---:|" * (len(head) - 1))
    for k in order:
        rs = cpu[k]
        cells = [label(k)]
        for lo, hi in BANDS:
            band = [r for r in rs if lo <= float(r["theta_deg"]) < hi]
            cells.append(fmt(mean(num(r["err_mean"]) for r in band)) + " / " +
                         fmt(mean(num(r["err_p95"]) for r in band)))
        cells.append(fmt(mean(num(r["fetches_mean"]) for r in rs), 1))
        cells.append(fmt(median(time_in(r, "ns/sample") for r in rs), 0))
        cells.append(fmt(median(time_in(r, "ms/frame") for r in gl[k]), 2))
        by = pre.get(resource_key(rs[0]), {}) if rs else {}
        t = [by.get(n, (None, None))[:2] for n in PRE_SIZES]
        if not any(b for _, b in t):
            cells += ["-", "-"]
        else:
            cells.append(" / ".join("-" if ms is None else fmt_ms(ms) for ms, _ in t))
            cells.append(" / ".join("-" if b is None else fmt_bytes(b) for _, b in t))
        print("| " + " | ".join(cells) + " |")


def growth_exponent(by):
    """The exponent a of t ~ N^a: least squares of log t on log N over the sizes >= 256 (smaller
    builds are dominated by fixed costs), or over every size when fewer than two are >= 256."""
    pts = [(math.log(n), math.log(v[0])) for n, v in by.items() if n >= 256 and v[0] and v[0] > 0]
    if len(pts) < 2:  # a method limited to small fields: every size it ran at
        pts = [(math.log(n), math.log(v[0])) for n, v in by.items() if v[0] and v[0] > 0]
    if len(pts) < 2:
        return None
    mx = sum(x for x, _ in pts) / len(pts)
    my = sum(y for _, y in pts) / len(pts)
    sxx = sum((x - mx) ** 2 for x, _ in pts)
    return sum((x - mx) * (y - my) for x, y in pts) / sxx if sxx > 0 else None


def table_growth(pre, runs):
    sizes = sorted({n for v in pre.values() for n in v})
    print(f"precompute_ms: median of {runs} run(s) [range], aux_bytes; growth: t ~ N^a fitted over"
          " N >= 256")
    print()
    print("| method | " + " | ".join(f"{n}²" for n in sizes) + " | growth |")
    print("|---|" + "---:|" * (len(sizes) + 1))
    for k, by in pre.items():
        if all((by.get(n, (0, 0))[1] or 0) == 0 for n in sizes):
            continue
        cells = [label(k)]
        for n in sizes:
            ms, b, lo, hi = by.get(n, (None, None, None, None))
            if ms is None:
                cells.append("-")
                continue
            t = fmt_ms(ms) + (f" [{fmt_ms(lo)}–{fmt_ms(hi)}]" if runs > 1 else "")
            cells.append(t + ", " + fmt_bytes(b))
        g = growth_exponent(by)
        cells.append("-" if g is None else f"N^{g:.2f}")
        print("| " + " | ".join(cells) + " |")


def fmt_ms(ms):
    return f"{ms / 1000:.2f} s" if ms >= 1000 else f"{ms:.1f} ms"


def main():
    args = sys.argv[1:]
    if not args or args[0] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if args else 2
    rows = read_rows(args[0])
    pre = precompute_by_size([read_rows(a) for a in args[1:]])
    table_methods(rows, pre)
    if pre:
        print()
        table_growth(pre, len(args) - 1)
    return 0


if __name__ == "__main__":
    sys.exit(main())

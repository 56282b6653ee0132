#!/usr/bin/env python3
# The table of docs/findings/camera.md from a run of results/experiments/camera.toml:
#   /usr/bin/python3 scripts/camera_table.py RUN/results.csv
# Per method group (the seed methods, the engine presets) and level mode: the median over the
# group's settings of each setting's mean over its rows in a distance band (all theta) of
# err_mean (texels) and err_px_mean (screen pixels). CPU float rows for base and level, GLSL
# r32f rows for grad and implicit (the CPU has no such rows).
import csv
import statistics
import sys

SEEDS = {"parallax", "parallax_limited", "steep", "pom", "relief"}
BANDS = [(1, 2), (4, 8), (16, 32)]
rows = [r for r in csv.DictReader(open(sys.argv[1], encoding="utf-8")) if r["status"] == "ok"]


def cell(group, lod, lo, hi, col):
    per = {}
    for r in rows:
        if (r["method"] in SEEDS) != (group == "seed methods") or r["lod"] != lod:
            continue
        on_cpu = lod in ("base", "level")
        if on_cpu and not (r["backend"] == "cpu" and r["precision"] == "float"):
            continue
        if not on_cpu and not (r["backend"] == "glsl" and r["texture_format"] == "r32f"):
            continue
        if not lo <= float(r["distance"]) <= hi or not r[col]:
            continue
        per.setdefault((r["method"], r["params"]), []).append(float(r[col]))
    if not per:
        return "-"
    return f"{statistics.median(statistics.mean(v) for v in per.values()):.3g}"


lods = sorted({r["lod"] for r in rows}, key=["base", "level", "grad", "implicit"].index)
head = "| methods | lod | " + " | ".join(f"D {lo}-{hi}: texels / pixels" for lo, hi in BANDS) + " |"
print(head)
print("|" + "---|" * (2 + len(BANDS)))
for group in ("seed methods", "engine presets"):
    for lod in lods:
        cells = [f"{cell(group, lod, lo, hi, 'err_mean')} / {cell(group, lod, lo, hi, 'err_px_mean')}"
                 for lo, hi in BANDS]
        print(f"| {group} | {lod} | " + " | ".join(cells) + " |")

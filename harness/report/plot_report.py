#!/usr/bin/python3
"""Draws the plots of `pxh report` from the numbers the harness computed (report/data/*.csv).

Only drawing happens here: every value plotted was computed by pxh. Usage:
    /usr/bin/python3 harness/plot_report.py RESULTS_DIR/report
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.ticker  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def num(s):
    try:
        v = float(s)
        return v if math.isfinite(v) else None
    except (TypeError, ValueError):
        return None


# A series is identified by its keys (given as separate fields by pxh report); "series" is only
# its label.
KEYS = ("method", "params", "backend", "precision", "texture_format")


def key(r):
    return tuple(r[k] for k in KEYS)


def setting(r):
    return (r["method"], r["params"])


def group(r):
    return (r["backend"], r["texture_format"] or r["precision"])


def series_labels(rows):
    """Series keys in order of appearance, and each one's label."""
    out = {}
    for r in rows:
        out.setdefault(key(r), r["series"])
    return out


def save(fig, out, name):
    for ext in ("png", "svg"):
        fig.savefig(os.path.join(out, f"{name}.{ext}"), dpi=130, bbox_inches="tight")
    plt.close(fig)
    print(f"plot: {os.path.join(out, name)}.png/.svg")


def colours(series):
    cmap = plt.get_cmap("tab20")
    return {s: cmap(i % 20) for i, s in enumerate(series)}


def panels(n):
    cols = min(n, 2)
    rows = (n + cols - 1) // cols
    return rows, cols


def vs_theta(out, rows):
    fields = list(dict.fromkeys(r["heightfield"] for r in rows))
    label = series_labels(rows)
    series = list(label)
    col = colours(series)
    nr, nc = panels(len(fields))
    fig, axes = plt.subplots(nr, nc, figsize=(7.5 * nc, 4.8 * nr), squeeze=False)
    for ax, field in zip(axes.flat, fields):
        for s in series:
            pts = [(num(r["theta_deg"]), num(r["err_p50"]), num(r["err_p95"]))
                   for r in rows if r["heightfield"] == field and key(r) == s]
            pts = [p for p in pts if p[0] is not None]
            if not pts:
                continue
            th = [p[0] for p in pts]
            ax.plot(th, [p[1] for p in pts], "-", color=col[s], label=label[s], lw=1.6)
            ax.plot(th, [p[2] for p in pts], "--", color=col[s], lw=1.0)
        ax.set_yscale("symlog", linthresh=0.01)
        ax.set_title(field)
        ax.set_xlabel("view angle θ from the normal (degrees)")
        ax.set_ylabel("texel error (texels; solid p50, dashed p95)")
        ax.grid(True, which="both", alpha=0.3)
    for ax in list(axes.flat)[len(fields):]:
        ax.axis("off")
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="upper center", ncol=3, fontsize=8,
               bbox_to_anchor=(0.5, 1.0 + 0.03 * math.ceil(len(labels) / 3)))
    fig.suptitle("Texel error against view angle", y=1.0 + 0.03 * math.ceil(len(labels) / 3) + 0.03)
    fig.tight_layout()
    save(fig, out, "error_vs_theta")


def sweep_vs_theta(out, rows):
    rows = [r for r in rows if num(r["shimmering"]) is not None]
    if not rows:
        return
    fields = list(dict.fromkeys(r["heightfield"] for r in rows))
    label = series_labels(rows)
    series = list(label)
    col = colours(series)
    fig, axes = plt.subplots(2, len(fields), figsize=(6.5 * len(fields), 8), squeeze=False)
    for c, field in enumerate(fields):
        for r_i, column in enumerate(("sliding", "shimmering")):
            ax = axes[r_i][c]
            for s in series:
                pts = [(num(r["theta_deg"]), num(r[column])) for r in rows
                       if r["heightfield"] == field and key(r) == s]
                pts = [p for p in pts if p[0] is not None and p[1] is not None]
                if pts:
                    ax.plot([p[0] for p in pts], [p[1] for p in pts], "-o", ms=3, color=col[s],
                            label=label[s], lw=1.4)
            ax.set_yscale("symlog", linthresh=0.001)
            ax.set_title(f"{column}: {field}")
            ax.set_xlabel("view angle θ (degrees)")
            ax.set_ylabel(f"{column} (texels per degree)")
            ax.grid(True, which="both", alpha=0.3)
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="upper center", ncol=3, fontsize=8,
               bbox_to_anchor=(0.5, 1.0 + 0.03 * math.ceil(len(labels) / 3)))
    fig.tight_layout()
    save(fig, out, "sweep_vs_theta")


def cost_vs_error(out, rows):
    """One row of panels per group (backend/precision or texture format), one panel per cost it
    has. Each panel draws exactly the points its Pareto flags were computed over (by pxh): the
    group's series with that cost."""
    costs = [("fetches_mean", "pareto_fetches", "height fetches per sample"),
             ("ns_per_sample", "pareto_ns", "CPU time per sample (ns, single thread)"),
             ("ms_per_frame", "pareto_ms", "GLSL time per frame (ms, llvmpipe)")]
    groups = list(dict.fromkeys(group(r) for r in rows))
    group_label = {group(r): r["group"] for r in rows}
    col = colours(list(dict.fromkeys(setting(r) for r in rows)))
    panels_of = {g: [c for c in costs if any(group(r) == g and num(r[c[0]]) is not None
                                            and num(r["err_mean"]) is not None for r in rows)]
                 for g in groups}
    ncols = max(len(p) for p in panels_of.values())
    fig, axes = plt.subplots(len(groups), ncols, figsize=(6.5 * ncols, 5.2 * len(groups)),
                             squeeze=False)
    for g_i, g in enumerate(groups):
        for ax in axes[g_i][len(panels_of[g]):]:
            ax.axis("off")
        for ax, (cost, front, label) in zip(axes[g_i], panels_of[g]):
            pts = [(num(r[cost]), num(r["err_mean"]), r) for r in rows if group(r) == g]
            pts = [p for p in pts if p[0] is not None and p[1] is not None]
            for x, y, r in pts:
                ax.scatter([x], [y], color=col[setting(r)], s=36, zorder=3)
                ax.annotate(r["setting"], (x, y), fontsize=6.5, xytext=(4, 3),
                            textcoords="offset points")
            fr = sorted((x, y) for x, y, r in pts if r[front] == "1")
            if fr:
                ax.step([p[0] for p in fr], [p[1] for p in fr], where="post", color="black",
                        lw=1.2, ls=":", label="Pareto front", zorder=2)
                ax.legend(fontsize=8)
            xs = [p[0] for p in pts if p[0] > 0]
            if cost == "fetches_mean":
                ax.set_xscale("symlog", linthresh=1)
            elif xs and max(xs) / min(xs) > 10:
                ax.set_xscale("log")
            ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
            ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
            ax.set_yscale("symlog", linthresh=0.01)
            ax.set_ylim(bottom=0)
            ax.set_xlabel(label)
            ax.set_ylabel("mean texel error (texels)")
            ax.set_title(f"[{group_label[g]}] error against {label.split(' (')[0]}")
            ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    save(fig, out, "cost_vs_error")


def montage(out, rows):
    # Map paths are relative to the results folder, the report folder's parent.
    results = os.path.dirname(os.path.abspath(out))
    label = series_labels(rows)
    series = list(label)
    thetas = sorted({num(r["theta_deg"]) for r in rows})
    fig, axes = plt.subplots(len(series), len(thetas), figsize=(2.6 * len(thetas), 2.9 * len(series)),
                             squeeze=False)
    for i, s in enumerate(series):
        for j, th in enumerate(thetas):
            ax = axes[i][j]
            ax.axis("off")
            match = [r for r in rows if key(r) == s and num(r["theta_deg"]) == th]
            if match:
                path = os.path.join(results, match[0]["map"])
                if os.path.exists(path):
                    ax.imshow(mpimg.imread(path))
                else:
                    print(f"pxh: warning: error map not found: {path} (left blank)",
                          file=sys.stderr)
            if i == 0:
                ax.set_title(f"θ = {th:g}°", fontsize=9)
            if j == 0:
                ax.text(-0.05, 0.5, label[s], transform=ax.transAxes, rotation=90, ha="right",
                        va="center", fontsize=7)
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.5 / (2.9 * len(series))))
    fig.suptitle("Error maps (each with its own legend: log texel error)", y=1.0)
    save(fig, out, "error_maps_montage")


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: plot_report.py RESULTS_DIR/report")
    out = sys.argv[1]
    data = os.path.join(out, "data")
    vt = read(os.path.join(data, "vs_theta.csv"))
    vs_theta(out, vt)
    sweep_vs_theta(out, vt)
    cost_vs_error(out, read(os.path.join(data, "cost_vs_error.csv")))
    maps = os.path.join(data, "maps.csv")
    if os.path.exists(maps):
        montage(out, read(maps))


if __name__ == "__main__":
    main()

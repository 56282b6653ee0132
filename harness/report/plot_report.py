#!/usr/bin/python3
"""Draws the figures of `pxh report` from the numbers the harness computed (report/data/*.csv).

Only drawing happens here: every value plotted was computed by pxh. Usage:
    /usr/bin/python3 harness/report/plot_report.py RESULTS_DIR/report [--width INCHES]
                                                   [--formats png,svg,pdf]

Every figure is written as PNG (300 dpi), SVG and PDF (TrueType fonts embedded: pdf.fonttype
42), WIDTH inches wide (pxh report --figure-width: single = 3.5, double = 7) with 8 pt text.
One method setting has one colour and one marker in every figure of a report (Paul Tol's
colour-blind-safe "muted" palette plus black, markers cycling with it). Series of one setting
whose numbers agree within 0.1% on every backend / precision / texture format are drawn once,
and the legend says which agree; where they differ, each is drawn with its own line style.
report/figures.json lists what was drawn: per figure its files, panels, series and legend.
"""
import argparse
import csv
import json
import math
import os
import sys
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.lines as mlines  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import numpy as np  # noqa: E402

matplotlib.rcParams.update({
    "font.size": 8, "axes.titlesize": 8, "axes.labelsize": 8, "legend.fontsize": 7,
    "xtick.labelsize": 7, "ytick.labelsize": 7, "pdf.fonttype": 42, "ps.fonttype": 42,
    "svg.fonttype": "path", "axes.linewidth": 0.6, "lines.linewidth": 1.2,
    "lines.markersize": 3.5, "legend.frameon": False, "figure.dpi": 100,
    "svg.hashsalt": "pxh", "pdf.compression": 6,
})

# Paul Tol's "muted" scheme (https://personal.sron.nl/~pault/, colour-blind safe) and black.
PALETTE = ["#332288", "#88CCEE", "#44AA99", "#117733", "#999933", "#DDCC77", "#CC6677",
           "#882255", "#AA4499", "#000000"]
MARKERS = ["o", "s", "^", "D", "v", "P", "X", "<", ">", "*"]
GROUP_STYLES = ["-", "--", ":", "-."]
REL_TOL = 1e-3  # series within 0.1% of each other (and 1e-6 absolute) are drawn once


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def num(s):
    try:
        v = float(s)
        return v if math.isfinite(v) else None
    except (TypeError, ValueError):
        return None


def setting(r):
    return (r["method"], r["params"])


def group(r):
    return r["backend"] + "/" + (r["texture_format"] or r["precision"])


def short_params(params):
    """Parameters for a legend: those set to "off" left out, "; " between the others."""
    return ", ".join(p for p in params.split(";") if p and not p.endswith("=off"))


class Styles:
    """One colour + marker per method setting, in the order the report lists the settings."""

    def __init__(self, settings):
        self.order = list(dict.fromkeys(settings))
        labels = [(m + " " + short_params(p)).strip() for m, p in self.order]
        if len(set(labels)) < len(labels):  # shortening merged two settings: keep them whole
            labels = [(m + " " + p).strip() for m, p in self.order]
        self.labels = dict(zip(self.order, labels))

    def colour(self, s):
        return PALETTE[self.order.index(s) % len(PALETTE)]

    def marker(self, s):
        i = self.order.index(s)
        return MARKERS[(i + i // len(PALETTE)) % len(MARKERS)]

    def handle(self, s, **kw):
        return mlines.Line2D([], [], color=self.colour(s), marker=self.marker(s),
                             label=self.labels[s], **kw)


class Figures:
    """Figure size, legend and saving, with the manifest of what was drawn."""

    def __init__(self, out, width, formats):
        self.out, self.width, self.formats, self.drawn = out, width, formats, []

    def columns(self, n):
        return max(1, min(n, 3 if self.width >= 6 else 2))

    def grid(self, n, aspect=0.72, ncols=None):
        nc = ncols or self.columns(n)
        nr = max(1, math.ceil(n / nc))
        pw = self.width / nc
        fig, axes = plt.subplots(nr, nc, figsize=(self.width, pw * aspect * nr + 0.35),
                                 squeeze=False, constrained_layout=True)
        for ax in list(axes.flat)[n:]:
            ax.axis("off")
        return fig, list(axes.flat)[:n]

    def legend(self, fig, handles, title=None):
        """Below the panels, as many columns as fit the width (no empty band: the saved
        bounding box is the panels' and the legend's)."""
        if not handles:
            return []
        chars = max(len(h.get_label()) for h in handles) + 4
        ncol = max(1, min(len(handles), int(self.width * 72 / (chars * 7 * 0.55))))
        fig.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, 0.0), ncol=ncol,
                   title=title, title_fontsize=7, handlelength=2.6, columnspacing=1.2)
        return [h.get_label() for h in handles]

    def save(self, fig, name, panels, series, legend, **extra):
        files = []
        for ext in self.formats:
            path = os.path.join(self.out, f"{name}.{ext}")
            fig.savefig(path, dpi=300, bbox_inches="tight", pad_inches=0.02,
                        metadata={"svg": {"Date": None}, "pdf": {"CreationDate": None}}.get(ext))
            files.append(f"{name}.{ext}")
        plt.close(fig)
        print(f"plot: {os.path.join(self.out, name)}." + "/.".join(self.formats))
        self.drawn.append(dict(name=name, files=files, panels=panels, series=series,
                               legend=legend, **extra))

    def manifest(self):
        path = os.path.join(self.out, "figures.json")
        with open(path, "w") as f:
            json.dump({"width_in": self.width, "figures": self.drawn}, f, indent=1)
        print(f"wrote {path}")


def close(a, b):
    if a is None or b is None:
        return a is None and b is None
    return abs(a - b) <= 1e-6 + REL_TOL * max(abs(a), abs(b))


def fold(curves):
    """curves: {group: {x: (y, ...)}} of one setting. Returns [(groups, curve)]: each curve
    drawn once, with every group whose numbers agree with it within REL_TOL."""
    out = []
    for g, c in curves.items():
        for groups, ref in out:
            if ref.keys() == c.keys() and all(
                    all(close(a, b) for a, b in zip(ref[x], c[x])) for x in c):
                groups.append(g)
                break
        else:
            out.append(([g], c))
    return out


def fold_note(folded):
    """The legend's title: which groups agree (drawn once), and the line styles of the rest."""
    together = sorted({" = ".join(gs) for per in folded.values() for gs, _ in per if len(gs) > 1})
    if not together:
        return None
    return "drawn once where equal within 0.1%:\n" + "; ".join(together)


def group_handles(folded):
    """Line-style legend entries for the groups drawn separately (when some setting's groups
    differ)."""
    styles = {}
    for per in folded.values():
        if len(per) > 1:
            for i, (gs, _) in enumerate(per):
                styles.setdefault(" = ".join(gs), GROUP_STYLES[i % len(GROUP_STYLES)])
    return [mlines.Line2D([], [], color="0.3", ls=ls, label=lab) for lab, ls in styles.items()]


def field_titles(fields):
    """Panel titles: the fields' names, with the " s=.. b=.." every one of them shares taken
    out (returned once, for the legend's title)."""
    tails = {f[f.rfind(" s="):] if " s=" in f else "" for f in fields}
    if len(tails) == 1 and "" not in tails:
        tail = tails.pop()
        return {f: f[: -len(tail)] for f in fields}, "all fields:" + tail
    return {f: f for f in fields}, None


def join_notes(*notes):
    return "\n".join(n for n in notes if n) or None


def curves_of(rows, field, columns):
    """{setting: {group: {theta: values}}} of one field, points with a finite theta."""
    per = {}
    for r in rows:
        if r["heightfield"] != field or num(r["theta_deg"]) is None:
            continue
        vals = tuple(num(r[c]) for c in columns)
        if all(v is None for v in vals):
            continue
        per.setdefault(setting(r), {}).setdefault(group(r), {})[num(r["theta_deg"])] = vals
    return per


def draw_curves(ax, st, per, thin_second=False):
    """Draws one panel's curves; returns {setting: [(groups, curve)]} and the lines drawn."""
    folded, lines = {}, 0
    for s in st.order:
        if s not in per:
            continue
        folded[s] = fold(per[s])
        for i, (gs, c) in enumerate(folded[s]):
            th = sorted(c)
            ls = GROUP_STYLES[i % len(GROUP_STYLES)]
            kw = dict(color=st.colour(s), ls=ls)
            ax.plot(th, [c[t][0] for t in th], marker=st.marker(s), lw=1.1, **kw)
            lines += 1
            if thin_second:
                ax.plot(th, [c[t][1] for t in th], lw=0.6, alpha=0.55, **kw)
    return folded, lines


def log_axis(ax, linthresh):
    ax.set_yscale("symlog", linthresh=linthresh, linscale=0.4)
    ax.yaxis.set_minor_locator(matplotlib.ticker.NullLocator())
    ax.grid(True, which="major", alpha=0.3, lw=0.4)


def vs_theta(F, st, rows):
    fields = list(dict.fromkeys(r["heightfield"] for r in rows))
    titles, common = field_titles(fields)
    fig, axes = F.grid(len(fields))
    folded_all, series = {}, 0
    for k, (ax, field) in enumerate(zip(axes, fields)):
        folded, n = draw_curves(ax, st, curves_of(rows, field, ("err_p50", "err_p95")), True)
        folded_all.update(folded)
        series += n
        log_axis(ax, 0.01)
        ax.set_title(titles[field])
        ax.set_xticks([0, 30, 60, 90])
        if k % F.columns(len(fields)) == 0:
            ax.set_ylabel("texel error")
        if k >= len(fields) - F.columns(len(fields)):
            ax.set_xlabel("view angle θ (degrees)")
    handles = [st.handle(s) for s in st.order if s in folded_all] + group_handles(folded_all)
    handles += [mlines.Line2D([], [], color="0.3", lw=1.1, marker="o", label="p50"),
                mlines.Line2D([], [], color="0.3", lw=0.6, alpha=0.55, label="p95")]
    note = join_notes(common, fold_note(folded_all))
    legend = F.legend(fig, handles, note)
    F.save(fig, "error_vs_theta", len(fields), series, legend, note=note)


def sweep_vs_theta(F, st, rows):
    rows = [r for r in rows if num(r["sliding"]) is not None or num(r["shimmering"]) is not None]
    if not rows:
        return
    fields = list(dict.fromkeys(r["heightfield"] for r in rows))
    titles, common = field_titles(fields)
    panels = [(c, f) for c in ("sliding", "shimmering") for f in fields]
    fig, axes = F.grid(len(panels))
    folded_all, series = {}, 0
    nc = F.columns(len(panels))
    for k, (ax, (column, field)) in enumerate(zip(axes, panels)):
        folded, n = draw_curves(ax, st, curves_of(rows, field, (column,)))
        folded_all.update(folded)
        series += n
        log_axis(ax, 0.001)
        ax.set_title(f"{column}: {titles[field]}")
        ax.set_xticks([0, 30, 60, 90])
        if k % nc == 0:
            ax.set_ylabel("texels per degree")
        if k >= len(panels) - nc:
            ax.set_xlabel("view angle θ (degrees)")
    handles = [st.handle(s) for s in st.order if s in folded_all] + group_handles(folded_all)
    note = join_notes(common, fold_note(folded_all))
    legend = F.legend(fig, handles, note)
    F.save(fig, "sweep_vs_theta", len(panels), series, legend, note=note)


COSTS = {"fetches_mean": ("pareto_fetches", "fetches / sample (height and map lookups)"),
         "ns_per_sample": ("pareto_ns", "CPU ns / sample"),
         "ms_per_frame": ("pareto_ms", "GLSL ms / frame")}


def band_rows(rows, cost):
    """{group: {band: [rows with that cost and an error]}} in order of appearance."""
    out = {}
    for r in rows:
        if num(r[cost]) is not None and num(r["err_mean"]) is not None:
            out.setdefault(group(r), {}).setdefault(r["band"], []).append(r)
    return out


def fold_groups(per_group, cost):
    """Groups whose points (setting -> cost, error) agree within REL_TOL in every band are
    drawn once: [(groups, {band: rows})]."""
    def points(bands):
        return {(b, setting(r)): (num(r[cost]), num(r["err_mean"]), r[COSTS[cost][0]])
                for b, rs in bands.items() for r in rs}
    out = []
    for g, bands in per_group.items():
        p = points(bands)
        for gs, ref in out:
            q = points(ref)
            if q.keys() == p.keys() and all(close(q[k][0], p[k][0]) and close(q[k][1], p[k][1])
                                            and q[k][2] == p[k][2] for k in p):
                gs.append(g)
                break
        else:
            out.append(([g], bands))
    return out


def draw_front(ax, st, pts, front_col, cost):
    """The points of one panel and the front computed over exactly them."""
    for r in pts:
        s = setting(r)
        ax.plot([num(r[cost])], [num(r["err_mean"])], ls="none", marker=st.marker(s),
                color=st.colour(s), ms=4.5, zorder=3)
    fr = sorted((num(r[cost]), num(r["err_mean"])) for r in pts if r[front_col] == "1")
    if fr:
        ax.step([p[0] for p in fr], [p[1] for p in fr], where="post", color="0.2", lw=0.8,
                ls=":", zorder=2)
    return len(fr)


def cost_axes(ax, cost, xs):
    if cost == "fetches_mean":
        ax.set_xscale("symlog", linthresh=1, linscale=0.4)
    else:
        ax.set_xscale("log")
        if xs and max(xs) / min(xs) < 30:
            ax.xaxis.set_major_locator(matplotlib.ticker.LogLocator(subs=(1, 2, 5)))
    ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    log_axis(ax, 0.001)


def cost_figure(F, st, rows, name, costs):
    """One panel per band (all bands side by side at double width, two per row at single) and
    per group (groups with equal points folded into one)."""
    lines = []  # (cost, groups, {band: rows})
    for cost in costs:
        lines += [(cost, gs, bands) for gs, bands in fold_groups(band_rows(rows, cost), cost)]
    if not lines:
        return
    bands = list(dict.fromkeys(r["band"] for r in rows))
    label = {r["band"]: r["band_label"].replace("<=", "≤") for r in rows}
    nc = len(bands) if F.width >= 6 else min(2, len(bands))
    panels = [(line, b) for line in lines for b in bands]
    fig, axes = F.grid(len(panels), aspect=0.95 if nc > 3 else 0.75, ncols=nc)
    drawn, fronts = set(), []
    for k, ((cost, gs, per_band), b) in enumerate(panels):
        ax = axes[k]
        pts = per_band.get(b, [])
        drawn.update(setting(r) for r in pts)
        fronts.append(draw_front(ax, st, pts, COSTS[cost][0], cost))
        cost_axes(ax, cost, [num(r[cost]) for rs in per_band.values() for r in rs
                             if num(r[cost]) > 0])
        ys = [num(r["err_mean"]) for rs in per_band.values() for r in rs]
        ax.set_ylim(-0.0002, max(ys) * 1.6)
        ax.set_title(label[b] + (f"  [{' = '.join(gs)}]" if len(lines) > 1 else ""), fontsize=7)
        ax.set_xlabel(COSTS[cost][1], fontsize=7)
        if k % nc == 0:
            ax.set_ylabel("mean texel error" + ("" if len(lines) > 1 else f"\n({' = '.join(gs)})"),
                          fontsize=7)
        else:
            ax.tick_params(labelleft=False)
    handles = [st.handle(s, ls="none") for s in st.order if s in drawn]
    handles.append(mlines.Line2D([], [], color="0.2", ls=":", lw=0.8,
                                 label="Pareto front (of the panel's points)"))
    note = "† the band holds a single view (one θ)" if any("†" in label[b] for b in bands) else None
    legend = F.legend(fig, handles, note)
    F.save(fig, name, len(panels), len(drawn), legend,
           rows=[" = ".join(gs) for _, gs, _ in lines], bands=[label[b] for b in bands],
           front_points=fronts)


def montage(F, rows):
    """The error maps of the first field and azimuth (each PNG with its own title and legend),
    one row per series, one column per θ."""
    results = os.path.dirname(os.path.abspath(F.out))  # map paths: relative to the results
    label = {}
    for r in rows:
        label.setdefault((setting(r), group(r)), r["series"])
    series = list(label)
    thetas = sorted({num(r["theta_deg"]) for r in rows})
    cw = F.width / len(thetas)
    fig, axes = plt.subplots(len(series), len(thetas), figsize=(F.width, cw * 1.15 * len(series)),
                             squeeze=False)
    for i, s in enumerate(series):
        for j, th in enumerate(thetas):
            ax = axes[i][j]
            ax.axis("off")
            match = [r for r in rows if (setting(r), group(r)) == s and num(r["theta_deg"]) == th]
            if match:
                path = os.path.join(results, match[0]["map"])
                if os.path.exists(path):
                    ax.imshow(mpimg.imread(path))
                else:
                    print(f"pxh: warning: error map not found: {path} (left blank)",
                          file=sys.stderr)
            if i == 0:
                ax.set_title(f"θ = {th:g}°")
            if j == 0:
                ax.text(-0.05, 0.5, label[s], transform=ax.transAxes, rotation=90, ha="right",
                        va="center", fontsize=6)
    fig.subplots_adjust(wspace=0.02, hspace=0.05)
    F.save(fig, "error_maps_montage", len(series) * len(thetas), len(series), [])


def safe(name):
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in name)


def load(results, rel, cache={}):
    path = os.path.join(results, rel)
    if path not in cache:
        if not os.path.exists(path):
            print(f"pxh: warning: picture not found: {path} (left blank)", file=sys.stderr)
            cache[path] = None
        else:
            cache[path] = mpimg.imread(path)
    return cache[path]


def same_picture(results, a, b):
    x, y = load(results, a), load(results, b)
    return x is not None and y is not None and x.shape == y.shape and (x == y).all()


def fold_pictures(results, rows):
    """[(groups, row)] per setting: rows whose pictures are identical, pixel for pixel, are
    shown once."""
    out = {}
    for r in rows:
        per = out.setdefault(setting(r), [])
        for gs, ref in per:
            if same_picture(results, ref["picture"], r["picture"]):
                gs.append(group(r))
                break
        else:
            per.append(([group(r)], r))
    return out


def metrics_text(r):
    p, q = num(r["img_psnr_db"]), num(r["img_ssim"])
    psnr = "∞" if r["img_psnr_db"] in ("inf", "+inf") else (f"{p:.1f}" if p is not None else "–")
    return f"PSNR {psnr} dB, SSIM {q:.3f}" if q is not None else f"PSNR {psnr} dB"


def show(ax, img):
    ax.set_xticks([])
    ax.set_yticks([])
    for sp in ax.spines.values():
        sp.set_linewidth(0.3)
    if img is not None:
        ax.imshow(img, interpolation="nearest")


def image_grid(width, ncols, pads, bottom, left=0.0):
    """A figure of square image axes, ncols wide: pads[i] inches above row i (titles, labels),
    `bottom` inches below the last row, `left` inches for row labels; exact positions, so the
    images fill the width with no empty band."""
    gap = 0.04
    cell = (width - left - (ncols - 1) * gap) / ncols
    height = sum(pads) + len(pads) * cell + bottom
    fig = plt.figure(figsize=(width, height))
    axes, y = [], height
    for pad in pads:
        y -= pad + cell
        axes.append([fig.add_axes([(left + j * (cell + gap)) / width, y / height, cell / width,
                                   cell / height]) for j in range(ncols)])
    return fig, axes


def picture_montage(F, st, results, rows):
    """One field and view: the truth's picture, then per method setting its picture over its
    difference from the truth (identical pictures of several groups shown once)."""
    r0 = rows[0]
    folded = fold_pictures(results, rows)
    tiles = [(s, gs, r) for s in st.order if s in folded for gs, r in folded[s]]
    multi = any(len(v) > 1 for v in folded.values())
    cells = [(None, None, r0)] + tiles
    nc = min(len(cells), 6 if F.width >= 6 else 3)
    blocks = math.ceil(len(cells) / nc)
    pads = [p for k in range(blocks) for p in ((0.58 if k == 0 else 0.55), 0.03)]
    fig, axes = image_grid(F.width, nc, pads, 0.3)
    for ax in (a for row in axes for a in row):
        ax.axis("off")
    for k, (s, gs, r) in enumerate(cells):
        top, bottom = axes[2 * (k // nc)][k % nc], axes[2 * (k // nc) + 1][k % nc]
        top.axis("on")
        if s is None:
            show(top, load(results, r["picture_truth"]))
            top.set_title("truth (ray traced)", fontsize=6.5)
            continue
        bottom.axis("on")
        show(top, load(results, r["picture"]))
        show(bottom, load(results, r["picture_diff"]))
        name = textwrap.fill(st.labels[s], 30) + (f"\n[{' = '.join(gs)}]" if multi else "")
        top.set_title(name, fontsize=6)
        bottom.text(0.5, -0.04, metrics_text(r).replace(", ", "\n"), fontsize=5.5,
                    ha="center", va="top", transform=bottom.transAxes)
    groups = sorted({g for t in tiles for g in t[1]})
    note = None if multi or len(groups) < 2 else (
        " and ".join(groups) + " pictures identical, pixel for pixel: shown once")
    fig.suptitle(f"{r0['heightfield']}, θ = {num(r0['theta_deg']):g}°, "
                 f"φ = {num(r0['phi_deg']):g}°: a numbered checkerboard through each method's "
                 "uv; below it, |method − truth|" + (f"\n({note})" if note else ""),
                 fontsize=7, y=1.0, va="top")
    name = safe(f"picture_{r0['heightfield']}_t{num(r0['theta_deg']):g}_p{num(r0['phi_deg']):g}")
    F.save(fig, name, 1 + 2 * len(tiles), len(tiles), [], note=note)


def strip(F, st, results, rows):
    """One method setting over the θ sweep: truth, method, difference per θ (its first group;
    with an animated GIF of the same frames)."""
    s = setting(rows[0])
    g = group(rows[0])
    rows = sorted((r for r in rows if group(r) == g), key=lambda r: num(r["theta_deg"]))
    n = len(rows)
    fig, axes = image_grid(F.width, n, [0.4, 0.03, 0.03], 0.3, left=0.16)
    for j, r in enumerate(rows):
        for i, key in enumerate(("picture_truth", "picture", "picture_diff")):
            show(axes[i][j], load(results, r[key]))
        axes[0][j].set_title(f"θ = {num(r['theta_deg']):g}°", fontsize=7)
        axes[2][j].text(0.5, -0.04, metrics_text(r).replace(", ", "\n"), fontsize=5.5,
                        ha="center", va="top", transform=axes[2][j].transAxes)
    for i, lab in enumerate(("truth", textwrap.fill(st.labels[s], 18), "|difference|")):
        axes[i][0].set_ylabel(lab, fontsize=6)
    r0 = rows[0]
    fig.suptitle(f"{st.labels[s]} [{g}] on {r0['heightfield']} over the θ sweep "
                 f"(φ = {num(r0['phi_deg']):g}°)", fontsize=7, y=1.0, va="top")
    name = safe(f"strip_{r0['heightfield']}_p{num(r0['phi_deg']):g}")
    F.save(fig, name, 3 * n, 1, [])
    animate(F, results, rows, name, f"{st.labels[s]} [{g}] on {r0['heightfield']}")


def animate(F, results, rows, name, what):
    """An animated GIF: per θ, truth | method | difference side by side (Pillow, the
    python3-pil package matplotlib depends on)."""
    from PIL import Image, ImageDraw
    frames = []
    for r in rows:
        imgs = [load(results, r[k]) for k in ("picture_truth", "picture", "picture_diff")]
        if any(i is None for i in imgs):
            return
        row = np.concatenate([i[..., :3] for i in imgs], axis=1)
        img = Image.fromarray((row * 255).round().astype("uint8")).resize(
            (row.shape[1] * 2, row.shape[0] * 2), Image.NEAREST)
        canvas = Image.new("RGB", (img.width, img.height + 16), "white")
        canvas.paste(img, (0, 16))
        ImageDraw.Draw(canvas).text(
            (4, 2), f"{what}  theta = {num(r['theta_deg']):g} deg  (truth | method | difference)"
            f"  {metrics_text(r).replace('∞', 'inf')}", fill="black")
        frames.append(canvas)
    path = os.path.join(F.out, name + ".gif")
    frames[0].save(path, save_all=True, append_images=frames[1:], duration=900, loop=0)
    print(f"plot: {path}")
    F.drawn[-1]["files"].append(name + ".gif")


def pictures(F, st, rows):
    results = os.path.dirname(os.path.abspath(F.out))
    views = {}
    strips = {}
    for r in rows:
        if "montage" in r["picture_use"].split():
            views.setdefault((r["heightfield"], r["theta_deg"], r["phi_deg"]), []).append(r)
        if "strip" in r["picture_use"].split():
            strips.setdefault((r["heightfield"], r["phi_deg"]), []).append(r)
    for v in views.values():
        picture_montage(F, st, results, v)
    for v in strips.values():
        strip(F, st, results, v)


def parse_args(argv):
    ap = argparse.ArgumentParser(prog="plot_report.py")
    ap.add_argument("report", help="RESULTS_DIR/report (with data/*.csv)")
    ap.add_argument("--width", type=float, default=7.0, help="figure width in inches, [2, 20]")
    ap.add_argument("--formats", default="png,svg,pdf", help="comma list of png, svg, pdf")
    a = ap.parse_args(argv[1:])
    formats = a.formats.split(",")
    if not (math.isfinite(a.width) and 2 <= a.width <= 20):
        ap.error(f"--width {a.width:g}: not a width in inches in [2, 20]")
    if not formats or any(f not in ("png", "svg", "pdf") for f in formats):
        ap.error(f"--formats {a.formats}: not a comma list of png, svg, pdf")
    return a.report, a.width, formats


def main():
    out, width, formats = parse_args(sys.argv)
    data = os.path.join(out, "data")
    F = Figures(out, width, formats)
    vt = read(os.path.join(data, "vs_theta.csv"))
    cost = read(os.path.join(data, "cost_vs_error.csv"))
    bands = read(os.path.join(data, "cost_vs_error_bands.csv"))
    st = Styles([setting(r) for r in cost + vt + bands])
    vs_theta(F, st, vt)
    sweep_vs_theta(F, st, vt)
    cost_figure(F, st, bands, "cost_vs_error", ["fetches_mean"])
    cost_figure(F, st, bands, "time_vs_error", ["ns_per_sample", "ms_per_frame"])
    maps = os.path.join(data, "maps.csv")
    if os.path.exists(maps):
        montage(F, read(maps))
    pics = os.path.join(data, "pictures.csv")
    if os.path.exists(pics):
        pictures(F, st, read(pics))
    F.manifest()


if __name__ == "__main__":
    main()

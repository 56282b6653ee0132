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

Files are written as pxh report writes them (report/manifest.txt lists every one): through a
temporary name created exclusively, never following a link, then linked to their name; a name
that exists and is not in the manifest is someone else's file and stops the script (exit 2).
Picture and map paths must lie inside the results folder with no link on the way (exit 2).
Any field or method name draws: labels too long for the width are shortened in the middle (…).
"""
import argparse
import csv
import errno
import io
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


MANIFEST = "manifest.txt"


def fail(msg, status=2):
    print("pxh: error: " + msg.replace("\n", "\\n"), file=sys.stderr)
    sys.exit(status)


class Own:
    """The report folder's files as pxh report writes them (harness/report/report_data.h)."""

    def __init__(self, out):
        self.out = out
        self.manifest = os.path.join(out, MANIFEST)
        if os.path.islink(out):
            fail(f"{out}: is a symbolic link; pxh report writes only into a folder of its own")
        try:
            fd = os.open(self.manifest, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW,
                         0o644)
            os.write(fd, b"# The files pxh report wrote in this folder, one a line: the next "
                         b"pxh report removes exactly these, and nothing else.\n")
            os.close(fd)
        except FileExistsError:
            pass
        if os.path.islink(self.manifest) or not os.path.isfile(self.manifest):
            fail(f"{self.manifest}: is not a regular file (a link?), so not pxh report's list "
                 "of its files")
        with open(self.manifest, encoding="utf-8", errors="replace") as f:
            self.ours = {line.rstrip("\n") for line in f if not line.startswith("#")}

    def record(self, name):
        fd = os.open(self.manifest, os.O_WRONLY | os.O_APPEND | os.O_NOFOLLOW)
        try:
            os.write(fd, (name + "\n").encode("utf-8", "surrogateescape"))
        finally:
            os.close(fd)
        self.ours.add(name)

    def write(self, name, writer):
        """writer(binary file) writes the contents; then the file takes its name."""
        path = os.path.join(self.out, name)
        tmp_name = f".{name}.tmp-{os.getpid()}"
        tmp = os.path.join(self.out, tmp_name)
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o644)
        self.record(tmp_name)
        try:
            with os.fdopen(fd, "wb") as f:
                writer(f)
        except BaseException:
            os.unlink(tmp)
            raise
        if name in self.ours and os.path.isfile(path) and not os.path.islink(path):
            os.unlink(path)  # ours, from an earlier drawing: replaced
        try:
            os.link(tmp, path)
        except FileExistsError:
            os.unlink(tmp)
            fail(f"{path}: exists and pxh report did not write it (it is not in "
                 f"{self.manifest}); move it away or remove it")
        except OSError as e:
            if e.errno not in (errno.EPERM, errno.ENOTSUP, errno.EXDEV, errno.EMLINK) or \
                    os.path.lexists(path):
                os.unlink(tmp)
                raise
            os.rename(tmp, path)  # a file system without hard links
        else:
            os.unlink(tmp)
        self.record(name)


def inside(results, rel, what):
    """RESULTS/rel, refused (exit 2) unless rel is relative, without '..' and with no link on
    the way."""
    if os.path.isabs(rel) or ".." in rel.split("/"):
        fail(f"{what}: '{rel}' lies outside the results folder {results}; refused")
    at = results
    for part in rel.split("/"):
        at = os.path.join(at, part)
        if os.path.islink(at):
            fail(f"{what}: '{rel}' passes through a symbolic link ({at}); refused")
    return os.path.join(results, rel)


def ellipsize(text, n):
    """text shortened in the middle to n characters (…) when longer."""
    n = max(n, 5)
    if len(text) <= n:
        return text
    head = (n - 1) - (n - 1) // 2
    return text[:head] + "…" + text[len(text) - (n - 1) // 2:]


def chars_for(width_in, fontsize):
    """How many characters of an fontsize-pt label fit width_in inches (DejaVu Sans averages
    about 0.6 em a character)."""
    return max(5, int(width_in * 72 / (fontsize * 0.62)))


def fit(text, width_in, fontsize, lines=2):
    """text wrapped into at most `lines` lines of width_in inches, the rest shortened (…)."""
    n = chars_for(width_in, fontsize)
    for sym in ("θ", "φ"):  # "φ = 0°" is never broken across lines (no-break spaces)
        text = text.replace(f"{sym} = ", f"{sym}\u00a0=\u00a0")
    out = []
    for para in text.split("\n"):
        out += textwrap.wrap(para, n, break_long_words=False, break_on_hyphens=False) or [""]
    if len(out) > lines:
        out = out[: lines - 1] + [ellipsize(" ".join(out[lines - 1:]), n)]
    return "\n".join(ellipsize(line, n) for line in out)


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

    def __init__(self, settings, width=7.0):
        self.order = list(dict.fromkeys(settings))
        labels = [(m + " " + short_params(p)).strip() for m, p in self.order]
        if len(set(labels)) < len(labels):  # shortening merged two settings: keep them whole
            labels = [(m + " " + p).strip() for m, p in self.order]
        n = chars_for(0.85 * width - 0.5, 7)  # a legend entry: at most the width, less a handle
        short = [ellipsize(lab, n) for lab in labels]
        if len(set(short)) < len(short):  # two shortened alike: numbered
            short = [f"{lab} ({i + 1})" for i, lab in enumerate(short)]
        self.labels = dict(zip(self.order, short))
        self.full = dict(zip(self.order, labels))  # unshortened, for titles that wrap
        # legend entries: whole, wrapped onto two lines where one is too narrow (shortened only
        # beyond that)
        wrapped = [fit(lab, 0.9 * width - 0.45, 7, 2) for lab in labels]
        self.legend_labels = dict(zip(self.order, (
            sh if len(lab) <= n or "…" in w else w for lab, sh, w in zip(labels, short, wrapped))))
        if len(set(self.legend_labels.values())) < len(labels):
            self.legend_labels = dict(self.labels)

    def colour(self, s):
        return PALETTE[self.order.index(s) % len(PALETTE)]

    def marker(self, s):
        i = self.order.index(s)
        return MARKERS[(i + i // len(PALETTE)) % len(MARKERS)]

    def handle(self, s, **kw):
        return mlines.Line2D([], [], color=self.colour(s), marker=self.marker(s),
                             label=self.legend_labels[s], **kw)


class Figures:
    """Figure size, legend and saving, with the manifest of what was drawn."""

    def __init__(self, out, width, formats):
        self.out, self.width, self.formats, self.drawn = out, width, formats, []
        self.own = Own(out)

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
        if title:
            title = "\n".join(fit(t, self.width - 0.1, 7, lines=3) for t in title.split("\n"))
        chars = max(len(line) for h in handles for line in h.get_label().split("\n")) + 4
        ncol = max(1, min(len(handles), int(self.width * 72 / (chars * 7 * 0.55))))
        renderer = fig.canvas.get_renderer()
        while True:  # as many columns as fit the width, measured
            leg = fig.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, 0.0),
                             ncol=ncol, title=title, title_fontsize=7, handlelength=2.6,
                             columnspacing=1.2)
            if ncol == 1 or leg.get_window_extent(renderer).width <= self.width * fig.dpi - 4:
                break
            leg.remove()
            ncol -= 1
        return [h.get_label() for h in handles]

    def save(self, fig, name, panels, series, legend, **extra):
        files = []
        for ext in self.formats:
            meta = {"svg": {"Date": None}, "pdf": {"CreationDate": None}}.get(ext)
            self.own.write(f"{name}.{ext}", lambda f: fig.savefig(
                f, format=ext, dpi=300, bbox_inches="tight", pad_inches=0.02, metadata=meta))
            files.append(f"{name}.{ext}")
        plt.close(fig)
        print(f"plot: {os.path.join(self.out, name)}." + "/.".join(self.formats))
        self.drawn.append(dict(name=name, files=files, panels=panels, series=series,
                               legend=legend, **extra))

    def manifest(self):
        path = os.path.join(self.out, "figures.json")
        text = json.dumps({"width_in": self.width, "figures": self.drawn}, indent=1)
        self.own.write("figures.json", lambda f: f.write(text.encode("utf-8")))
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
                ax.plot(th, [c[t][1] for t in th], lw=0.6, marker=st.marker(s), ms=3,
                        mfc="white", mew=0.6, **kw)  # p95: hollow markers, as the legend says
    return folded, lines


def decade_ticks(lo, hi, max_n, first_step=0):
    """Decades 10^k in [lo, hi], every k-th so that at most max_n remain (the highest kept)."""
    if not (hi > 0 and lo > 0):
        return []
    ks = list(range(math.ceil(math.log10(lo) - 1e-9) + first_step,
                    math.floor(math.log10(hi) + 1e-9) + 1))
    if not ks:
        return []
    step = max(1, math.ceil(len(ks) / max(1, max_n)))
    return [10.0 ** k for k in ks[::-1][::step][::-1]]


def log_ticks(lo, hi, max_n):
    """Ticks for a log axis over [lo, hi]: 1-2-5 steps where they fit, else 1-3, else
    decades (every k-th where even those do not fit)."""
    for subs in ((1, 2, 5), (1, 3)):
        t = [m * 10.0 ** e for e in range(math.floor(math.log10(lo)) - 1,
                                          math.ceil(math.log10(hi)) + 1) for m in subs]
        t = [v for v in t if lo * (1 - 1e-9) <= v <= hi * (1 + 1e-9)]
        if 2 <= len(t) <= max_n:
            return t
    t = decade_ticks(lo, hi, max_n)
    return t if len(t) >= 2 else [v for v in (lo, hi)]


def tick_text(v):
    if v == 0:
        return "0"
    if abs(v) >= 1e4 or abs(v) < 1e-2:
        e = math.floor(math.log10(abs(v)) + 1e-9)
        m = v / 10 ** e
        return f"$10^{{{e}}}$" if abs(m - 1) < 1e-9 else f"${m:g}\\times10^{{{e}}}$"
    return f"{v:g}"


def error_axis(ax, linthresh, top, height_in):
    """A symlog error axis from 0 to top: ticks 0 and decades (none crowding the 0)."""
    ax.set_yscale("symlog", linthresh=linthresh, linscale=0.4)
    ax.set_ylim(0, top)
    max_n = max(2, int(height_in * 72 / 16))
    ticks = [0.0] + decade_ticks(linthresh, top, max_n - 1, first_step=1)
    ax.yaxis.set_major_locator(matplotlib.ticker.FixedLocator(ticks))
    ax.yaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: tick_text(v)))
    ax.yaxis.set_minor_locator(matplotlib.ticker.NullLocator())
    ax.grid(True, which="major", alpha=0.3, lw=0.4)


def top_of(values, linthresh):
    v = [x for x in values if x is not None and math.isfinite(x)]
    return max(max(v) * 1.6 if v else 0, linthresh * 10)


def theta_axis(ax, show_labels):
    ax.set_xlim(-3, 93)
    ax.set_xticks([0, 30, 60, 90])
    if not show_labels:
        ax.tick_params(labelbottom=False)


def panel_size(F, nc, aspect):
    pw = F.width / nc
    return pw, pw * aspect


def by_view(rows):
    """[(rows, tag, title)] per camera view of vs_theta.csv rows (the camera's keys: a view
    each, in ascending order of their values; one, with no tag or title, for a camera
    without keys or data without the field)."""
    views = {}
    for r in rows:
        views.setdefault(r.get("camera_view") or "", []).append(r)

    def values(v):
        return [num(p.split("=", 1)[1]) or 0 for p in v.split() if "=" in p]
    return [(vr, vr[0].get("camera_tag") or "", view_title(vr[0]))
            for v, vr in sorted(views.items(), key=lambda kv: values(kv[0]))]


def vs_theta(F, st, rows, tag="", cam=""):
    """error_vs_theta: p50 and p95 texel error against θ, a panel per field; a camera view's
    (error_vs_theta_d4_f45_r256: one per view) with its pixel error in the rows below."""
    if cam and any(num(r.get("err_px_p50")) is not None for r in rows):
        return vs_theta_camera(F, st, rows, tag, cam)
    fields = list(dict.fromkeys(r["heightfield"] for r in rows))
    titles, common = field_titles(fields)
    nc = F.columns(len(fields))
    fig, axes = F.grid(len(fields))
    pw, ph = panel_size(F, nc, 0.72)
    folded_all, series = {}, 0
    for k, (ax, field) in enumerate(zip(axes, fields)):
        folded, n = draw_curves(ax, st, curves_of(rows, field, ("err_p50", "err_p95")), True)
        folded_all.update(folded)
        series += n
        top = top_of([num(r["err_p95"]) for r in rows if r["heightfield"] == field], 0.01)
        error_axis(ax, 0.01, top, ph)
        ax.set_title(fit(titles[field], 0.8 * pw, 8, 2))
        theta_axis(ax, k >= len(fields) - nc)
        if k % nc == 0:
            ax.set_ylabel("texel error")
        if k >= len(fields) - nc:
            ax.set_xlabel("view angle θ (°)")
    handles = [st.handle(s) for s in st.order if s in folded_all] + group_handles(folded_all)
    handles += [mlines.Line2D([], [], color="0.3", lw=1.1, marker="o", label="p50"),
                mlines.Line2D([], [], color="0.3", lw=0.7, marker="o", mfc="white",
                              label="p95")]
    phis = sorted({p for r in rows for p in r.get("phi_deg_list", "").split(";") if p},
                  key=lambda p: num(p) if num(p) is not None else 0)
    azimuth = ("means over the azimuths φ = " + ", ".join(phis) + "°") if len(phis) > 1 else (
        f"φ = {phis[0]}°" if phis else None)
    note = join_notes(azimuth, f"camera: {cam}" if cam else None, common,
                      fold_note(folded_all))
    legend = F.legend(fig, handles, note)
    F.save(fig, "error_vs_theta" + tag, len(fields), series, legend, note=note)


def azimuth_note(rows):
    phis = sorted({p for r in rows for p in r.get("phi_deg_list", "").split(";") if p},
                  key=lambda p: num(p) if num(p) is not None else 0)
    return ("means over the azimuths φ = " + ", ".join(phis) + "°") if len(phis) > 1 else (
        f"φ = {phis[0]}°" if phis else None)


def vs_theta_camera(F, st, rows, tag, cam):
    """A camera view's error_vs_theta: texel error (top rows) and pixel error |J⁻¹e| (rows
    below), p50 solid, p95 hollow, a panel per field."""
    fields = list(dict.fromkeys(r["heightfield"] for r in rows))
    titles, common = field_titles(fields)
    nc = F.columns(len(fields))
    per = math.ceil(len(fields) / nc)
    fig, grid = plt.subplots(2 * per, nc, figsize=(F.width, F.width / nc * 0.72 * 2 * per + 0.35),
                             squeeze=False, constrained_layout=True)
    pw, ph = panel_size(F, nc, 0.72)
    folded_all, series, panels = {}, 0, 0
    for q, (p50, p95, what) in enumerate((("err_p50", "err_p95", "texel error"),
                                          ("err_px_p50", "err_px_p95", "pixel error"))):
        for k in range(per * nc):
            ax = grid[q * per + k // nc][k % nc]
            if k >= len(fields):
                ax.axis("off")
                continue
            field = fields[k]
            folded, n = draw_curves(ax, st, curves_of(rows, field, (p50, p95)), True)
            folded_all.update(folded)
            series += n
            panels += 1
            vals = [num(r[c]) for r in rows if r["heightfield"] == field for c in (p50, p95)]
            lin = linthresh_of(vals, 0.01)
            error_axis(ax, lin, top_of(vals, lin), ph)
            ax.set_title(fit(f"{what.split()[0]}: {titles[field]}", 0.8 * pw, 8, 2))
            bottom = q == 1 and k >= len(fields) - nc
            theta_axis(ax, bottom)
            if k % nc == 0:
                ax.set_ylabel(what)
            if bottom:
                ax.set_xlabel("view angle θ (°)")
    handles = [st.handle(s) for s in st.order if s in folded_all] + group_handles(folded_all)
    handles += [mlines.Line2D([], [], color="0.3", lw=1.1, marker="o", label="p50"),
                mlines.Line2D([], [], color="0.3", lw=0.7, marker="o", mfc="white",
                              label="p95")]
    note = join_notes(f"camera: {cam}; top: texel error, below: pixel error |J⁻¹e|",
                      azimuth_note(rows), common, fold_note(folded_all))
    legend = F.legend(fig, handles, note)
    F.save(fig, "error_vs_theta" + tag, panels, series, legend, note=note)


def sweep_vs_theta(F, st, rows, tag="", cam=""):
    last_theta = max((num(r["theta_deg"]) for r in rows if num(r["theta_deg"]) is not None),
                     default=None)
    rows = [r for r in rows if num(r["sliding"]) is not None or num(r["shimmering"]) is not None]
    if not rows:
        return
    missing_last = all(num(r["theta_deg"]) != last_theta for r in rows)
    fields = list(dict.fromkeys(r["heightfield"] for r in rows))
    titles, common = field_titles(fields)
    nc = F.columns(len(fields))
    per = math.ceil(len(fields) / nc)  # rows of panels per quantity
    fig, grid = plt.subplots(2 * per, nc, figsize=(F.width, F.width / nc * 0.72 * 2 * per + 0.35),
                             squeeze=False, constrained_layout=True)
    pw, ph = panel_size(F, nc, 0.72)
    folded_all, series, panels = {}, 0, 0
    for q, column in enumerate(("sliding", "shimmering")):
        for k in range(per * nc):
            ax = grid[q * per + k // nc][k % nc]
            if k >= len(fields):
                ax.axis("off")
                continue
            field = fields[k]
            folded, n = draw_curves(ax, st, curves_of(rows, field, (column,)))
            folded_all.update(folded)
            series += n
            panels += 1
            top = top_of([num(r[column]) for r in rows if r["heightfield"] == field], 0.001)
            error_axis(ax, 0.001, top, ph)
            ax.set_title(fit(f"{column}: {titles[field]}", 0.8 * pw, 8, 2))
            bottom = k >= len(fields) - nc
            theta_axis(ax, bottom)
            if k % nc == 0:
                ax.set_ylabel("texels / degree")
            if bottom:
                ax.set_xlabel("view angle θ (°)")
    handles = [st.handle(s) for s in st.order if s in folded_all] + group_handles(folded_all)
    why = (f"sliding, shimmering: change to the next θ of the sweep, so the last θ "
           f"({last_theta:g}°) has none (sweep_dt_deg gives every θ a step)"
           ) if missing_last else None
    note = join_notes("top rows: sliding; bottom rows: shimmering (each a mean over φ)",
                      f"camera: {cam}" if cam else None, why, common, fold_note(folded_all))
    legend = F.legend(fig, handles, note)
    F.save(fig, "sweep_vs_theta" + tag, panels, series, legend, note=note)


def distance_axis(ax, distances, show_labels, width_in):
    """A log axis over the swept eye distances (tiles), ticked at the distances themselves, as
    many as fit the panel's width (a label about 0.3 in)."""
    lo, hi = min(distances), max(distances)
    ax.set_xscale("log")
    ax.set_xlim(lo / 1.25, hi * 1.25)
    ticks = sorted(set(distances))
    max_n = max(2, min(6, int(width_in / 0.3)))
    while len(ticks) > max_n:
        ticks = ticks[::2]
    ax.xaxis.set_major_locator(matplotlib.ticker.FixedLocator(ticks))
    ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    ax.xaxis.set_minor_locator(matplotlib.ticker.NullLocator())
    if not show_labels:
        ax.tick_params(labelbottom=False)


def vs_distance(F, st, rows):
    """error_vs_distance_FIELD: texel error (top row) and pixel error (bottom row) against the
    eye's distance, a column per view angle; one figure per field (named by it, as the error
    maps and pictures are), means and p95 as in vs_theta."""
    if not rows:
        return
    fields = list(dict.fromkeys(r["heightfield"] for r in rows))
    for field in fields:
        vs_distance_field(F, st, [r for r in rows if r["heightfield"] == field],
                          safe(f"error_vs_distance_{field}"))


def linthresh_of(values, most=0.01):
    """The linear range of a symlog error axis: a decade below the smallest positive value
    (at most `most`), so small errors (pixel errors near 1e-3 far away) lie on the log part,
    with a decade tick at or below them, and are not squashed onto the axis."""
    v = [x for x in values if x is not None and math.isfinite(x) and x > 0]
    if not v:
        return most
    return min(most, 10.0 ** (math.floor(math.log10(min(v)) + 1e-9) - 1))


def vs_distance_field(F, st, rows, name):
    fields = list(dict.fromkeys(r["heightfield"] for r in rows))
    thetas = sorted({num(r["theta_deg"]) for r in rows if num(r["theta_deg"]) is not None})
    distances = sorted({num(r["distance"]) for r in rows if num(r["distance"]) is not None})
    if not thetas or len(distances) < 2:
        return
    titles, common = field_titles(fields)
    nc = len(thetas)
    nr = 2 * len(fields)
    pw = F.width / nc
    ph = pw * 0.72
    fig, grid = plt.subplots(nr, nc, figsize=(F.width, ph * nr + 0.35), squeeze=False,
                             constrained_layout=True)
    folded_all, series, panels, y_ticks = {}, 0, 0, {}
    quantities = (("err_mean", "err_p95", "texel error", 0.01),
                  ("err_px_mean", "err_px_p95", "pixel error", 0.01))
    for f, field in enumerate(fields):
        for q, (mean, p95, label, lin) in enumerate(quantities):
            for c, theta in enumerate(thetas):
                ax = grid[2 * f + q][c]
                per = {}
                for r in rows:
                    if r["heightfield"] != field or num(r["theta_deg"]) != theta:
                        continue
                    x = num(r["distance"])
                    vals = (num(r[mean]), num(r[p95]))
                    if x is None or all(v is None for v in vals):
                        continue
                    per.setdefault(setting(r), {}).setdefault(group(r), {})[x] = vals
                folded, n = draw_curves(ax, st, per, True)
                folded_all.update(folded)
                series += n
                panels += 1
                vals = [num(r[k]) for r in rows if r["heightfield"] == field
                        for k in (mean, p95)]
                lin_q = linthresh_of(vals, lin)
                top = top_of([num(r[p95]) for r in rows if r["heightfield"] == field], lin_q)
                error_axis(ax, lin_q, top, ph)
                # every decade marked (unlabelled where the labels were thinned to fit)
                ax.yaxis.set_minor_locator(matplotlib.ticker.FixedLocator(
                    decade_ticks(lin_q, top, 100, first_step=1)))
                y_ticks.setdefault(label, [float(t) for t in ax.get_yticks()])
                last = 2 * f + q == nr - 1
                distance_axis(ax, distances, last, pw)
                head = f"θ = {theta:g}°" + ("" if len(fields) == 1 else f", {titles[field]}")
                ax.set_title(fit(head, 0.8 * pw, 8, 2))
                if c == 0:
                    ax.set_ylabel(label)
                if last and c == nc // 2:  # one label under the middle column
                    ax.set_xlabel("eye distance (tiles)")
    handles = [st.handle(s) for s in st.order if s in folded_all] + group_handles(folded_all)
    handles += [mlines.Line2D([], [], color="0.3", lw=1.1, marker="o", label="mean"),
                mlines.Line2D([], [], color="0.3", lw=0.7, marker="o", mfc="white",
                              label="p95")]
    field_note = f"field: {fields[0]}" if len(fields) == 1 else common
    note = join_notes("top: texel error; bottom: pixel error |J⁻¹e| (means over φ and fov)",
                      field_note, fold_note(folded_all))
    legend = F.legend(fig, handles, note)
    F.save(fig, name, panels, series, legend, note=note, y_ticks=y_ticks)


def unit_of(cost):
    """The unit of a time cost column, time[UNIT] (one per time_unit of the rows), or None."""
    return cost[5:-1] if cost.startswith("time[") and cost.endswith("]") else None


def cost_info(cost):
    """(Pareto column, axis label, note) of a cost column: fetches_mean or time[UNIT]."""
    if cost == "fetches_mean":
        return ("pareto_fetches", "fetches / sample", "fetches: height and map lookups")
    return (f"pareto_{cost}", f"time ({unit_of(cost)})", None)


def time_costs(rows):
    """The time[UNIT] columns of cost_vs_error_bands.csv, in the harness's order."""
    return [c for c in (rows[0].keys() if rows else []) if unit_of(c)]


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
        return {(b, setting(r)): (num(r[cost]), num(r["err_mean"]), r[cost_info(cost)[0]])
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


def spread_of(r, cost):
    """The timing repeats' range of a point (mean of the rows' min and max), or None."""
    unit = unit_of(cost)
    if unit is None:
        return None
    lo, hi = (num(r.get(f"time_{c}[{unit}]", "")) for c in ("min", "max"))
    return (lo, hi) if lo is not None and hi is not None and hi >= lo else None


def draw_front(ax, st, pts, front_col, cost):
    """The points of one panel (with the timing spread) and the front over exactly them."""
    spreads = 0
    for r in pts:
        s = setting(r)
        x, y = num(r[cost]), num(r["err_mean"])
        sp = spread_of(r, cost)
        if sp and sp[1] > sp[0]:
            ax.plot(list(sp), [y, y], color=st.colour(s), lw=0.9, alpha=0.8, zorder=2.5,
                    solid_capstyle="butt")
            spreads += 1
        ax.plot([x], [y], ls="none", marker=st.marker(s), color=st.colour(s), ms=4, zorder=3)
    fr = sorted((num(r[cost]), num(r["err_mean"])) for r in pts if r[front_col] == "1")
    if fr:
        ax.step([p[0] for p in fr], [p[1] for p in fr], where="post", color="0.2", lw=0.8,
                ls=":", zorder=2)
    return len(fr), spreads


def cost_axis(ax, cost, lo, hi, width_in, show_labels):
    """One x range for a row of panels: [lo, hi] with a margin; ticks that fit the panel."""
    max_n = max(2, int(width_in * 72 / 26))
    if cost == "fetches_mean":
        ax.set_xscale("symlog", linthresh=1, linscale=0.4)
        ax.set_xlim(0 if lo < 1 else lo / 1.4, hi * 1.4)
        ticks = ([0.0] if lo < 1 else []) + log_ticks(max(1, lo), max(hi, 2),
                                                      max_n - (lo < 1))
    else:
        ax.set_xscale("log")
        ax.set_xlim(lo / 1.4, hi * 1.4)
        ticks = log_ticks(lo / 1.4, hi * 1.4, max_n)
    ax.xaxis.set_major_locator(matplotlib.ticker.FixedLocator(ticks))
    ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: tick_text(v)))
    ax.xaxis.set_minor_locator(matplotlib.ticker.NullLocator())
    if not show_labels:
        ax.tick_params(labelbottom=False)


def cost_figure(F, st, rows, name, costs, cam=""):
    """Per cost and group (groups with equal points folded into one) a block of panels, one
    per band (all bands side by side at double width, two per row at single); one x range per
    block and one y range per row of panels, so a row reads across."""
    lines = []  # (cost, groups, {band: rows})
    for cost in costs:
        lines += [(cost, gs, bands) for gs, bands in fold_groups(band_rows(rows, cost), cost)]
    if not lines:
        return
    bands = list(dict.fromkeys(r["band"] for r in rows))
    label = {r["band"]: r["band_label"].replace("<=", "≤") for r in rows}
    nc = len(bands) if F.width >= 6 else min(2, len(bands))
    per = math.ceil(len(bands) / nc)
    aspect = 0.95 if nc > 3 else 0.75
    pw, ph = panel_size(F, nc, aspect)
    fig, grid = plt.subplots(per * len(lines), nc, figsize=(F.width, ph * per * len(lines) + 0.3),
                             squeeze=False, constrained_layout=True)
    drawn, fronts, spreads = set(), [], 0
    for li, (cost, gs, per_band) in enumerate(lines):
        xs = [v for rs in per_band.values() for r in rs
              for v in [num(r[cost])] + list(spread_of(r, cost) or ())]
        positive = [x for x in xs if x > 0]
        lo, hi = (min(positive), max(positive)) if positive else (1, 10)
        if cost == "fetches_mean" and any(x <= 0 for x in xs):
            lo = 0
        for row in range(per):
            ys = [num(r["err_mean"]) for b in bands[row * nc:(row + 1) * nc]
                  for r in per_band.get(b, [])]
            top = top_of(ys, 0.001)
            for col in range(nc):
                ax = grid[li * per + row][col]
                bi = row * nc + col
                if bi >= len(bands):
                    ax.axis("off")
                    continue
                b = bands[bi]
                pts = per_band.get(b, [])
                drawn.update(setting(r) for r in pts)
                f, n = draw_front(ax, st, pts, cost_info(cost)[0], cost)
                fronts.append(f)
                spreads += n
                last = row == per - 1 or bi + nc >= len(bands)
                cost_axis(ax, cost, lo, hi, pw, last)
                error_axis(ax, 0.001, top, ph)
                ax.set_title(label[b], fontsize=7)
                if last:
                    ax.set_xlabel(cost_info(cost)[1], fontsize=7)
                if col == 0:
                    ax.set_ylabel(fit("mean texel error" + (f"\n{' = '.join(gs)}"), ph, 7, 2),
                                  fontsize=7)
                else:
                    ax.tick_params(labelleft=False)
    handles = [st.handle(s, ls="none") for s in st.order if s in drawn]
    handles.append(mlines.Line2D([], [], color="0.2", ls=":", lw=0.8,
                                 label="Pareto front (of the panel's points)"))
    if spreads:
        handles.append(mlines.Line2D([], [], color="0.3", lw=0.9,
                                     label="timing repeats' range (min to max)"))
    notes = [cost_info(c)[2] for c in costs if cost_info(c)[2]]
    if any("†" in label[b] for b in bands):
        notes.append("† the band holds a single view (one θ)")
    notes.append("means over the fields, azimuths and θ of each band")
    if cam:
        notes.append(f"camera: {cam}")
    note = join_notes(*notes)
    legend = F.legend(fig, handles, note)
    F.save(fig, name, sum(1 for _ in fronts), len(drawn), legend,
           rows=[" = ".join(gs) for _, gs, _ in lines], bands=[label[b] for b in bands],
           x_labels=[cost_info(c)[1] for c, _, _ in lines],
           front_points=fronts, spreads=spreads)


def same_image(a, b):
    return a is not None and b is not None and a.shape == b.shape and (a == b).all()


def load_map(results, r, px):
    """The map of a maps.csv row, cut out of pxh run's PNG (its title and colour bar left out:
    the montage draws one bar for all), every k-th pixel so it is about px wide; not kept (a
    run has thousands)."""
    path = inside(results, r["map"], "data/maps.csv")
    if not os.path.exists(path):
        print(f"pxh: warning: error map not found: {path} (left blank)", file=sys.stderr)
        return None
    img = mpimg.imread(path)
    x0, y0, side = (int(r[k]) for k in ("map_x0", "map_y0", "map_side"))
    if side <= 0 or y0 + side > img.shape[0] or x0 + side > img.shape[1]:
        print(f"pxh: warning: {path}: not the layout of a pxh run map (left blank)",
              file=sys.stderr)
        return None
    img = img[y0:y0 + side, x0:x0 + side, :3]
    k = max(1, side // max(1, px))
    return img[::k, ::k]


def error_colourbar(fig, rect, scale, outside=False):
    """The colour scale all maps of a montage share (data/error_scale.csv: pxh's own colours),
    drawn once in rect (figure fractions)."""
    l2 = np.array([float(r["log2_texels"]) for r in scale])
    rgb = np.array([[float(r[c]) for c in "rgb"] for r in scale])
    ax = fig.add_axes(rect)
    ax.imshow(rgb[None, :, :], aspect="auto", extent=(l2[0], l2[-1], 0, 1),
              interpolation="nearest")
    ax.set_yticks([])
    ticks = [t for t in range(int(math.ceil(l2[0])), int(math.floor(l2[-1])) + 1) if t % 2 == 0]
    ax.set_xticks(ticks)
    ax.set_xticklabels([f"1/{2 ** -t:g}" if t < 0 else f"{2 ** t:g}" for t in ticks])
    ax.tick_params(axis="x", labelsize=6, length=2, pad=1)
    for sp in ax.spines.values():
        sp.set_linewidth(0.3)
    label = "texel error (log scale; below 1/16: darkest; magenta: non-finite" + (
        "; grey: outside the camera's view)" if outside else ")")
    width = rect[2] * fig.get_figwidth()  # the bar's width, inches: the label wrapped to it
    ax.set_xlabel(fit(label, width + 0.4, 6, 2) if outside else label, fontsize=6, labelpad=1)
    return ax


def montage(F, st, rows, scale):
    """Per field and azimuth, a montage of its error maps: one row per series (series whose
    maps are identical, pixel for pixel, shown once and named together), one column per θ,
    every tile on the one colour scale pxh run draws, its bar drawn once below."""
    results = os.path.dirname(os.path.abspath(F.out))  # map paths: relative to the results
    views = {}
    for r in rows:  # a montage per field, azimuth and camera view
        views.setdefault((r.get("heightfield", ""), r.get("phi_deg", ""),
                          r.get("camera_view", "")), []).append(r)
    for (field, phi, _), vrows in views.items():
        cam = view_title(vrows[0])
        thetas = sorted({num(r["theta_deg"]) for r in vrows})
        per = {}
        for r in vrows:
            per.setdefault((setting(r), group(r)), {})[num(r["theta_deg"])] = r
        px = int(F.width / len(thetas) * 300)  # a tile's width in pixels at 300 dpi
        tiles = []  # [(setting, [groups], {theta: image})]
        for (s, g), by_theta in per.items():
            imgs = {th: load_map(results, r, px) for th, r in by_theta.items()}
            for t in tiles:
                if t[0] == s and t[2].keys() == imgs.keys() and all(
                        same_image(t[2][th], imgs[th]) for th in imgs):
                    t[1].append(g)
                    break
            else:
                tiles.append((s, [g], imgs))
        order = {s: i for i, s in enumerate(st.order)}
        tiles.sort(key=lambda t: order.get(t[0], len(order)))
        # one axes per row of tiles (the tiles side by side in one image, white between them:
        # a montage of hundreds of maps draws in seconds, not minutes)
        gap, margin, bar = 0.04, 0.03, 0.62  # inches; bar: below the last row, for the scale
        nc = len(thetas)
        cell = (F.width - 2 * margin - (nc - 1) * gap) / nc
        labels = []
        for s, gs, _ in tiles:
            label = " ".join(x for x in (s[0], short_params(s[1])) if x)  # whole: 2 lines
            labels.append(fit(f"{label} [{' = '.join(gs)}]", F.width - 0.1, 6, 2))
        # above each row its label (one or two lines of 6 pt), above the first the θ titles
        # (upright, or thinned, where many angles leave narrow tiles)
        heads, rotation, short = column_heads(thetas, cell)
        head_h = 0.15 if not rotation else max(len(h) for h in heads) * 6.5 * 0.62 / 72 + 0.06
        pads = [0.05 + (lab.count("\n") + 1) * 6 * 1.25 / 72 for lab in labels]
        pads[0] += head_h
        height = sum(pads) + len(tiles) * cell + bar
        fig = plt.figure(figsize=(F.width, height))
        sides = [im.shape[0] for _, _, imgs in tiles for im in imgs.values() if im is not None]
        px_side = min(sides) if sides else 1
        gap_px = max(1, round(px_side * gap / cell))
        y = height
        for i, (s, gs, imgs) in enumerate(tiles):
            y -= pads[i] + cell
            row = np.ones((px_side, nc * px_side + (nc - 1) * gap_px, 3))
            for j, th in enumerate(thetas):
                im = imgs.get(th)
                if im is not None:
                    idx = np.linspace(0, im.shape[0] - 1, px_side).round().astype(int)
                    x0 = j * (px_side + gap_px)
                    row[:, x0:x0 + px_side] = im[idx][:, idx, :3]
            ax = fig.add_axes([margin / F.width, y / height, (F.width - 2 * margin) / F.width,
                               cell / height])
            ax.imshow(row, interpolation="nearest", aspect="auto")
            ax.axis("off")
            if i == 0:
                for j, head in enumerate(heads):
                    if head:
                        fig.text((margin + j * (cell + gap) + cell / 2) / F.width,
                                 (y + cell + pads[0] - head_h + 0.02) / height, head,
                                 ha="center", va="bottom", fontsize=6.5, rotation=rotation)
            fig.text(0.5, (y + cell + 0.02) / height, labels[i], ha="center", va="bottom",
                     fontsize=6)
        bw = min(F.width - 0.6, 4.0)
        error_colourbar(fig, [(F.width - bw) / 2 / F.width, 0.36 / height, bw / F.width,
                              0.1 / height], scale, outside=bool(cam))
        fig.suptitle(fit(f"error maps: {field}, φ = {phi}°" + (f", {cam}" if cam else "") +
                         ("\ncolumns: view angle θ" if short else "") +
                         "\na row per method setting; maps "
                         "identical pixel for pixel shown once, their backends named together",
                         F.width - 0.1, 7, 5), fontsize=7, y=1.0, va="bottom")
        name = safe(f"error_maps_{field}_p{phi}{vrows[0].get('camera_tag') or ''}")
        F.save(fig, name, len(tiles) * len(thetas), len(tiles), [],
               rows=[f"{s[0]} {s[1]} [{' = '.join(gs)}]".strip() for s, gs, _ in tiles])


def view_title(r):
    """A row's camera view as a title part, from its camera_view field (data/pictures.csv,
    data/maps.csv: the camera's own keys, "distance=4 fov_deg=45"): "distance = 4,
    fov_deg = 45"; "" for a camera without keys (orthographic) or data without the field."""
    kv = [p.split("=", 1) for p in (r.get("camera_view") or "").split() if "=" in p]
    return ", ".join(f"{k} = {v}" for k, v in kv)


def view_tag(r):
    """The part of file names that tells camera views apart (pxh run's own: "_d4_f45_r256")
    and a level mode other than base ("_level")."""
    lod = r.get("lod") or ""
    return (r.get("camera_tag") or "") + ("" if lod in ("", "base") else f"_{lod}")


def column_heads(thetas, cell, pt=6.5):
    """The θ heads of a montage's columns, each a tile `cell` inches wide: ("θ = 30°", 0)
    where those fit, else the angles alone ("30°": the title says the columns are θ), else
    the angles turned upright (90); upright heads too close for their line height are
    thinned to every k-th column. Returns (heads, rotation, shortened)."""
    def width(t):
        return len(t) * pt * 0.62 / 72
    full = [f"θ = {t:g}°" for t in thetas]
    if all(width(t) <= cell - 0.03 for t in full):
        return full, 0, False
    short = [f"{t:g}°" for t in thetas]
    if all(width(t) <= cell - 0.03 for t in short):
        return short, 0, True
    step = max(1, math.ceil(pt * 1.3 / 72 / max(cell + 0.04, 1e-3)))
    return [h if j % step == 0 else "" for j, h in enumerate(short)], 90, True


def safe(name):
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in name)


def load(results, rel, what="data/pictures.csv", cache={}):
    path = inside(results, rel, what)
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
    gap, margin = 0.04, 0.03  # margin: each side, so spines and labels stay inside the width
    left += margin
    cell = (width - left - margin - (ncols - 1) * gap) / ncols
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
    cell = F.width / nc - 0.06
    names = ["truth (ray traced)"] + [fit(st.full[s], cell, 6, 2 if multi else 3) + (
        "\n" + fit(f"[{' = '.join(gs)}]", cell, 6, 1) if multi else "") for s, gs, _ in tiles]
    groups = sorted({g for t in tiles for g in t[1]})
    note = None if multi or len(groups) < 2 else (
        " and ".join(groups) + " pictures identical, pixel for pixel: shown once")
    cam = view_title(r0)
    title = fit(f"{r0['heightfield']}, θ = {num(r0['theta_deg']):g}°, "
                f"φ = {num(r0['phi_deg']):g}°" + (f", {cam}" if cam else "") +
                ": a numbered checkerboard through each "
                "method's uv; below it, |method − truth|" + (f"\n({note})" if note else ""),
                F.width, 7, 4)

    def lines_in(k):  # the most title lines of block k
        return max(n.count("\n") + 1 for n in names[k * nc:(k + 1) * nc])

    def line(pt):  # inches a line of pt-point text takes
        return pt * 1.25 / 72

    # above block 0: the figure's title and the tiles' titles; above the others: the previous
    # block's PSNR / SSIM lines (two, 5.5 pt) and the titles
    pads = [p for k in range(blocks) for p in (
        ((title.count("\n") + 1) * line(7) + 0.06 if k == 0 else 2 * line(5.5) + 0.08) +
        lines_in(k) * line(6.5) + 0.06, 0.03)]
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
        top.set_title(names[k], fontsize=6)
        bottom.text(0.5, -0.03, metrics_text(r).replace(", ", "\n"), fontsize=5.5,
                    ha="center", va="top", transform=bottom.transAxes)
    fig.suptitle(title, fontsize=7, y=1.0, va="top")
    name = safe(f"picture_{r0['heightfield']}_t{num(r0['theta_deg']):g}_p{num(r0['phi_deg']):g}"
                + (r0.get("camera_tag") or ""))
    F.save(fig, name, 1 + 2 * len(tiles), len(tiles), [], note=note)


def strip(F, st, results, rows):
    """One method setting over the θ sweep: truth, method, difference per θ (its first group;
    with an animated GIF of the same frames)."""
    s = setting(rows[0])
    g = group(rows[0])
    rows = sorted((r for r in rows if group(r) == g), key=lambda r: num(r["theta_deg"]))
    n = len(rows)
    r0 = rows[0]
    cam = view_title(r0)
    title = fit(f"{st.labels[s]} [{g}] on {r0['heightfield']} over the θ sweep "
                f"(φ = {num(r0['phi_deg']):g}°" + (f", {cam}" if cam else "") +
                "); under each: PSNR dB, SSIM", F.width, 7, 3)
    # above the tiles: the title's lines (7 pt) and the θ heads (6 pt); 0.45 in for two lines
    top = max(0.45, (title.count("\n") + 1) * 7 * 1.25 / 72 + 6 * 1.25 / 72 + 0.1)
    fig, axes = image_grid(F.width, n, [top, 0.03, 0.03], 0.3, left=0.3)
    for j, r in enumerate(rows):
        for i, key in enumerate(("picture_truth", "picture", "picture_diff")):
            show(axes[i][j], load(results, r[key]))
        cell = (F.width - 0.3) / n
        axes[0][j].set_title(fit(f"θ = {num(r['theta_deg']):g}°", cell, 6, 1), fontsize=6)
        # PSNR over SSIM, alternate tiles a line lower when tiles are too narrow for them
        low = cell < 0.62 and j % 2 == 1
        axes[2][j].text(0.5, -0.03 - (0.42 if low else 0), metrics_text(r).replace(", ", "\n")
                        .replace("PSNR ", "").replace("SSIM ", ""), fontsize=5 if cell < 0.62
                        else 5.5, ha="center", va="top", transform=axes[2][j].transAxes)
    side = axes[0][0].get_position().height * fig.get_figheight()
    small = side < 0.6
    for i, lab in enumerate(("truth", st.labels[s], "|diff.|" if small else "|difference|")):
        axes[i][0].set_ylabel(fit(lab, side, 5 if small else 6, 3 if small else 2),
                              fontsize=5 if small else 6, labelpad=2)
    fig.suptitle(title, fontsize=7, y=1.0, va="top")
    name = safe(f"strip_{r0['heightfield']}_p{num(r0['phi_deg']):g}{view_tag(r0)}")
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
        text = (f"{what}  theta = {num(r['theta_deg']):g} deg  (truth | method | difference)"
                f"  {metrics_text(r).replace('∞', 'inf')}")
        # PIL's built-in bitmap font draws Latin-1 only: anything else becomes '?'
        text = ellipsize(text, img.width // 6).replace("…", "...")
        text = text.encode("latin-1", "replace").decode("latin-1")
        ImageDraw.Draw(canvas).text((4, 2), text, fill="black")
        frames.append(canvas)
    path = os.path.join(F.out, name + ".gif")
    F.own.write(name + ".gif", lambda f: frames[0].save(
        f, format="GIF", save_all=True, append_images=frames[1:], duration=900, loop=0))
    print(f"plot: {path}")
    F.drawn[-1]["files"].append(name + ".gif")


def pictures(F, st, rows):
    results = os.path.dirname(os.path.abspath(F.out))
    views = {}
    strips = {}
    for r in rows:  # a montage per view (camera keys included: one truth each), a strip per
        # field, azimuth, camera view and setting (its level mode: one strip each)
        cam = r.get("camera_view", "")
        if "montage" in r["picture_use"].split():
            views.setdefault((r["heightfield"], r["theta_deg"], r["phi_deg"], cam),
                             []).append(r)
        if "strip" in r["picture_use"].split():
            strips.setdefault((r["heightfield"], r["phi_deg"], cam, setting(r)), []).append(r)
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
    maps = os.path.join(data, "maps.csv")
    pics = os.path.join(data, "pictures.csv")
    extra = [read(p) for p in (maps, pics) if os.path.exists(p)]
    st = Styles([setting(r) for r in cost + vt + bands + [r for e in extra for r in e]], width)
    for rows, tag, cam in by_view(vt):  # a camera run: a figure per camera view
        vs_theta(F, st, rows, tag, cam)
        sweep_vs_theta(F, st, rows, tag, cam)
    vd_path = os.path.join(data, "vs_distance.csv")
    if os.path.exists(vd_path):
        vs_distance(F, st, read(vd_path))
    for rows, tag, cam in by_view(bands):  # a camera run: a figure per camera view
        cost_figure(F, st, rows, "cost_vs_error" + tag, ["fetches_mean"], cam)
        cost_figure(F, st, rows, "time_vs_error" + tag, time_costs(rows), cam)
    if os.path.exists(maps):
        montage(F, st, read(maps), read(os.path.join(data, "error_scale.csv")))
    if os.path.exists(pics):
        pictures(F, st, read(pics))
    F.manifest()


if __name__ == "__main__":
    try:
        main()
    except OSError as e:  # a full disk, a file-size limit, a folder that went away
        fail(f"{e.filename or ''}: {e.strerror or e}", 1)

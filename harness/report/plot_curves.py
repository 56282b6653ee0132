"""pxh report's plot script (plot_report.py): the curves against the view angle and the camera's
distance (error_vs_theta, sweep_vs_theta, error_vs_distance): series folded where the groups
agree, the symlog error axes and their ticks."""
import math

import matplotlib.lines as mlines
import matplotlib.ticker

from plot_files import num, safe
from plot_text import field_titles, fit, join_notes, tick_text, view_title
from plot_figures import GROUP_STYLES, REL_TOL, group, plt, setting


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


def error_axis(ax, linthresh, top, height_in):
    """A symlog error axis from 0 to top: ticks at 0 and at the decades from linthresh up (a
    labelled tick down at the smallest errors' decade, below 0.1 where the good methods sit),
    the linear part [0, linthresh] one decade tall so the 0 and linthresh labels never crowd."""
    ax.set_yscale("symlog", linthresh=linthresh, linscale=1.0)
    ax.set_ylim(0, top)
    max_n = max(2, int(height_in * 72 / 16))
    ticks = [0.0] + decade_ticks(linthresh, top, max_n - 1)  # linthresh's decade labelled
    ax.yaxis.set_major_locator(matplotlib.ticker.FixedLocator(ticks))
    ax.yaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: tick_text(v)))
    # every decade marked, labelled or not (a label per decade does not fit a small panel;
    # without the marks two decades read as a linear axis)
    ax.yaxis.set_minor_locator(matplotlib.ticker.FixedLocator(decade_ticks(linthresh, top, 100)))
    ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
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
    # one field: its texel and pixel panels side by side (not two full-width panels stacked)
    side = len(fields) == 1
    nc = 2 if side else F.columns(len(fields))
    per = 1 if side else math.ceil(len(fields) / nc)
    nr = 1 if side else 2 * per
    fig, grid = plt.subplots(nr, nc, figsize=(F.width, F.width / nc * 0.72 * nr + 0.35),
                             squeeze=False, constrained_layout=True)
    pw, ph = panel_size(F, nc, 0.72)
    folded_all, series, panels = {}, 0, 0
    for q, (p50, p95, what) in enumerate((("err_p50", "err_p95", "texel error"),
                                          ("err_px_p50", "err_px_p95", "pixel error"))):
        for k in range(1 if side else per * nc):
            ax = grid[0][q] if side else grid[q * per + k // nc][k % nc]
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
            bottom = side or (q == 1 and k >= len(fields) - nc)
            theta_axis(ax, bottom)
            if side or k % nc == 0:
                ax.set_ylabel(what)
            if bottom:
                ax.set_xlabel("view angle θ (°)")
    handles = [st.handle(s) for s in st.order if s in folded_all] + group_handles(folded_all)
    handles += [mlines.Line2D([], [], color="0.3", lw=1.1, marker="o", label="p50"),
                mlines.Line2D([], [], color="0.3", lw=0.7, marker="o", mfc="white",
                              label="p95")]
    note = join_notes(f"camera: {cam}; " + ("left: texel error, right" if side else
                                            "top: texel error, below") + ": pixel error |J⁻¹e|",
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
    maps and pictures are), p50 and p95 as in vs_theta."""
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
    quantities = (("err_p50", "err_p95", "texel error", 0.01),
                  ("err_px_p50", "err_px_p95", "pixel error", 0.01))
    for f, field in enumerate(fields):
        for q, (p50, p95, label, lin) in enumerate(quantities):
            for c, theta in enumerate(thetas):
                ax = grid[2 * f + q][c]
                per = {}
                for r in rows:
                    if r["heightfield"] != field or num(r["theta_deg"]) != theta:
                        continue
                    x = num(r["distance"])
                    vals = (num(r[p50]), num(r[p95]))
                    if x is None or all(v is None for v in vals):
                        continue
                    per.setdefault(setting(r), {}).setdefault(group(r), {})[x] = vals
                folded, n = draw_curves(ax, st, per, True)
                folded_all.update(folded)
                series += n
                panels += 1
                vals = [num(r[k]) for r in rows if r["heightfield"] == field
                        for k in (p50, p95)]
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
    handles += [mlines.Line2D([], [], color="0.3", lw=1.1, marker="o", label="p50"),
                mlines.Line2D([], [], color="0.3", lw=0.7, marker="o", mfc="white",
                              label="p95")]
    field_note = f"field: {fields[0]}" if len(fields) == 1 else common
    note = join_notes("top: texel error; bottom: pixel error |J⁻¹e| (means over φ and fov)",
                      field_note, fold_note(folded_all))
    legend = F.legend(fig, handles, note)
    F.save(fig, name, panels, series, legend, note=note, y_ticks=y_ticks)

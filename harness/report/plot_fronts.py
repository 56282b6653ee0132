"""pxh report's plot script (plot_report.py): cost against error per theta band (cost_vs_error,
time_vs_error): each setting's points with their spreads and the Pareto front."""
import math

import matplotlib.lines as mlines
import matplotlib.ticker

from plot_files import num
from plot_text import fit, join_notes, tick_text
from plot_figures import group, plt, setting
from plot_curves import close, error_axis, log_ticks, panel_size, top_of


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

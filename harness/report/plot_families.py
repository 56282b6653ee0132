"""pxh report's plot script (plot_report.py): a figure per metric family and x axis, from
data/families/index.csv (harness/report/families.cpp): a panel per headline column and view
(base, radius, distance, ...: whatever key of the run tells rows apart besides the series), a
line per series, the same statistic named on every axis: the mean over the rows at each x of
the per-row column. Families, columns, units and views come from the data alone: a family a
component brings is drawn without a line here."""
import math
import os

import matplotlib.ticker

import matplotlib.lines as mlines

from plot_files import num, read
from plot_figures import GROUP_STYLES, MARKERS, PALETTE, REL_TOL, plt
from plot_curves import error_axis, linthresh_of, log_ticks, theta_axis, top_of
from plot_text import chars_for, ellipsize, fit, short_params, tick_text

X_LABELS = {"theta_deg": "θ"}


def x_label(x, unit):
    """The key's name (θ for theta_deg) and its unit from the key registry (index.csv)."""
    return X_LABELS.get(x, x) + (f" ({unit})" if unit else "")


def same(a, b):
    """Two points agree: within REL_TOL of each other, relatively only (the families' axes are
    logarithmic: 2e-8 and 7e-8 are two values, not one), or both missing."""
    if a is None or b is None:
        return a is None and b is None
    return a == b or abs(a - b) <= REL_TOL * max(abs(a), abs(b))


def nice_125(v, up):
    """The 1-2-5 value (1, 2, 5 times a power of ten) next to v > 0, above it (up) or below."""
    e = math.floor(math.log10(v))
    steps = [m * 10.0 ** k for k in (e - 1, e, e + 1) for m in (1, 2, 5)]
    return min(s for s in steps if s >= v * (1 - 1e-9)) if up else max(
        s for s in steps if s <= v * (1 + 1e-9))


def wrap_keys(panel, n):
    """"distance = 1.5, depth = hit, cut = 0.27" on lines of at most n characters, broken only
    between keys: a key and its value are never cut (a key longer than a line is a line)."""
    out = []
    for part in panel.split(", "):
        if out and len(out[-1]) + 2 + len(part) <= n:
            out[-1] += ", " + part
        else:
            out.append(part)
    return "\n".join(out)


def wrap_name(name, n):
    """A column name on lines of at most n characters, broken after an "_" (never cut)."""
    lines = [""]
    for part in name.split("_"):
        piece = part if not lines[-1] else "_" + part
        if lines[-1] and len(lines[-1]) + len(piece) > n:
            lines[-1] += "_"
            lines.append(part)
        else:
            lines[-1] += piece
    return "\n".join(lines)


def split_line(line):
    """"pom layers=32;layers_min=off [cpu/float]" -> ("pom layers=32;layers_min=off",
    "cpu/float")."""
    head, _, group = line.rpartition(" [")
    return (head, group[:-1]) if head else (line, "")


def fold_groups(rows, cols):
    """[(label, line)]: one drawn line per setting, its backend groups named together where all
    their points agree within 0.1% (the others drawn apart); labels with "off" parameters left
    out."""
    points = {}
    for r in rows:
        points.setdefault(r["line"], {})[(r["panel"], r["x"])] = tuple(num(r[c]) for c in cols)
    drawn = []  # [setting, [groups], line]
    for line, pts in points.items():
        setting, group = split_line(line)
        for d in drawn:
            if d[0] == setting and points[d[2]].keys() == pts.keys() and all(
                    same(a, b) for k in pts for a, b in zip(pts[k], points[d[2]][k])):
                d[1].append(group)
                break
        else:
            drawn.append([setting, [group], line])
    out = []
    for setting, groups, line in drawn:
        method, _, params = setting.partition(" ")
        label = (method + " " + short_params(params)).strip()
        out.append((label + " [" + " = ".join(groups) + "]", line, (method, params)))
    return out


def line_styles(st, lines):
    """{line: (colour, marker, linestyle)}: the setting's colour and marker as every figure of
    the report draws it (st: plot_figures.Styles over the report's settings; a setting only
    this family has comes after them), its backend groups drawn apart by line style."""
    extra, seen, out = [], {}, {}
    for _, line, s in lines:
        if s not in st.order and s not in extra:
            extra.append(s)
        i = st.order.index(s) if s in st.order else len(st.order) + extra.index(s)
        style = GROUP_STYLES[seen.setdefault(s, 0) % len(GROUP_STYLES)]
        seen[s] += 1
        out[line] = (PALETTE[i % len(PALETTE)], MARKERS[(i + i // len(PALETTE)) % len(MARKERS)],
                     style)
    return out


def family_figure(F, st, entry, data_dir):
    rows = read(os.path.join(os.path.dirname(data_dir), entry["file"]))
    if not rows:
        return
    cols = entry["columns"].split(";")
    units = entry["units"].split(";")
    better = entry["better"].split(";")
    x = entry["x"]
    panels = list(dict.fromkeys(r["panel"] for r in rows))
    lines = fold_groups(rows, cols)
    styles = line_styles(st, lines)
    cells = [(c, u, b, p) for c, u, b in zip(cols, units, better) for p in panels]
    cells = [cell for cell in cells if any(num(r[cell[0]]) is not None and num(r["x"]) is not None
                                           for r in rows if r["panel"] == cell[3])]
    if not cells:
        return
    # columns: the panels (a statistic a row) where the run has several; one panel's statistics
    # side by side, as many as the width takes (not stacked in one column)
    nc = max(1, min(len(panels), F.columns(len(cells)))) if len(panels) > 1 else \
        F.columns(len(cells))
    pw = F.width / nc
    thetas = max(int(num(r["thetas"]) or 1) for r in rows)
    n_chars = chars_for(0.7 * pw - 0.25, 8)  # the axes: the panel less its tick labels

    def title_of(col, panel):  # wrapped at "_", never cut: the name tells panels apart
        title = wrap_name(col, n_chars)
        return wrap_keys(panel, n_chars) + "\n" + title if panel else title

    # the titles' lines are added to the panels' height, not taken from the plot (at one
    # column's width a key and a long column name take three or four lines)
    title_lines = max(title_of(c[0], c[3]).count("\n") + 1 for c in cells)
    fig, axes = F.grid(len(cells), aspect=0.72, ncols=nc,
                       extra_row_in=max(0, title_lines - 1) * 8 * 1.3 / 72)
    drawn, under = set(), {}  # lines drawn in some panel; a hidden line: the lines it lay under
    for i, (ax, (col, unit, bt, panel)) in enumerate(zip(axes, cells)):
        values, shown = [], []  # shown: (points, line) drawn in this panel
        hidden = 0
        for k, (label, line, _) in enumerate(lines):
            pts = sorted((num(r["x"]), num(r[col])) for r in rows
                         if r["panel"] == panel and r["line"] == line
                         and num(r["x"]) is not None and num(r[col]) is not None)
            if not pts:
                continue
            # a line equal to one drawn already (within 0.1%) would hide under it: counted
            top = next((o_line for o, o_line in shown if len(o) == len(pts) and all(
                a[0] == b[0] and same(a[1], b[1]) for a, b in zip(o, pts))), None)
            if top is not None:
                hidden += 1
                under.setdefault(line, set()).add(top)
                continue
            shown.append((pts, line))
            drawn.add(line)
            values += [v for _, v in pts]
            colour, marker, style = styles[line]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], color=colour, marker=marker,
                    ls=style, lw=1.0, ms=3, alpha=0.9, zorder=3 + (len(lines) - k) * 0.01)
        title = title_of(col, panel)
        if hidden:  # said under the title, off the data: lines that lie under the one drawn
            note = f"({hidden + 1} lines coincide: drawn once)"
            title += "\n" + (note if len(note) <= n_chars else f"({hidden + 1} coincide)")
        ax.set_title(title, fontsize=8)
        # the axes' height: the panel's (its title's lines beyond one added to it) less one
        # title line (8 pt) and the x tick labels
        axis_in = max(0.3, pw * 0.72 - (title.count("\n") + 1 - (title_lines - 1)) * 8 * 1.3 / 72
                      - 0.3)
        if unit:
            ax.set_ylabel(ellipsize(unit, chars_for(pw * 0.6, 7)), fontsize=7)
        if values and min(values) > 0 and max(values) >= 10 * min(values):
            # no zero to show: a log axis from and to 1-2-5 values (markers off the frame),
            # ticks in 1-2-5 steps, every decade marked
            ax.set_yscale("log")
            lo, hi = nice_125(min(values) / 1.15, False), nice_125(max(values) * 1.15, True)
            ax.set_ylim(lo, hi)
            ticks = log_ticks(lo, hi, max(2, int(axis_in * 72 / 24)))
            ax.yaxis.set_major_locator(matplotlib.ticker.FixedLocator(ticks))
            ax.yaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(
                lambda v, _: tick_text(v)))
            ax.yaxis.set_minor_locator(matplotlib.ticker.FixedLocator(
                [10.0 ** e for e in range(math.floor(math.log10(lo)), math.ceil(math.log10(hi)) + 1)]))
            ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
            ax.grid(True, alpha=0.3, lw=0.4)
        elif bt == "smaller" and values and min(values) == 0:
            lin = linthresh_of(values, 0.01)
            error_axis(ax, lin, top_of(values, lin), axis_in)
        else:
            ax.grid(True, alpha=0.3, lw=0.4)
        xs = [num(r["x"]) for r in rows if r["panel"] == panel and num(r["x"]) is not None]
        if x == "theta_deg":
            theta_axis(ax, True)
        elif xs and min(xs) > 0 and max(xs) >= 10 * min(xs):  # radii, distances: decades
            ax.set_xscale("log")
            ticks = sorted(set(xs))
            if len(ticks) > 4:  # every value while they fit, else decades
                ticks = log_ticks(min(xs), max(xs), 4)
            ax.xaxis.set_major_locator(matplotlib.ticker.FixedLocator(ticks))
            ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(
                lambda v, _: tick_text(v)))
            ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        elif xs and len(set(xs)) <= 6:  # a few values (cut heights): ticked at each
            ax.xaxis.set_major_locator(matplotlib.ticker.FixedLocator(sorted(set(xs))))
            ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(
                lambda v, _: tick_text(v)))
        last_row = i + nc >= len(cells)
        if last_row:
            ax.set_xlabel(x_label(x, entry.get("x_unit", "")))
    # a setting drawn in no panel (always under another's line): its legend entry says whose
    name_of = {line: label.split(" ")[0] for label, line, _ in lines}
    handles = [mlines.Line2D([], [], color=styles[line][0], marker=styles[line][1],
                             ls=styles[line][2], label=fit(label + (
                                 " (under " + ", ".join(sorted({name_of[t] for t in under[line]}))
                                 + ")" if line not in drawn and line in under else ""),
                                 F.width - 0.6, 7, 2))
               for label, line, _ in lines]
    legend = F.legend(fig, handles)
    # the statistic, named as in every family figure: the mean over the rows at each x
    over = "" if x == "theta_deg" or thetas < 2 else f" (and over θ: x is {x})"
    fig.suptitle(fit(entry["title"] + "; each point: the mean over its rows" + over,
                     F.width - 0.2, 8, 3), fontsize=8)
    name = entry["family"] + "_vs_" + (x[:-4] if x.endswith("_deg") else x)
    F.save(fig, name, panels=[c[3] + " " + c[0] for c in cells],
           series=[label for label, _, _ in lines], legend=legend,
           family=entry["family"], x=x)


def family_jobs(F, st, data_dir):
    """A drawing job per entry of data/families/index.csv (st: the report's Styles, so a
    setting has the colour and marker of every other figure)."""
    index = os.path.join(data_dir, "families", "index.csv")
    if not os.path.exists(index):
        return []
    return [lambda entry=entry: family_figure(F, st, entry, data_dir) for entry in read(index)]

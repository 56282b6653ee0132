#!/usr/bin/python3
"""Draws the figures of `pxh report` from the numbers the harness computed (report/data/*.csv).

Only drawing happens here: every value plotted was computed by pxh. Usage:
    /usr/bin/python3 harness/report/plot_report.py RESULTS_DIR/report [--into FOLDER]
                                                   [--width INCHES] [--formats png,pdf]

Every figure is written as PNG (300 dpi) and PDF (and SVG when --formats asks: TrueType fonts embedded: pdf.fonttype
42), WIDTH inches wide (pxh report --figure-width: single = 3.5, double = 7) with 8 pt text.
One method setting has one colour and one marker in every figure of a report (Paul Tol's
colour-blind-safe "muted" palette plus black, markers cycling with it). Series of one setting
whose numbers agree within 0.1% on every backend / precision / texture format are drawn once,
and the legend says which agree; where they differ, each is drawn with its own line style.
report/figures.json lists what was drawn: per figure its files, panels, series and legend.

Files are created new in --into (default: the report folder), each exclusively and never through
a link; a name that exists stops the script (exit 2). pxh report passes a staging folder of its
own and then takes the files into the report folder as it takes its own tables
(harness/core/safe_files.h: OwnedFolder), so safe writing has one home.
Picture and map paths must lie inside the results folder with no link on the way (exit 2).
Any field or method name draws: labels too long for the width are shortened in the middle (…).

This file reads the data and calls the drawing; the modules beside it do the work: plot_files
(new files, data files), plot_text (text fitted to the width), plot_figures (styles, layout,
saving), plot_curves (against θ and distance), plot_fronts (cost against error), plot_maps
(error-map montages) and plot_pictures (picture montages, strips, GIFs).
"""
import argparse
import json
import math
import multiprocessing
import os
import sys
import traceback

# The modules beside this file (plot_*.py, shipped with it): found wherever it is run from,
# and never compiled into a __pycache__ there (an installed tree may be read-only).
sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from plot_files import fail, read  # noqa: E402
from plot_figures import Figures, Styles, setting  # noqa: E402
from plot_curves import by_view, sweep_vs_theta, vs_distance, vs_theta  # noqa: E402
from plot_fronts import cost_figure, time_costs  # noqa: E402
from plot_families import family_jobs  # noqa: E402
from plot_maps import montage  # noqa: E402
from plot_pictures import picture_jobs  # noqa: E402


def parse_args(argv):
    ap = argparse.ArgumentParser(prog="plot_report.py")
    ap.add_argument("report", help="RESULTS_DIR/report (with data/*.csv)")
    ap.add_argument("--into", help="the folder the figures are created in (new files only; "
                    "default: REPORT itself); pxh report passes a staging folder of its own")
    ap.add_argument("--width", type=float, default=7.0, help="figure width in inches, [2, 20]")
    ap.add_argument("--formats", default="png,pdf", help="comma list of png, svg, pdf")
    a = ap.parse_args(argv[1:])
    formats = a.formats.split(",")
    if not (math.isfinite(a.width) and 2 <= a.width <= 20):
        ap.error(f"--width {a.width:g}: not a width in inches in [2, 20]")
    if not formats or any(f not in ("png", "svg", "pdf") for f in formats):
        ap.error(f"--formats {a.formats}: not a comma list of png, svg, pdf")
    return a.report, a.into, a.width, formats


def fail_os(e):
    print(f"pxh: error: {e.filename or ''}: {e.strerror or e}", file=sys.stderr)
    return 1


def _draw_share(F, jobs, counter, wfd):
    """In a drawing process: the next job not taken yet, until none is left (a shared counter:
    a long montage does not hold up the rest); what each drew goes back through wfd as JSON
    (figures.json keeps the jobs' order); exits with the first failure's status."""
    status, out = 0, []
    try:
        while True:
            with counter.get_lock():
                i = counter.value
                counter.value += 1
            if i >= len(jobs):
                break
            F.drawn = []
            jobs[i]()
            out.append([i, F.drawn])
    except SystemExit as e:  # fail(): the message is printed already
        status = e.code if isinstance(e.code, int) else 2
    except OSError as e:
        status = fail_os(e)
    except BaseException:  # noqa: B902 - a bug: its traceback, and a failed report
        traceback.print_exc()
        status = 1
    with os.fdopen(wfd, "wb") as f:
        f.write(json.dumps(out).encode("utf-8"))
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(status)


def run_jobs(F, jobs):
    """The figures are independent: drawn by as many processes as there are cores (at most
    PXH_PLOT_JOBS when set; 1 draws them here), figures.json in the jobs' order whatever the
    process count."""
    limit = int(os.environ.get("PXH_PLOT_JOBS", "0") or 0)
    workers = min(len(jobs), os.cpu_count() or 1, limit or len(jobs))
    if workers <= 1:
        for job in jobs:
            job()
        return
    sys.stdout.flush()
    sys.stderr.flush()
    children = []
    counter = multiprocessing.Value("i", 0)  # the next job to draw, shared through fork
    for _ in range(workers):
        r, wfd = os.pipe()
        pid = os.fork()
        if pid == 0:
            os.close(r)
            _draw_share(F, jobs, counter, wfd)
        os.close(wfd)
        children.append((pid, r))
    drawn, status = {}, 0
    for pid, r in children:
        with os.fdopen(r, "rb") as f:
            data = f.read()
        code = os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1])
        status = status or (code if code > 0 else (1 if code else 0))
        for i, d in json.loads(data.decode("utf-8") or "[]"):
            drawn[i] = d
    if status:
        sys.exit(status)
    for i in sorted(drawn):
        F.drawn.extend(drawn[i])


def main():
    out, into, width, formats = parse_args(sys.argv)
    data = os.path.join(out, "data")
    F = Figures(out, width, formats, into)
    vt = read(os.path.join(data, "vs_theta.csv"))
    cost = read(os.path.join(data, "cost_vs_error.csv"))
    bands = read(os.path.join(data, "cost_vs_error_bands.csv"))
    maps = os.path.join(data, "maps.csv")
    pics = os.path.join(data, "pictures.csv")
    extra = [read(p) for p in (maps, pics) if os.path.exists(p)]
    st = Styles([setting(r) for r in cost + vt + bands + [r for e in extra for r in e]], width)
    jobs = []  # the long ones first: the drawing processes take them in this order
    if os.path.exists(pics):
        jobs += picture_jobs(F, st, read(pics))
    if os.path.exists(maps):
        jobs.append(lambda: montage(F, st, read(maps), read(os.path.join(data, "error_scale.csv"))))
    for rows, tag, cam in by_view(vt):  # a camera run: a figure per camera view
        jobs.append(lambda rows=rows, tag=tag, cam=cam: vs_theta(F, st, rows, tag, cam))
        jobs.append(lambda rows=rows, tag=tag, cam=cam: sweep_vs_theta(F, st, rows, tag, cam))
    vd_path = os.path.join(data, "vs_distance.csv")
    if os.path.exists(vd_path):
        jobs.append(lambda: vs_distance(F, st, read(vd_path)))
    for rows, tag, cam in by_view(bands):  # a camera run: a figure per camera view
        jobs.append(lambda rows=rows, tag=tag, cam=cam: cost_figure(
            F, st, rows, "cost_vs_error" + tag, ["fetches_mean"], cam))
        jobs.append(lambda rows=rows, tag=tag, cam=cam: cost_figure(
            F, st, rows, "time_vs_error" + tag, time_costs(rows), cam))
    jobs += family_jobs(F, st, data)
    run_jobs(F, jobs)
    F.manifest()


if __name__ == "__main__":
    try:
        main()
    except OSError as e:  # a full disk, a file-size limit, a folder that went away
        fail(f"{e.filename or ''}: {e.strerror or e}", 1)

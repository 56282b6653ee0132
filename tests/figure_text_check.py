#!/usr/bin/python3
"""Draws every figure of a report with harness/report/plot_report.py and checks its text on the
figure itself, after drawing, from the renderer's extents (Text.get_window_extent) of every Text
artist matplotlib actually drew: tick labels, axis labels, titles, suptitles, legend entries and
titles, colour-bar labels, annotations.

    /usr/bin/python3 tests/figure_text_check.py PLOT_REPORT.py RESULTS_DIR/report WIDTH [--save]

The files are created in a new temporary folder (removed afterwards), never in the report.
(--save: the figures are also written as PNG, as pxh report writes them, and their widths
checked; without it they are only drawn, at 100 dpi, and checked, and the strips' animated
GIFs, which hold no matplotlib text, are not made.)

Fails (exit 1, one line per finding) when
- two pieces of text overlap or come closer than GAP_PT (tick labels touching included);
- a piece of text leaves the canvas: the figure is WIDTH inches wide (a paper's column), so
  every text must lie within it horizontally; vertically within the saved (tight) box;
- the saved PNG is wider than WIDTH and the 0.02 in pad savefig adds at each side.
Prints "checked N figures, M texts" when all pass.
"""
import importlib.util
import os
import shutil
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.text as mtext  # noqa: E402

GAP_PT = 0.5  # two texts closer than this (points) "touch"
EDGE_PT = 0.25  # tolerance at the canvas edges (points)

drawn = []
_draw = mtext.Text.draw


def recording_draw(self, renderer):
    _draw(self, renderer)
    if self.get_visible() and self.get_text().strip() and self.figure is not None:
        drawn.append((self, self.get_window_extent(renderer)))


mtext.Text.draw = recording_draw


def describe(t):
    s = t.get_text().replace("\n", " | ")
    return repr(s if len(s) <= 60 else s[:57] + "...")


def check_figure(fig, name, width_in):
    """Draws fig and returns its findings (strings) and the number of texts."""
    drawn.clear()
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    texts = list({id(t): (t, bb) for t, bb in drawn}.values())
    dpi = fig.dpi
    gap = GAP_PT * dpi / 72 / 2  # each box grown by half the gap
    edge = EDGE_PT * dpi / 72
    found = []
    tight = fig.get_tightbbox(renderer)  # inches
    if tight.width > width_in + 0.05:
        found.append(f"{name}: the figure is {tight.width:.2f} in wide, more than its "
                     f"{width_in:g} in")
    W = width_in * dpi
    y0, y1 = tight.y0 * dpi - edge, tight.y1 * dpi + edge
    for t, bb in texts:
        if bb.x0 < -edge or bb.x1 > W + edge or bb.y0 < y0 or bb.y1 > y1:
            found.append(f"{name}: text {describe(t)} leaves the canvas (x {bb.x0:.1f}..{bb.x1:.1f}"
                         f" of 0..{W:.1f} px at {dpi:g} dpi)")
    for i in range(len(texts)):
        a, ba = texts[i]
        for j in range(i + 1, len(texts)):
            b, bb = texts[j]
            w = min(ba.x1, bb.x1) - max(ba.x0, bb.x0) + 2 * gap
            h = min(ba.y1, bb.y1) - max(ba.y0, bb.y0) + 2 * gap
            if w > 0 and h > 0:
                what = "overlap" if w > 2 * gap and h > 2 * gap else "touch"
                found.append(f"{name}: texts {describe(a)} and {describe(b)} {what} "
                             f"({w - 2 * gap:.1f} x {h - 2 * gap:.1f} px at {dpi:g} dpi)")
    return found, len(texts)


def main():
    script, report, width = sys.argv[1], sys.argv[2], float(sys.argv[3])
    argv = list(sys.argv)
    spec = importlib.util.spec_from_file_location("plot_report", script)
    pr = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(pr)
    pictures = sys.modules["plot_pictures"]  # the strips' GIFs (imported by plot_report)
    figures = sys.modules["plot_figures"]  # Figures and matplotlib's pyplot
    findings, counts = [], []
    save = figures.Figures.save

    def checked_save(self, fig, name, panels, series, legend, **extra):
        f, n = check_figure(fig, name, self.width)
        findings.extend(f)
        counts.append(n)
        if "--save" in argv[4:]:
            return save(self, fig, name, panels, series, legend, **extra)
        # checked as drawn; not written at 300 dpi (slow): the manifest entry only
        figures.plt.close(fig)
        self.drawn.append(dict(name=name, files=[], panels=panels, series=series,
                               legend=legend, **extra))

    figures.Figures.save = checked_save
    if "--save" not in argv[4:]:
        # the strips' animated GIFs are Pillow frames, no matplotlib text: nothing to check
        pictures.animate = lambda *args, **kwargs: None
    # every figure drawn in this process, where the checks run (not in drawing processes)
    os.environ["PXH_PLOT_JOBS"] = "1"
    into = tempfile.mkdtemp(prefix="pxh_figure_check_")
    sys.argv = [script, report, "--into", into, "--width", str(width), "--formats", "png"]
    try:
        pr.main()
        return report_findings(findings, counts, into, width)
    finally:
        shutil.rmtree(into, ignore_errors=True)


def report_findings(findings, counts, into, width):
    for line in findings:
        print("collision: " + line)
    print(f"checked {len(counts)} figures, {sum(counts)} texts, {len(findings)} findings "
          f"at {width:g} in")
    # the PNGs as saved: no wider than the width and savefig's pad_inches (0.02 in a side) at
    # 300 dpi, 3 px for rounding
    for f in sorted(os.listdir(into)):
        if f.endswith(".png"):
            with open(os.path.join(into, f), "rb") as fh:
                head = fh.read(24)
            w = int.from_bytes(head[16:20], "big")
            if w > (width + 0.04) * 300 + 3:
                print(f"collision: {f}: {w} px wide, more than {width:g} in at 300 dpi")
                findings.append(f)
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())

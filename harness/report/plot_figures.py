"""pxh report's plot script (plot_report.py): matplotlib set up for the report (Agg, 8 pt text,
embedded fonts, reproducible SVG and PDF), one colour and marker per method setting, and a
figure's layout, legend and saving with the manifest of what was drawn."""
import json
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.lines as mlines  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

from plot_files import NewFiles
from plot_text import chars_for, ellipsize, fit, short_params

matplotlib.rcParams.update({
    "font.size": 8, "axes.titlesize": 8, "axes.labelsize": 8, "legend.fontsize": 7,
    "xtick.labelsize": 7, "ytick.labelsize": 7, "pdf.fonttype": 42, "ps.fonttype": 42,
    "svg.fonttype": "path", "axes.linewidth": 0.6, "lines.linewidth": 1.2,
    "lines.markersize": 3.5, "legend.frameon": False, "figure.dpi": 100,
    "svg.hashsalt": "pxh", "pdf.compression": 6,
    # Glyphs unhinted: text measured for the layout at 100 dpi then has the extents it is drawn
    # with at 300 dpi (hinted, a 5.5 pt line measured a descent short at 100 dpi, and the
    # saved box cut the last line under a picture); at 300 dpi hinting shows no difference.
    "text.hinting": "no_hinting",
})


# Paul Tol's "muted" scheme (https://personal.sron.nl/~pault/, colour-blind safe) and black.
PALETTE = ["#332288", "#88CCEE", "#44AA99", "#117733", "#999933", "#DDCC77", "#CC6677",
           "#882255", "#AA4499", "#000000"]

MARKERS = ["o", "s", "^", "D", "v", "P", "X", "<", ">", "*"]

GROUP_STYLES = ["-", "--", ":", "-."]

def _share_font_subsets():
    """PDF (and EPS) figures embed their font as TrueType (pdf.fonttype 42), subset to the
    characters each figure uses: matplotlib loads and subsets the font file anew for every
    figure (a quarter of a second here, most of a small figure's PDF time). Figures whose
    characters all lie in a common set share one subset of that set, made once per process
    (before the drawing processes fork, they inherit it); a figure with another character gets
    its own subset, as before. matplotlib.backends._backend_pdf_ps.get_glyphs_subset is
    internal (matplotlib 3.6 to 3.9): where it is missing, nothing changes."""
    from io import BytesIO
    try:
        from matplotlib.backends import _backend_pdf_ps
        own = _backend_pdf_ps.get_glyphs_subset
    except (ImportError, AttributeError):
        return
    common = frozenset(chr(c) for c in range(32, 127)) | frozenset("\xa0θφ°…∞⁻†¹²³≤≥−–—×±·µΔσπ√≈→")
    text = "".join(sorted(common))
    shared = {}

    def subset(fontfile, characters):
        if not set(characters) <= common:
            return own(fontfile, characters)
        if fontfile not in shared:
            shared[fontfile] = own(fontfile, text).getvalue()
        return BytesIO(shared[fontfile])

    _backend_pdf_ps.get_glyphs_subset = subset


_share_font_subsets()

REL_TOL = 1e-3  # series within 0.1% of each other (and 1e-6 absolute) are drawn once


def setting(r):
    return (r["method"], r["params"])


def group(r):
    return r["backend"] + "/" + (r["texture_format"] or r["precision"])


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

    def __init__(self, out, width, formats, into=None):
        """out: the report folder (data/ is read there); into: where the files are created
        (pxh report's staging folder; out itself when the script is run by hand)."""
        self.out, self.width, self.formats, self.drawn = out, width, formats, []
        self.files = NewFiles(into or out)

    def columns(self, n):
        return max(1, min(n, 3 if self.width >= 6 else 2))

    def grid(self, n, aspect=0.72, ncols=None, extra_row_in=0.0):
        """n panels, ncols a row, each pw * aspect tall plus extra_row_in (its title's lines,
        which would otherwise come out of the plot's height)."""
        nc = ncols or self.columns(n)
        nr = max(1, math.ceil(n / nc))
        pw = self.width / nc
        fig, axes = plt.subplots(nr, nc, figsize=(self.width, (pw * aspect + extra_row_in) * nr
                                                  + 0.35),
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
        # The layout and the tight box once for every format (savefig's bbox_inches="tight"
        # would lay the figure out and draw it twice per file), at 100 dpi without rasterising
        # (savefig draws): unhinted text (rcParams above) measures the same at 100 dpi as it
        # is drawn at 300; PNG at zlib level 3 (level 6 costs a third more time for 10%
        # smaller files).
        fig.draw_without_rendering()
        box = fig.get_tightbbox(fig.canvas.get_renderer()).padded(0.02)
        fig.set_layout_engine("none")
        for ext in self.formats:
            meta = {"svg": {"Date": None}, "pdf": {"CreationDate": None}}.get(ext)
            kw = {"pil_kwargs": {"compress_level": 1}} if ext == "png" else {}
            self.files.write(f"{name}.{ext}", lambda f: fig.savefig(
                f, format=ext, dpi=300, bbox_inches=box, metadata=meta, **kw))
            files.append(f"{name}.{ext}")
        plt.close(fig)
        print(f"plot: {os.path.join(self.files.into, name)}." + "/.".join(self.formats))
        self.drawn.append(dict(name=name, files=files, panels=panels, series=series,
                               legend=legend, **extra))

    def manifest(self):
        path = os.path.join(self.files.into, "figures.json")
        text = json.dumps({"width_in": self.width, "figures": self.drawn}, indent=1)
        self.files.write("figures.json", lambda f: f.write(text.encode("utf-8")))
        print(f"wrote {path}")

"""What the findings' two-panel figures share (scripts/curved_table.py, scripts/depth_table.py):
the --figure / --width options; two panels side by side at the double-column width (7 in) or
stacked at the single-column width (3.5 in), 8 pt text, TrueType fonts in the PDF; the legend
below the panels, the title on one line (double) or two (single); OUT_STEM.png and
OUT_STEM.pdf at 200 dpi. The scripts import it as `figure_style` (a script's own folder is on
sys.path when it runs)."""

WIDTH_IN = {"single": 3.5, "double": 7.0}  # a column, the page


def add_options(ap):
    """Adds --figure OUT_STEM and --width single|double (default double) to the parser AP."""
    ap.add_argument("--figure", help="write OUT_STEM.png and OUT_STEM.pdf")
    ap.add_argument("--width", choices=["single", "double"], default="double")


def two_panels(width, height):
    """A figure and its two axes, side by side at WIDTH "double" and stacked at "single"; HEIGHT
    maps each width to the figure's height in inches. matplotlib (Agg) is imported here, so a
    run without --figure needs none."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    plt.rcParams.update({"font.size": 8, "pdf.fonttype": 42})
    double = width == "double"
    return plt.subplots(1 if double else 2, 2 if double else 1,
                        figsize=(WIDTH_IN[width], height[width]))


def finish(fig, stem, width, title, bottom, top):
    """Puts the legend of the labelled lines below the panels (4 columns double, 2 single) and
    TITLE, a pair of strings, above them (on one line double, on two single), lays the panels out
    between BOTTOM and TOP (each maps a width to a fraction of the figure's height) and writes
    STEM.png and STEM.pdf."""
    double = width == "double"
    fig.legend(fontsize=6.5, ncol=4 if double else 2, loc="lower center", frameon=False)
    fig.suptitle((" " if double else "\n").join(title), fontsize=8)
    fig.tight_layout(rect=(0, bottom[width], 1, top[width]))
    for ext in ("png", "pdf"):
        fig.savefig(f"{stem}.{ext}", dpi=200)

"""pxh report's plot script (plot_report.py): text fitted to the figure's width (wrapped, shortened
in the middle), and the labels, titles and notes made of the data's names."""
import math
import textwrap

from plot_files import num


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


def short_params(params):
    """Parameters for a legend: those set to "off" left out, "; " between the others."""
    return ", ".join(p for p in params.split(";") if p and not p.endswith("=off"))


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


def tick_text(v):
    if v == 0:
        return "0"
    if abs(v) >= 1e4 or abs(v) < 1e-2:
        e = math.floor(math.log10(abs(v)) + 1e-9)
        m = v / 10 ** e
        return f"$10^{{{e}}}$" if abs(m - 1) < 1e-9 else f"${m:g}\\times10^{{{e}}}$"
    return f"{v:g}"


def view_title(r, skip=()):
    """A row's camera view as a title part, from its camera_view field (data/pictures.csv,
    data/maps.csv: the camera's own keys, "distance=4 fov_deg=45"): "distance = 4,
    fov_deg = 45"; "" for a camera without keys (orthographic) or data without the field.
    skip: keys the title says otherwise (a montage's "on a sphere of radius R")."""
    kv = [p.split("=", 1) for p in (r.get("camera_view") or "").split() if "=" in p]
    return ", ".join(f"{k} = {v}" for k, v in kv if k not in skip)


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


def metrics_text(r):
    p, q = num(r["img_psnr_db"]), num(r["img_ssim"])
    psnr = "∞" if r["img_psnr_db"] in ("inf", "+inf") else (f"{p:.1f}" if p is not None else "–")
    return f"PSNR {psnr} dB, SSIM {q:.3f}" if q is not None else f"PSNR {psnr} dB"

"""pxh report's plot script (plot_report.py): the rendered pictures: a montage per view (truth,
each setting's picture over its difference), a strip per setting over the theta sweep, and its
animated GIF."""
import math
import os
import sys

import matplotlib
import matplotlib.image as mpimg
import numpy as np
from matplotlib.patches import Rectangle

from plot_files import inside, num, safe
from plot_text import ellipsize, fit, metrics_text, view_tag, view_title
from plot_figures import group, plt, setting


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


class Tile:
    """A square image slot of an image_grid figure, in inches on the figure's one canvas axes
    (one Axes per figure, not one per tile: a montage of 40 tiles would pay 40 axes' set-up,
    layout and tight-box passes, most of its drawing time)."""

    def __init__(self, ax, x, y, side):
        self.ax, self.x, self.y, self.side = ax, x, y, side

    def show(self, img):
        """The image, nearest-neighbour, in a thin frame (a missing picture: the frame only)."""
        if img is not None:
            self.ax.imshow(img, interpolation="nearest", aspect="auto",
                           extent=(self.x, self.x + self.side, self.y, self.y + self.side))
        self.ax.add_patch(Rectangle((self.x, self.y), self.side, self.side, fill=False, lw=0.3,
                                    ec="black"))

    def title(self, text, fontsize):
        """Above the tile, as an axes title sits (axes.titlepad points above it)."""
        pad = matplotlib.rcParams["axes.titlepad"] / 72
        self.ax.text(self.x + self.side / 2, self.y + self.side + pad, text, fontsize=fontsize,
                     ha="center", va="bottom")

    def below(self, text, drop, **kw):
        """Centred under the tile, its top `drop` tile sides below the tile's lower edge."""
        self.ax.text(self.x + self.side / 2, self.y - drop * self.side, text, ha="center",
                     va="top", **kw)

    def ylabel(self, text, fontsize, pad_pt=2):
        """Left of the tile, turned a quarter, as an axes' y label sits."""
        self.ax.text(self.x - pad_pt / 72, self.y + self.side / 2, text, fontsize=fontsize,
                     rotation=90, rotation_mode="anchor", ha="center", va="bottom")


def image_grid(width, ncols, pads, bottom, left=0.0):
    """A figure of square image tiles, ncols wide: pads[i] inches above row i (titles, labels),
    `bottom` inches below the last row, `left` inches for row labels; exact positions, so the
    images fill the width with no empty band. Returns the figure and its tiles per row."""
    gap, margin = 0.04, 0.03  # margin: each side, so frames and labels stay inside the width
    left += margin
    cell = (width - left - margin - (ncols - 1) * gap) / ncols
    height = sum(pads) + len(pads) * cell + bottom
    fig = plt.figure(figsize=(width, height))
    # the canvas spans the tiles only (its box is part of the saved tight box): data units are
    # the figure's inches
    x1, y0, y1 = width - margin, bottom, height - pads[0]
    ax = fig.add_axes([left / width, y0 / height, (x1 - left) / width, (y1 - y0) / height])
    ax.set_xlim(left, x1)
    ax.set_ylim(y0, y1)
    ax.set_autoscale_on(False)
    ax.axis("off")
    tiles, y = [], height
    for pad in pads:
        y -= pad + cell
        tiles.append([Tile(ax, left + j * (cell + gap), y, cell) for j in range(ncols)])
    return fig, tiles


def curved(r):
    """Whether a row lies on a curved base (a plane row's base is "plane", with no radius)."""
    return r.get("base") not in (None, "", "plane") and num(r.get("radius")) is not None


def base_tag(r):
    """A curved row's base and radius in a file name ("_sphereR0.25"), unless the run's view tag
    (camera_tag: the context keys that vary in the run) names them already."""
    tag = r.get("camera_tag") or ""
    if not curved(r) or "base-" in tag or "_R-" in tag:
        return ""
    return f"_{r['base']}R{num(r['radius']):g}"


def telling_params(settings):
    """{(method, params): "method k=v, ..."}: each setting's method and the parameters whose
    values differ between the given settings of the same method ("off" ones left out)."""
    kv = {s: dict(p.split("=", 1) for p in s[1].split(";") if "=" in p) for s in settings}
    out = {}
    for s in settings:
        same = [o for o in settings if o[0] == s[0]]
        keys = [k for k in kv[s] if len({kv[o].get(k) for o in same}) > 1]
        parts = [f"{k}={kv[s][k]}" for k in keys if kv[s][k] != "off"]
        out[s] = (s[0] + (" " + ", ".join(parts) if parts else "")).strip()
    return out


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
    # a setting's name and every parameter's value: up to 4 lines (a method with many
    # parameters, e.g. silhouette_pom, would lose one in the middle at 3)
    # Each tile is named by what tells it apart: its method and the parameters whose values
    # differ between the montage's settings of that method (the others are the same on every
    # tile: legend.md has them), so no fit() cuts the part that differs.
    apart = telling_params([s for s, _, _ in tiles])
    # the series keys that tell the tiles apart besides the setting (a depth mode, a level mode)
    modes = [k for k in ("lod", "depth") if len({r.get(k) or "" for _, _, r in tiles}) > 1]
    def named(s, r):  # the setting's telling parameters, then the modes it does not name
        extra = [f"{k}={r.get(k)}" for k in modes if f"{k}=" not in apart[s]]
        return apart[s] + ((" " if apart[s] == s[0] else ", ") + ", ".join(extra)
                           if extra else "")

    names = ["truth (ray traced)"] + [fit(named(s, r), cell, 6, 2 if multi else 4) + (
        "\n" + fit(f"[{' = '.join(gs)}]", cell, 6, 1) if multi else "") for s, gs, r in tiles]
    groups = sorted({g for t in tiles for g in t[1]})
    note = None if multi or len(groups) < 2 else (
        " and ".join(groups) + " pictures identical, pixel for pixel: shown once")
    cam = view_title(r0, skip=("base", "radius") if curved(r0) else ())
    cut = r0.get("cut") or ""
    base = f" on a {r0['base']} of radius {num(r0['radius']):g}" if curved(r0) else ""
    title = fit(f"{r0['heightfield']}{base}, θ = {num(r0['theta_deg']):g}°, "
                f"φ = {num(r0['phi_deg']):g}°" + (f", {cam}" if cam else "") +
                ": a numbered checkerboard through each "
                "method's uv" + (f"; blue: the plane at height {num(cut):g} where the depth "
                                 "test shows it" if cut else "") +
                "; below it, |method − truth|" + (f"\n({note})" if note else ""),
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
    fig, tiles = image_grid(F.width, nc, pads, 0.3)
    for k, (s, gs, r) in enumerate(cells):
        top, bottom = tiles[2 * (k // nc)][k % nc], tiles[2 * (k // nc) + 1][k % nc]
        if s is None:
            top.show(load(results, r["picture_truth"]))
            top.title("truth (ray traced)", fontsize=6.5)
            continue
        top.show(load(results, r["picture"]))
        bottom.show(load(results, r["picture_diff"]))
        top.title(names[k], fontsize=6)
        bottom.below(metrics_text(r).replace(", ", "\n"), 0.03, fontsize=5.5)
    fig.suptitle(title, fontsize=7, y=1.0, va="top")
    name = safe(f"picture_{r0['heightfield']}_t{num(r0['theta_deg']):g}_p{num(r0['phi_deg']):g}"
                + (r0.get("camera_tag") or "")
                + base_tag(r0)
                + (f"_cut{num(cut):g}" if cut else ""))
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
    fig, tiles = image_grid(F.width, n, [top, 0.03, 0.03], 0.3, left=0.3)
    for j, r in enumerate(rows):
        for i, key in enumerate(("picture_truth", "picture", "picture_diff")):
            tiles[i][j].show(load(results, r[key]))
        cell = (F.width - 0.3) / n
        tiles[0][j].title(fit(f"θ = {num(r['theta_deg']):g}°", cell, 6, 1), fontsize=6)
        # PSNR over SSIM, alternate tiles a line lower when tiles are too narrow for them
        low = cell < 0.62 and j % 2 == 1
        tiles[2][j].below(metrics_text(r).replace(", ", "\n").replace("PSNR ", "")
                          .replace("SSIM ", ""), 0.03 + (0.42 if low else 0),
                          fontsize=5 if cell < 0.62 else 5.5)
    side = tiles[0][0].side
    small = side < 0.6
    for i, lab in enumerate(("truth", st.labels[s], "|diff.|" if small else "|difference|")):
        tiles[i][0].ylabel(fit(lab, side, 5 if small else 6, 3 if small else 2),
                           fontsize=5 if small else 6)
    fig.suptitle(title, fontsize=7, y=1.0, va="top")
    name = safe(f"strip_{r0['heightfield']}_p{num(r0['phi_deg']):g}{view_tag(r0)}"
                + base_tag(r0))
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
        # a GIF frame's palette by fast octree, not Pillow's default median cut at save (a
        # third of a strip's time); the pictures hold far fewer than 256 colours either way
        frames.append(canvas.quantize(256, method=Image.Quantize.FASTOCTREE,
                                      dither=Image.Dither.NONE))
    path = F.files.write(name + ".gif", lambda f: frames[0].save(
        f, format="GIF", save_all=True, append_images=frames[1:], duration=900, loop=0))
    print(f"plot: {path}")
    F.drawn[-1]["files"].append(name + ".gif")


def picture_jobs(F, st, rows):
    """A drawing job per montage and per strip (independent figures: drawn in parallel)."""
    results = os.path.dirname(os.path.abspath(F.out))
    views, strips = picture_groups(rows)
    return ([lambda v=v: picture_montage(F, st, results, v) for v in views.values()] +
            [lambda v=v: strip(F, st, results, v) for v in strips.values()])


def picture_groups(rows):
    """The montages (per view) and strips (per field, azimuth, view and setting) of the rows."""
    views = {}
    strips = {}
    for r in rows:  # a montage per view (camera keys included: one truth each), a strip per
        # field, azimuth, camera view and setting (its level mode: one strip each)
        cam = r.get("camera_view", "")
        if "montage" in r["picture_use"].split():  # a cut plane's own montage (its truth)
            views.setdefault((r["heightfield"], r["theta_deg"], r["phi_deg"], cam,
                              r.get("cut") or "", r.get("base") or "", r.get("radius") or ""),
                             []).append(r)
        if "strip" in r["picture_use"].split():
            strips.setdefault((r["heightfield"], r["phi_deg"], cam, r.get("base") or "",
                               r.get("radius") or "", setting(r)), []).append(r)
    return views, strips


def pictures(F, st, rows):
    """Every montage and strip of the rows, drawn here (plot_report.py draws picture_jobs in
    parallel instead)."""
    for job in picture_jobs(F, st, rows):
        job()

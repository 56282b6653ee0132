"""pxh report's plot script (plot_report.py): the error-map montages (a row per series, a column
per view angle, identical maps shown once) and their shared colour bar."""
import math
import os
import sys

import matplotlib.image as mpimg
import numpy as np

from plot_files import inside, num, safe
from plot_text import column_heads, fit, short_params, view_title
from plot_figures import group, plt, setting


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

#!/usr/bin/python3
"""An independent check of pxh's perspective and level rows, from the contract alone.

    independent_check.py field OUT.png [--width W] [--height H] [--seed S]
    independent_check.py selftest
    independent_check.py check RUN_DIR [--root DIR] [--tolerance 0.02]
                                       [--require-backend cpu] [--quiet]

`field` writes a tileable height field of the check's own random process (a sum of random
sinusoids of whole periods per tile plus random periodic bumps, normalised to [0.03, 0.97]) as a
16-bit greyscale PNG, written by this file's own PNG encoder.

`check` reads a pxh results folder (results.csv, and run.json, whose `inputs` name the height
files and their sha256) and recomputes, for every ok row of the methods parallax, steep and pom
with lod `base` or `level` (parameters from the row's `params`), the columns err_mean, err_p50,
fetches_mean, err_px_mean and samples_outside, and lod_mean (the mean of max(lambda, 0) over
the inside pixels, whatever the row's lod: it pins the footprint and lambda on their own). It
uses nothing of pxh but the numbers it wrote: the field is decoded from the PNG here, and the
camera, the footprint, the texture levels, the trilinear fetch, the exact ground truth, the
methods and the statistics are written from the contract (docs/conventions.md, sections 1-5,
6 and 10, the repository's statement of it) in numpy.

Precision: everything runs in float64. pxh's rows are float (CPU float twin, GLSL); the float
rounding of a uv near 1 is about 6e-8 tile, 1e-5 texel at these sizes, far below 2% of any
measured error but not of an error that is itself near zero, hence the absolute floor below.
A layer decision that float rounding flips (a ray height within 1e-7 of the surface at a layer)
moves one sample by one layer; at 4096 samples that is 0.025% of a mean per flipped sample.

Pass rule per cell: |pxh - check| <= max(tolerance * |check|, floor), tolerance 2% (relative
difference printed as |pxh - check| / |check|), floor 1e-4 texel (err_mean, err_p50), 1e-4
pixel (err_px_mean), 1e-6 level (lod_mean, double on both sides), 0 for fetches_mean and
samples_outside (exact counts; the 2% still applies). The floor is about ten times the float
resolution of a uv in texels at the field sizes the check is meant for (<= 256 texels a side),
so it only matters for rows whose error is itself float noise (pom at level 0 and a gentle
angle: 1e-5 texel; s -> 0).

Rows of other methods or lods are ignored; a row that is not ok is listed as not checked, and
fails the check when its backend is named by --require-backend (so the CPU rows can be required
while a backend that cannot draw the view yet only reports its failed rows).

`selftest` checks the check's own pieces: the PNG reader on every filter type, the levels
(constant fields, power-of-two boxes, weights summing to 1, the 5 -> 2 weights), the trilinear
fetch, the orthographic lambda, the footprint against differences, the outside pixels against
the rays' angles, the exact hits against a fine march, and the methods' closed-form limits.

Exit 0 when every compared cell passes and at least one row was compared (and, with
--require-backend, every row of each named backend is ok and at least one was compared); 1 when
a cell fails; 2 on bad input (one line naming the file and the problem)."""
import argparse
import csv
import hashlib
import json
import math
import os
import struct
import sys
import zlib

import numpy as np

METHODS = ("parallax", "steep", "pom")
LODS = ("base", "level")
COLUMNS = ("err_mean", "err_p50", "fetches_mean", "err_px_mean", "samples_outside", "lod_mean")
FLOORS = {"err_mean": 1e-4, "err_p50": 1e-4, "err_px_mean": 1e-4, "fetches_mean": 0.0,
          "samples_outside": 0.0, "lod_mean": 1e-6}
COS_89 = math.cos(math.radians(89.0))


class BadInput(Exception):
    pass


# ---------------------------------------------------------------------------------------------
# PNG: a writer and a reader of greyscale images (8/16-bit, non-interlaced), no library.

def png_write_gray16(path, values):
    """values: H x W array of uint16; row 0 is written first (pxh reads it as j = 0)."""
    h, w = values.shape
    raw = b"".join(b"\x00" + values[j].astype(">u2").tobytes() for j in range(h))

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    ihdr = struct.pack(">IIBBBBB", w, h, 16, 0, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) +
                chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def png_read_gray(path):
    """The greyscale PNG at path as an H x W float64 array in [0, 1] (0..max -> [0, 1]),
    row j = the j-th row stored."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise BadInput(f"{path}: not a PNG file")
    pos, idat, hdr = 8, [], None
    while pos + 8 <= len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            hdr = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
        pos += 12 + n
    if hdr is None:
        raise BadInput(f"{path}: PNG without IHDR")
    w, h, depth, colour, _, _, interlace = hdr
    if colour != 0 or depth not in (8, 16) or interlace != 0:
        raise BadInput(f"{path}: only non-interlaced 8/16-bit greyscale PNGs are read here "
                       f"(colour type {colour}, depth {depth}, interlace {interlace})")
    bpp = depth // 8
    stride = w * bpp
    raw = zlib.decompress(b"".join(idat))
    if len(raw) != h * (stride + 1):
        raise BadInput(f"{path}: {len(raw)} bytes of pixels, expected {h * (stride + 1)}")
    out = np.zeros((h, stride), np.uint8)
    prev = np.zeros(stride, np.int32)
    for j in range(h):
        ftype = raw[j * (stride + 1)]
        line = np.frombuffer(raw, np.uint8, stride, j * (stride + 1) + 1).astype(np.int32)
        cur = np.zeros(stride, np.int32)
        if ftype == 0:
            cur = line
        elif ftype == 2:
            cur = (line + prev) & 255
        elif ftype in (1, 3, 4):
            for k in range(stride):  # byte by byte: each depends on the one bpp to its left
                left = cur[k - bpp] if k >= bpp else 0
                up = prev[k]
                if ftype == 1:
                    pred = left
                elif ftype == 3:
                    pred = (left + up) >> 1
                else:
                    ul = prev[k - bpp] if k >= bpp else 0
                    p = left + up - ul
                    pa, pb, pc = abs(p - left), abs(p - up), abs(p - ul)
                    pred = left if pa <= pb and pa <= pc else (up if pb <= pc else ul)
                cur[k] = (line[k] + pred) & 255
        else:
            raise BadInput(f"{path}: row {j} has PNG filter type {ftype}")
        out[j] = cur
        prev = cur
    if depth == 16:
        vals = out.reshape(h, w, 2).astype(np.uint32)
        return ((vals[..., 0] << 8) | vals[..., 1]).astype(np.float64) / 65535.0
    return out.astype(np.float64) / 255.0


def make_field(width, height, seed):
    """A tileable field of its own random process: random sinusoids with whole periods per tile
    (amplitude falling as 1/|k|) plus random bumps of periodic distance, in [0.03, 0.97]."""
    rng = np.random.default_rng(seed)
    u = (np.arange(width) + 0.5) / width
    v = (np.arange(height) + 0.5) / height
    uu, vv = np.meshgrid(u, v)
    f = np.zeros_like(uu)
    for _ in range(24):
        kx, ky = rng.integers(-9, 10, 2)
        if kx == 0 and ky == 0:
            continue
        amp = rng.uniform(0.3, 1.0) / math.hypot(kx, ky)
        f += amp * np.sin(2 * math.pi * (kx * uu + ky * vv) + rng.uniform(0, 2 * math.pi))
    for _ in range(14):
        cx, cy = rng.uniform(0, 1, 2)
        radius = rng.uniform(0.03, 0.12)
        dx = (uu - cx + 0.5) % 1.0 - 0.5
        dy = (vv - cy + 0.5) % 1.0 - 0.5
        f += rng.uniform(-1.0, 1.5) * np.exp(-(dx * dx + dy * dy) / (2 * radius * radius))
    f = (f - f.min()) / (f.max() - f.min())
    return np.round((0.03 + 0.94 * f) * 65535).astype(np.uint16)


# ---------------------------------------------------------------------------------------------
# Heights: the bilinear rule, the area-weighted levels and GL's trilinear fetch.

def bilinear(tex, u, v):
    """GL_LINEAR + GL_REPEAT on tex (rows j, columns i) at uv; texel centres at (i+0.5)/W."""
    h, w = tex.shape
    x = u * w - 0.5
    y = v * h - 0.5
    i0 = np.floor(x)
    j0 = np.floor(y)
    fx = x - i0
    fy = y - j0
    i0 = i0.astype(np.int64) % w
    j0 = j0.astype(np.int64) % h
    i1 = (i0 + 1) % w
    j1 = (j0 + 1) % h
    return ((tex[j0, i0] * (1 - fx) + tex[j0, i1] * fx) * (1 - fy) +
            (tex[j1, i0] * (1 - fx) + tex[j1, i1] * fx) * fy)


def axis_weights(n, n_level):
    """n_level x n matrix: texel i of the level covers [i n/n_level, (i+1) n/n_level) in
    level-0 texels; each level-0 texel weighs its overlap, the row divided by its length."""
    m = np.zeros((n_level, n))
    span = n / n_level
    for i in range(n_level):
        lo, hi = i * span, (i + 1) * span
        for k in range(int(math.floor(lo)), min(n, int(math.ceil(hi)))):
            m[i, k] = max(0.0, min(hi, k + 1) - max(lo, k))
    return m / span


def build_levels(h0):
    hgt, wid = h0.shape
    q = int(math.floor(math.log2(max(wid, hgt))))
    levels = [h0]
    for lvl in range(1, q + 1):
        wl, hl = max(1, wid >> lvl), max(1, hgt >> lvl)
        levels.append(axis_weights(hgt, hl) @ h0 @ axis_weights(wid, wl).T)
    return levels


def fetch(levels, u, v, lam):
    """Height at uv: level 0 (lam None), else LINEAR_MIPMAP_LINEAR at lambda lam."""
    if lam is None:
        return bilinear(levels[0], u, v)
    q = len(levels) - 1
    out = np.empty_like(u)
    mag = ~(lam > 0)
    out[mag] = bilinear(levels[0], u[mag], v[mag])
    ell = np.minimum(lam, q)
    d1 = np.where(mag, -1, np.floor(ell)).astype(np.int64)
    for d in np.unique(d1[~mag]):
        sel = d1 == d
        b1 = bilinear(levels[d], u[sel], v[sel])
        if d == q:
            out[sel] = b1
        else:
            tau = ell[sel] - d
            out[sel] = b1 + (bilinear(levels[d + 1], u[sel], v[sel]) - b1) * tau
    return out


# ---------------------------------------------------------------------------------------------
# Cameras: per pixel P, V, outside, footprint J.

def view_vector(theta, phi):
    t, p = math.radians(theta), math.radians(phi)
    return np.array([math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)])


def subset_pixels(n, res):
    """The image pixel of each of n samples along one axis of an image of res pixels:
    floor((a + 0.5) res / n)."""
    return ((2 * np.arange(n) + 1) * res) // (2 * n)


def perspective(theta, phi, dist, fov, n, res=None):
    """P (n*n x 2), V (n*n x 3), inside mask, dP/di and dP/dj (n*n x 2); sample b n + a is
    image pixel (subset_pixels(a), subset_pixels(b)) of the res x res image (res = n: pixel
    (a, b))."""
    res = n if res is None else res
    t, p = math.radians(theta), math.radians(phi)
    v0 = view_vector(theta, phi)
    eye = np.array([0.5, 0.5, 0.0]) + dist * v0
    fwd = -v0
    right = np.array([-math.sin(p), math.cos(p), 0.0])
    up = np.array([-math.cos(t) * math.cos(p), -math.cos(t) * math.sin(p), math.sin(t)])
    a = math.tan(math.radians(fov) / 2)
    px = subset_pixels(n, res)
    jj, ii = np.meshgrid(px, px, indexing="ij")
    x = (2 * (ii.ravel() + 0.5) / res - 1)[:, None]
    y = (2 * (jj.ravel() + 0.5) / res - 1)[:, None]
    d = fwd + a * x * right + a * y * up
    with np.errstate(divide="ignore", invalid="ignore"):
        pt = eye - (eye[2] / d[:, 2:3]) * d
        vv = -d / np.linalg.norm(d, axis=1, keepdims=True)
        inside = vv[:, 2] > COS_89
        dz = d[:, 2:3]
        k = -eye[2] * (2 * a / res) / (dz * dz)
        dpdi = k * (right * dz - d * right[2])
        dpdj = k * (up * dz - d * up[2])
    return pt[:, :2], vv, inside, dpdi[:, :2], dpdj[:, :2], (eye, d)


def orthographic(theta, phi, n):
    c = (np.arange(n) + 0.5) / n
    jj, ii = np.meshgrid(c, c, indexing="ij")
    pt = np.stack([ii.ravel(), jj.ravel()], axis=1)
    vv = np.tile(view_vector(theta, phi), (n * n, 1))
    dpdi = np.tile([1.0 / n, 0.0], (n * n, 1))
    dpdj = np.tile([0.0, 1.0 / n], (n * n, 1))
    return pt, vv, np.ones(n * n, bool), dpdi, dpdj


def footprint_by_differences(theta, phi, dist, fov, n, step=1e-3, res=None):
    """dP/di, dP/dj by central differences of P over a fraction of a pixel (the closed form's
    independent check)."""
    res = n if res is None else res
    t, p = math.radians(theta), math.radians(phi)
    v0 = view_vector(theta, phi)
    eye = np.array([0.5, 0.5, 0.0]) + dist * v0
    right = np.array([-math.sin(p), math.cos(p), 0.0])
    up = np.array([-math.cos(t) * math.cos(p), -math.cos(t) * math.sin(p), math.sin(t)])
    a = math.tan(math.radians(fov) / 2)
    px = subset_pixels(n, res)
    jj, ii = np.meshgrid(px, px, indexing="ij")

    def point(di, dj):
        x = (2 * (ii.ravel() + 0.5 + di) / res - 1)[:, None]
        y = (2 * (jj.ravel() + 0.5 + dj) / res - 1)[:, None]
        d = -v0 + a * x * right + a * y * up
        with np.errstate(divide="ignore", invalid="ignore"):
            return (eye - (eye[2] / d[:, 2:3]) * d)[:, :2]

    return ((point(step, 0) - point(-step, 0)) / (2 * step),
            (point(0, step) - point(0, -step)) / (2 * step))


def lambdas(dpdi, dpdj, wid, hgt):
    scale = np.array([wid, hgt], float)
    rho = np.maximum(np.linalg.norm(dpdi * scale, axis=1), np.linalg.norm(dpdj * scale, axis=1))
    return np.log2(rho)


# ---------------------------------------------------------------------------------------------
# Ground truth: the first hit of P + t V (from z_top, along -V) with z = s (h - b), h bilinear.

def exact_hits(h0, s, b, pts, vv):
    """uv of the first hit, unwrapped, for every ray (P on z = 0, V toward the eye): a DDA over
    the cells between texel centres; per cell the ray's height above the bilinear patch is a
    quadratic in the travel, whose first root in the cell is the hit."""
    hgt, wid = h0.shape
    z_top = s * (1 - b)
    nray = len(pts)
    start = pts + vv[:, :2] * (z_top / vv[:, 2:3])  # the ray at z = z_top
    # texel coordinates x = u W - 0.5 along the travel tau (the ray S - tau V)
    x0 = start[:, 0] * wid - 0.5
    y0 = start[:, 1] * hgt - 0.5
    dx = -vv[:, 0] * wid
    dy = -vv[:, 1] * hgt
    vz = vv[:, 2]
    tau_end = s / vz  # the ray reaches z_bot: the surface is at or above it
    ix = np.floor(x0)
    iy = np.floor(y0)
    ix = np.where((x0 == ix) & (dx < 0), ix - 1, ix)
    iy = np.where((y0 == iy) & (dy < 0), iy - 1, iy)
    with np.errstate(divide="ignore"):
        tdx = np.where(dx != 0, 1.0 / np.abs(dx), np.inf)
        tdy = np.where(dy != 0, 1.0 / np.abs(dy), np.inf)
        tmx = np.where(dx > 0, (ix + 1 - x0) / dx, np.where(dx < 0, (ix - x0) / dx, np.inf))
        tmy = np.where(dy > 0, (iy + 1 - y0) / dy, np.where(dy < 0, (iy - y0) / dy, np.inf))
    sx = np.sign(dx)
    sy = np.sign(dy)
    tau_in = np.zeros(nray)
    hit = np.full(nray, np.nan)
    act = np.arange(nray)
    guard = 0
    while act.size:
        guard += 1
        if guard > 100000:
            raise RuntimeError("exact_hits: a ray crossed 100000 cells")
        t0 = tau_in[act]
        t1 = np.minimum(np.minimum(tmx[act], tmy[act]), tau_end[act])
        cx, cy = ix[act], iy[act]
        i0 = cx.astype(np.int64) % wid
        j0 = cy.astype(np.int64) % hgt
        i1 = (i0 + 1) % wid
        j1 = (j0 + 1) % hgt
        h00, h10, h01, h11 = h0[j0, i0], h0[j0, i1], h0[j1, i0], h0[j1, i1]
        c1, c2, c3 = h10 - h00, h01 - h00, h00 - h10 - h01 + h11
        ddx, ddy = dx[act], dy[act]
        fx0 = x0[act] + ddx * t0 - cx
        fy0 = y0[act] + ddy * t0 - cy
        hin = h00 + c1 * fx0 + c2 * fy0 + c3 * fx0 * fy0
        cc = z_top - t0 * vz[act] - s * (hin - b)
        bb = -vz[act] - s * (c1 * ddx + c2 * ddy + c3 * (fx0 * ddy + fy0 * ddx))
        aa = -s * c3 * ddx * ddy
        span = t1 - t0
        with np.errstate(divide="ignore", invalid="ignore"):
            disc = bb * bb - 4 * aa * cc
            sq = np.sqrt(np.maximum(disc, 0.0))
            qq = -0.5 * (bb + np.copysign(sq, bb))
            r1 = np.where(aa != 0, qq / aa, np.inf)
            r2 = np.where(qq != 0, cc / qq, np.inf)
        ok_disc = disc >= 0
        tol = 1e-12 * np.maximum(span, 1e-300)
        best = np.full(act.size, np.inf)
        for r in (r1, r2):
            good = ok_disc & np.isfinite(r) & (r >= -tol) & (r <= span + tol)
            best = np.where(good & (r < best), r, best)
        found = np.isfinite(best) | (cc <= 0)
        best = np.where(np.isfinite(best), np.clip(best, 0.0, span), best)
        best = np.where(cc <= 0, 0.0, best)
        # rounding guard: the end value proves a crossing the roots missed; bisect for it
        gend = cc + span * (bb + aa * span)
        missed = ~found & (gend <= 0)
        if missed.any():
            lo = np.zeros(missed.sum())
            hi = span[missed]
            ca, cb, ccm = aa[missed], bb[missed], cc[missed]
            for _ in range(80):
                mid = 0.5 * (lo + hi)
                gm = ccm + mid * (cb + ca * mid)
                lo = np.where(gm > 0, mid, lo)
                hi = np.where(gm > 0, hi, mid)
            best[missed] = hi
            found = found | missed
        last = t1 >= tau_end[act]
        done = found | last
        fin = np.where(found, t0 + best, tau_end[act])
        hit[act[done]] = fin[done]
        # advance the rest to the next cell
        rest = ~done
        ar = act[rest]
        stepx = tmx[ar] <= tmy[ar]
        ax, ay = ar[stepx], ar[~stepx]
        tau_in[ax] = tmx[ax]
        ix[ax] += sx[ax]
        tmx[ax] += tdx[ax]
        tau_in[ay] = tmy[ay]
        iy[ay] += sy[ay]
        tmy[ay] += tdy[ay]
        act = ar
    return start - hit[:, None] * vv[:, :2]


# ---------------------------------------------------------------------------------------------
# The methods (docs/conventions.md section 6), each height fetch at the pixel's lambda or level 0.

def surface(levels, s, b, uv, lam):
    return s * (fetch(levels, uv[:, 0], uv[:, 1], lam) - b)


def parallax(levels, s, b, pts, vv, lam):
    z = surface(levels, s, b, pts, lam)
    return pts + z[:, None] * vv[:, :2] / vv[:, 2:3], np.ones(len(pts))


def layered(levels, s, b, pts, vv, lam, layers, interpolate):
    """steep (interpolate False) and pom (True): layer k at uv_0 + k duv, z_top - k dz; the first
    k with g_k <= 0, k = ceil(n) at the latest; fetches k + 1."""
    n = layers(vv[:, 2])
    kmax = np.ceil(n).astype(np.int64)
    z_top = s * (1 - b)
    dz = s / n
    duv = -vv[:, :2] / vv[:, 2:3] * dz[:, None]
    uv0 = pts + vv[:, :2] / vv[:, 2:3] * z_top
    m = len(pts)
    uv_k = uv0.copy()
    g_prev = np.zeros(m)
    k_stop = np.full(m, -1)
    uv_out = np.zeros((m, 2))
    act = np.arange(m)
    k = 0
    while act.size:
        uvk = uv0[act] + k * duv[act]
        lk = None if lam is None else lam[act]
        g = (z_top - k * dz[act]) - surface(levels, s, b, uvk, lk)
        stop = (g <= 0) | (k >= kmax[act])
        st = act[stop]
        k_stop[st] = k
        if interpolate and k > 0:
            gp = g_prev[st]
            gk = g[stop]
            den = gk - gp
            w = np.where(den != 0, gk / np.where(den != 0, den, 1.0), 0.0)
            prev = uv0[st] + (k - 1) * duv[st]
            uv_out[st] = w[:, None] * prev + (1 - w[:, None]) * uvk[stop]
        else:
            uv_out[st] = uvk[stop]
        g_prev[act] = g
        act = act[~stop]
        k += 1
    return uv_out, (k_stop + 1).astype(float)


def parse_params(text):
    out = {}
    for part in text.split(";"):
        part = part.strip()
        if part:
            key, _, val = part.partition("=")
            out[key.strip()] = val.strip()
    return out


def layer_rule(params, where):
    layers = params.get("layers", "32")
    if layers == "adaptive":
        try:
            lo, hi = float(params["layers_min"]), float(params["layers_max"])
        except (KeyError, ValueError):
            raise BadInput(f"{where}: adaptive layers without numeric layers_min/layers_max")
        return lambda vz: hi + (lo - hi) * np.abs(vz)  # mix(n_max, n_min, |V.z|)
    try:
        n = float(layers)
    except ValueError:
        raise BadInput(f"{where}: layers '{layers}' is neither a number nor 'adaptive'")
    return lambda vz: np.full(len(vz), n)


def run_method(name, params, levels, s, b, pts, vv, lam, where):
    if name == "parallax":
        return parallax(levels, s, b, pts, vv, lam)
    return layered(levels, s, b, pts, vv, lam, layer_rule(params, where), name == "pom")


# ---------------------------------------------------------------------------------------------
# Errors (section 5 and the pixel error of section 7) and the row's statistics.

def wrap(e):
    return e - np.floor(e + 0.5)  # per component to [-0.5, 0.5)


def statistics(uv, uv_true, dpdi, dpdj, fetches, wid, hgt):
    e = wrap(uv - uv_true)
    texel = np.hypot(e[:, 0] * wid, e[:, 1] * hgt)
    # J^-1 e with J = [dP/di dP/dj] (columns)
    a, c = dpdi[:, 0], dpdi[:, 1]
    bq, d = dpdj[:, 0], dpdj[:, 1]
    det = a * d - bq * c
    px_i = (d * e[:, 0] - bq * e[:, 1]) / det
    px_j = (-c * e[:, 0] + a * e[:, 1]) / det
    px = np.hypot(px_i, px_j)
    return {"err_mean": float(texel.mean()), "err_p50": float(np.percentile(texel, 50)),
            "fetches_mean": float(fetches.mean()), "err_px_mean": float(px.mean())}


# ---------------------------------------------------------------------------------------------
# The results folder.

def read_rows(run_dir):
    path = os.path.join(run_dir, "results.csv")
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        raise BadInput(f"{path}: {e.strerror}")
    need = ("method", "params", "lod", "camera", "status", "heightfield", "scale", "bias",
            "theta_deg", "phi_deg", "samples", "backend") + COLUMNS
    if rows:
        missing = [c for c in need if c not in rows[0]]
        if missing:
            raise BadInput(f"{path}: no column(s) {', '.join(missing)}")
    return rows


def field_files(run_dir, root):
    """heightfield name -> (path, sha256) of every image file the run read (run.json's
    `inputs`: paths as given to pxh, relative to the folder it ran in, `root`)."""
    rj_path = os.path.join(run_dir, "run.json")
    try:
        with open(rj_path) as f:
            rj = json.load(f)
    except (OSError, ValueError) as e:
        raise BadInput(f"{rj_path}: {e}")
    out = {}
    for entry in rj.get("inputs", []):
        if isinstance(entry, dict) and "heightfield" in entry and "path" in entry:
            out[entry["heightfield"]] = (os.path.join(root, entry["path"]), entry.get("sha256"))
    return out


def load_field(path, sha256):
    try:
        with open(path, "rb") as f:
            digest = hashlib.sha256(f.read()).hexdigest()
    except OSError as e:
        raise BadInput(f"{path}: {e.strerror} (--root names the folder pxh ran in)")
    if digest != sha256:
        raise BadInput(f"{path}: sha256 {digest}, the run recorded {sha256} (the file changed "
                       f"since the run, or --root names another folder)")
    return png_read_gray(path)


def check(args):
    rows = read_rows(args.run_dir)
    fields = field_files(args.run_dir, args.root)
    cache = {}
    compared, failures, skipped = [], [], []
    worst = {c: 0.0 for c in COLUMNS}  # over the cells the relative rule decides
    worst_all = {c: (0.0, 0.0) for c in COLUMNS}  # over every cell: (relative, check value)
    backends = set()
    for line, row in enumerate(rows, start=2):
        where = f"{os.path.join(args.run_dir, 'results.csv')}:{line}"
        if row["method"] not in METHODS or row["lod"] not in LODS:
            continue
        if row["status"] != "ok":
            if row["backend"] in args.require_backend:
                failures.append(f"{where}: {row['method']} {row['backend']} (a required "
                                f"backend) failed: {row.get('error', '')[:160]}")
                continue
            skipped.append(f"{where}: {row['method']} {row['backend']} not ok: "
                           f"{row.get('error', '')[:160]}")
            continue
        if row["camera"] not in ("perspective", "orthographic"):
            skipped.append(f"{where}: camera '{row['camera']}' not checked")
            continue
        if row["heightfield"] not in fields:
            raise BadInput(f"{where}: heightfield '{row['heightfield']}' is not an image file "
                           f"of the experiment (the check reads the field from its file)")
        if row["heightfield"] not in cache:
            h0 = load_field(*fields[row["heightfield"]])
            cache[row["heightfield"]] = (h0, build_levels(h0))
        h0, levels = cache[row["heightfield"]]
        hgt, wid = h0.shape
        s, b = float(row["scale"]), float(row["bias"])
        theta, phi, n = float(row["theta_deg"]), float(row["phi_deg"]), int(row["samples"])
        if row["camera"] == "perspective":
            dist, fov = float(row["distance"]), float(row["fov_deg"])
            # Results written before the camera had a resolution: an image of n pixels a side.
            res = int(float(row["resolution"])) if row.get("resolution") else n
            key = ("p", row["heightfield"], s, b, theta, phi, n, dist, fov, res)
        else:
            key = ("o", row["heightfield"], s, b, theta, phi, n)
        if key not in cache:
            if row["camera"] == "perspective":
                pts, vv, inside, dpdi, dpdj, _ = perspective(theta, phi, dist, fov, n, res)
                fdi, fdj = footprint_by_differences(theta, phi, dist, fov, n, res=res)
                interior = inside.copy()
                jj, ii = np.divmod(np.arange(n * n), n)
                interior &= (ii > 0) & (ii < n - 1) & (jj > 0) & (jj < n - 1)
                for fd, cf in ((fdi, dpdi), (fdj, dpdj)):
                    rel = (np.linalg.norm(fd[interior] - cf[interior], axis=1) /
                           np.linalg.norm(cf[interior], axis=1))
                    if rel.size and rel.max() > 1e-4:
                        raise RuntimeError(f"closed-form footprint disagrees with finite "
                                           f"differences by {rel.max():.3g} ({key})")
            else:
                pts, vv, inside, dpdi, dpdj = orthographic(theta, phi, n)
            p_in, v_in = pts[inside], vv[inside]
            truth = exact_hits(h0, s, b, p_in, v_in)
            lam = lambdas(dpdi[inside], dpdj[inside], wid, hgt)
            cache[key] = (p_in, v_in, inside, dpdi[inside], dpdj[inside], truth, lam)
        p_in, v_in, inside, dpdi, dpdj, truth, lam = cache[key]
        params = parse_params(row["params"])
        uv, fetches = run_method(row["method"], params, levels, s, b, p_in, v_in,
                                 lam if row["lod"] == "level" else None, where)
        mine = statistics(uv, truth, dpdi, dpdj, fetches, wid, hgt)
        mine["samples_outside"] = float((~inside).sum())
        mine["lod_mean"] = float(np.maximum(lam, 0.0).mean())
        backends.add(row["backend"])
        label = (f"{row['method']} {row['params']} lod={row['lod']} {row['backend']} "
                 f"t={row['theta_deg']} D={row.get('distance', '')}")
        cells = []
        for col in COLUMNS:
            try:
                theirs = float(row[col])
            except ValueError:
                raise BadInput(f"{where}: column {col} is '{row[col]}', not a number")
            ref = mine[col]
            diff = abs(theirs - ref)
            rel = diff / abs(ref) if ref != 0 else (0.0 if diff == 0 else math.inf)
            if rel > worst_all[col][0]:
                worst_all[col] = (rel, ref)
            if args.tolerance * abs(ref) >= FLOORS[col]:
                worst[col] = max(worst[col], rel)
            ok = diff <= max(args.tolerance * abs(ref), FLOORS[col])
            cells.append((col, theirs, ref, rel, ok))
            if not ok:
                failures.append(f"{where}: {label}: {col} pxh {theirs:.6g} check {ref:.6g} "
                                f"(relative difference {rel:.3%})")
        compared.append((label, cells))
    if not args.quiet:
        for label, cells in compared:
            print(label + ": " + ", ".join(
                f"{c} {t:.5g}/{r:.5g}{'' if ok else ' FAIL'}" for c, t, r, _, ok in cells))
    if skipped:
        kinds = {}
        for msg in skipped:
            kinds.setdefault(msg.split(": ", 2)[-1], []).append(msg)
        for why, msgs in kinds.items():
            print(f"not checked: {len(msgs)} row(s), e.g. {msgs[0]}")
    print(f"{len(compared)} row(s) compared ({len(compared) * len(COLUMNS)} cells; backends: "
          f"{', '.join(sorted(backends)) or 'none'}), tolerance {args.tolerance * 100:g}%")
    print("max relative difference per column, where the 2% rule decides (tolerance x value "
          "above the floor): " + ", ".join(f"{c} {worst[c]:.3g}" for c in COLUMNS))
    print("max relative difference per column over every row (value at that cell): " +
          ", ".join(f"{c} {worst_all[c][0]:.3g} ({worst_all[c][1]:.3g})" for c in COLUMNS))
    for msg in failures:
        print("FAIL " + msg)
    missing = [bk for bk in args.require_backend if bk not in backends]
    if not compared:
        print("FAIL: no row of parallax/steep/pom with lod base or level was compared")
        return 1
    if missing:
        print(f"FAIL: no compared row of backend(s) {', '.join(missing)}")
        return 1
    print("PASS" if not failures else f"FAIL: {len(failures)} cell(s) off by more than "
          f"{args.tolerance * 100:g}%")
    return 0 if not failures else 1


def png_write_filtered(path, values, depth):
    """A greyscale PNG whose rows cycle through the filter types 0-4 (the reader's test)."""
    h, w = values.shape
    bpp = depth // 8
    rows = [values[j].astype(">u2" if depth == 16 else "u1").tobytes() for j in range(h)]
    raw = bytearray()
    prev = bytes(w * bpp)
    for j, row in enumerate(rows):
        ftype = j % 5
        out = bytearray(len(row))
        for k in range(len(row)):
            left = row[k - bpp] if k >= bpp else 0
            up = prev[k]
            ul = prev[k - bpp] if k >= bpp else 0
            pred = [0, left, up, (left + up) >> 1, 0][ftype]
            if ftype == 4:
                p = left + up - ul
                pa, pb, pc = abs(p - left), abs(p - up), abs(p - ul)
                pred = left if pa <= pb and pa <= pc else (up if pb <= pc else ul)
            out[k] = (row[k] - pred) & 255
        raw += bytes([ftype]) + out
        prev = row

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" +
                chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, depth, 0, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(bytes(raw))) + chunk(b"IEND", b""))


def selftest(args):
    """The check's own pieces against closed forms and brute force."""
    import tempfile
    rng = np.random.default_rng(5)
    results = []

    def expect(name, ok, detail):
        results.append(ok)
        print(f"{'ok  ' if ok else 'FAIL'} {name}: {detail}")

    with tempfile.TemporaryDirectory() as tmp:
        for depth in (8, 16):
            vals = rng.integers(0, 2 ** depth, (11, 7))
            path = os.path.join(tmp, f"f{depth}.png")
            png_write_filtered(path, vals, depth)
            back = png_read_gray(path)
            err = np.abs(back * (2 ** depth - 1) - vals).max()
            expect(f"PNG {depth}-bit, filters 0-4", err < 1e-9, f"max error {err:.3g}")
        f16 = make_field(30, 20, 1)
        path = os.path.join(tmp, "field.png")
        png_write_gray16(path, f16)
        err = np.abs(png_read_gray(path) * 65535 - f16).max()
        expect("the field's PNG round trip", err < 1e-9, f"max error {err:.3g}")
    lv = build_levels(np.full((70, 90), 0.3))
    err = max(np.abs(x - 0.3).max() for x in lv)
    expect("a constant field on every level", err < 1e-12, f"{len(lv)} levels, max error {err:.3g}")
    p2 = rng.random((32, 64))
    lv = build_levels(p2)
    err = max(np.abs(lv[k] - p2.reshape(32 >> k, 1 << k, 64 >> k, 1 << k).mean((1, 3))).max()
              for k in range(1, 6))
    expect("power-of-two levels = 2^L x 2^L boxes", err < 1e-12, f"max error {err:.3g}")
    sums = max(np.abs(axis_weights(n, max(1, n >> k)).sum(1) - 1).max()
               for n in range(1, 71) for k in range(1, 8))
    expect("area weights of sizes 1-70 sum to 1", sums < 1e-12, f"max error {sums:.3g}")
    w52 = axis_weights(5, 2)
    expect("5 -> 2 weights", np.allclose(w52, [[0.4, 0.4, 0.2, 0, 0], [0, 0, 0.2, 0.4, 0.4]]),
           str(w52.round(3).tolist()))
    field = rng.random((14, 18))
    lv = build_levels(field)
    u, v = rng.random(500) * 3 - 1, rng.random(500) * 3 - 1
    e0 = np.abs(fetch(lv, u, v, np.full(500, -0.7)) - bilinear(field, u, v)).max()
    e2 = np.abs(fetch(lv, u, v, np.full(500, 2.0)) - bilinear(lv[2], u, v)).max()
    blend = (1 - 0.3) * bilinear(lv[1], u, v) + 0.3 * bilinear(lv[2], u, v)
    e13 = np.abs(fetch(lv, u, v, np.full(500, 1.3)) - blend).max()
    eq = np.abs(fetch(lv, u, v, np.full(500, 9.0)) - lv[-1][0, 0]).max()
    expect("trilinear fetch: lambda <= 0, integer, between, past q",
           max(e0, e2, e13, eq) < 1e-12, f"{e0:.2g} {e2:.2g} {e13:.2g} {eq:.2g}")
    dpdi = np.tile([1 / 64, 0.0], (3, 1))
    dpdj = np.tile([0.0, 1 / 64], (3, 1))
    lam = lambdas(dpdi, dpdj, 256, 128)
    expect("orthographic lambda = log2(max(W, H) / N)", np.allclose(lam, 2.0), str(lam[0]))
    for theta, phi, dist in ((30, 20, 1.5), (80, 200, 4.0)):
        _, _, inside, cdi, cdj, _ = perspective(theta, phi, dist, 45, 32)
        fdi, fdj = footprint_by_differences(theta, phi, dist, 45, 32)
        rel = max(np.abs(fdi[inside] - cdi[inside]).max() / np.abs(cdi[inside]).max(),
                  np.abs(fdj[inside] - cdj[inside]).max() / np.abs(cdj[inside]).max())
        expect(f"footprint closed form = differences (theta {theta})", rel < 1e-5,
               f"relative {rel:.2g}, {int((~inside).sum())} outside")
    # outside pixels from geometry: row j's rays leave the eye at atan(a y_j) above the optical
    # axis (toward the horizon), so V.z = cos(theta + atan(a y)) shrunk by the column's tilt
    theta, fov, n = 80.0, 45.0, 32
    _, vv, inside, _, _, _ = perspective(theta, 0.0, 2.0, fov, n)
    a = math.tan(math.radians(fov) / 2)
    predicted = np.zeros(n * n, bool)
    for j in range(n):
        ay = a * (2 * (j + 0.5) / n - 1)
        for i in range(n):
            ax = a * (2 * (i + 0.5) / n - 1)
            tilt = math.sqrt(1 + ax * ax / (1 + ay * ay))
            vz = math.cos(math.radians(theta) + math.atan(ay)) / tilt
            predicted[j * n + i] = vz <= COS_89
    top = predicted.reshape(n, n).any(1)
    expect("outside pixels from the rays' angles (the top rows)",
           np.array_equal(predicted, ~inside) and top[-1] and not top[0],
           f"{int(predicted.sum())} predicted, {int((~inside).sum())} outside")
    # the exact hits against a fine march
    field = make_field(40, 30, 9).astype(float) / 65535
    s, b = 0.05, 0.75
    for theta in (30.0, 75.0, 88.0):
        m = 400
        pts = rng.random((m, 2))
        ph = np.radians(rng.uniform(0, 360, m))
        t = math.radians(theta)
        vv = np.stack([math.sin(t) * np.cos(ph), math.sin(t) * np.sin(ph),
                       np.full(m, math.cos(t))], 1)
        uv = exact_hits(field, s, b, pts, vv)
        z_top = s * (1 - b)
        start = pts + vv[:, :2] * (z_top / vv[:, 2:3])
        vxy = vv[:, :2]
        tau_exact = np.einsum("ij,ij->i", start - uv, vxy) / np.einsum("ij,ij->i", vxy, vxy)
        q = start - tau_exact[:, None] * vv[:, :2]
        g_at = z_top - tau_exact * vv[:, 2] - s * (bilinear(field, q[:, 0], q[:, 1]) - b)
        steps = 4000
        tau_march = np.full(m, np.nan)
        for k in range(steps + 1):
            tau = k / steps * s / vv[:, 2]
            qq = start - tau[:, None] * vv[:, :2]
            g = z_top - tau * vv[:, 2] - s * (bilinear(field, qq[:, 0], qq[:, 1]) - b)
            tau_march = np.where(np.isnan(tau_march) & (g <= 0), tau, tau_march)
        step = s / vv[:, 2] / steps
        later = (tau_exact > tau_march + 1e-12).sum()  # the exact root never after the march's
        near = (np.abs(tau_exact - tau_march) <= step * 1.0001).mean()
        expect(f"exact hits vs a fine march (theta {theta})",
               later == 0 and np.abs(g_at).max() < 1e-12 and near > 0.99,
               f"|g| at the hit <= {np.abs(g_at).max():.2g}, {near:.1%} within one march step, "
               f"{later} after it")
    # methods: a flat field makes parallax and pom exact; s -> 0 returns P
    flat = np.full((16, 16), 0.4)
    lv = build_levels(flat)
    pts, vv, inside, _, _, _ = perspective(60, 30, 2.0, 45, 16)
    pts, vv = pts[inside], vv[inside]
    truth = exact_hits(flat, 0.05, 1.0, pts, vv)
    for name in ("parallax", "pom"):
        uv, _ = run_method(name, {"layers": "32"}, lv, 0.05, 1.0, pts, vv, None, "selftest")
        err = np.abs(wrap(uv - truth)).max() * 16
        expect(f"{name} exact on a flat field", err < 1e-9, f"max error {err:.2g} texel")
    for name in METHODS:
        uv, _ = run_method(name, {"layers": "16"}, lv, 1e-9, 0.5, pts, vv, None, "selftest")
        err = np.abs(uv - pts).max()
        expect(f"{name} returns P as s -> 0", err < 1e-8, f"max offset {err:.2g}")
    print("PASS" if all(results) else f"FAIL: {results.count(False)} check(s)")
    return 0 if all(results) else 1


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="command", required=True)
    fp = sub.add_parser("field", help="write the check's own random height field (16-bit PNG)")
    fp.add_argument("out")
    fp.add_argument("--width", type=int, default=90)
    fp.add_argument("--height", type=int, default=70)
    fp.add_argument("--seed", type=int, default=20261202)
    sub.add_parser("selftest", help="the check's own pieces against closed forms and a march")
    cp = sub.add_parser("check", help="recompute a run's rows and compare")
    cp.add_argument("run_dir")
    cp.add_argument("--root", default=".", help="the folder pxh ran in: run.json's input "
                    "paths are relative to it (default: the current folder)")
    cp.add_argument("--tolerance", type=float, default=0.02)
    cp.add_argument("--require-backend", action="append", default=[])
    cp.add_argument("--quiet", action="store_true")
    args = ap.parse_args()
    try:
        if args.command == "field":
            png_write_gray16(args.out, make_field(args.width, args.height, args.seed))
            back = png_read_gray(args.out)
            print(f"{args.out}: {back.shape[1]} x {back.shape[0]}, heights "
                  f"{back.min():.4f} .. {back.max():.4f}")
            return 0
        if args.command == "selftest":
            return selftest(args)
        return check(args)
    except BadInput as e:
        print(f"independent_check: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())

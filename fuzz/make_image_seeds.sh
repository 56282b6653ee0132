#!/usr/bin/env bash
# Writes the seed corpus of the image fuzz target, fuzz/corpus/image/ (committed; rerun only to
# change it). Each seed is one byte, the requested channel, then the file (see
# fuzz/image_fuzz.cpp). Valid tiny height maps in every format pxh reads (PNG 8/16-bit, gray
# and RGB, PGM binary and ASCII, PFM, OpenEXR float and half, TIFF, JPEG), plus invalid ones:
# truncated, NaN, out of range, oversized header, zero width, Radiance HDR (not accepted), not
# an image. Needs oiiotool and python3.
set -euo pipefail
cd "$(dirname "$0")"
out=corpus/image
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"

# seed NAME CHANNEL FILE: the channel byte (decimal) followed by FILE's bytes.
seed() { { printf "\\$(printf '%03o' "$2")"; cat "$3"; } > "$out/$1"; }

oiiotool --pattern fill:top=0:bottom=1 4x3 1 -d uint8 -o "$tmp/gray8.png"
oiiotool --pattern fill:left=0:right=1 2x2 1 -d uint16 -o "$tmp/gray16.png"
oiiotool --pattern checker:width=1:height=1 3x3 3 -d uint8 -o "$tmp/rgb.png"
oiiotool --pattern fill:top=0.25:bottom=0.75 4x4 1 -d float -o "$tmp/float.exr"
oiiotool --pattern fill:top=0:bottom=1 4x4 1 -d half -o "$tmp/half.exr"
oiiotool --pattern fill:top=0:bottom=1 4x4 1 -d uint16 -o "$tmp/gray16.tif"
oiiotool --pattern fill:top=0.1:bottom=0.9 3x3 3 -d float -o "$tmp/rgb.hdr"
oiiotool --pattern fill:top=0:bottom=1 8x8 1 -d uint8 -o "$tmp/gray.jpg"
/usr/bin/python3 - "$tmp" <<'PY'
import struct, sys
d = sys.argv[1]
def w(name, data):
    open(f"{d}/{name}", "wb").write(data)
w("p5.pgm", b"P5\n3 2\n255\n" + bytes([0, 64, 128, 192, 255, 7]))
w("p2_16.pgm", b"P2\n# 16-bit ascii\n2 2\n65535\n0 65535\n32768 1\n")
pfm = lambda vals, w_, h_: b"Pf\n%d %d\n-1.0\n" % (w_, h_) + struct.pack("<%df" % len(vals), *vals)
w("gray.pfm", pfm([0.0, 0.5, 1.0, 0.25, 0.75, 0.125], 3, 2))
w("nan.pfm", pfm([0.0, float("nan"), 1.0, 0.25], 2, 2))
w("range.pfm", pfm([0.0, 2.0, 1.0, -0.5], 2, 2))
w("huge.pgm", b"P5\n100000 100000\n255\n" + bytes(16))
w("zero.pgm", b"P5\n0 5\n255\n")
w("text.txt", b"this is not an image\n")
PY
head -c 40 "$tmp/gray8.png" > "$tmp/truncated.png"

seed png_gray8 0 "$tmp/gray8.png"
seed png_gray16 0 "$tmp/gray16.png"
seed png_rgb_channel1 1 "$tmp/rgb.png"
seed png_rgb_channel3 3 "$tmp/rgb.png"
seed png_truncated 0 "$tmp/truncated.png"
seed pgm_p5 0 "$tmp/p5.pgm"
seed pgm_p2_16bit 0 "$tmp/p2_16.pgm"
seed pgm_huge_header 0 "$tmp/huge.pgm"
seed pgm_zero_width 0 "$tmp/zero.pgm"
seed pfm_gray 0 "$tmp/gray.pfm"
seed pfm_nan 0 "$tmp/nan.pfm"
seed pfm_out_of_range 0 "$tmp/range.pfm"
seed exr_float 0 "$tmp/float.exr"
seed exr_half 0 "$tmp/half.exr"
seed tif_gray16 0 "$tmp/gray16.tif"
seed jpg_gray 0 "$tmp/gray.jpg"
seed hdr_rgb 0 "$tmp/rgb.hdr"
seed text 0 "$tmp/text.txt"
ls -l "$out"

// The image pairs of tests/metrics/flip_test.cpp and of the FLIP benchmark (scripts/
// flip_bench.sh): 8-bit sRGB, row-major, 3 bytes a pixel, made here from integers only so that
// anyone can make the same pair (or write it as a PNG for the authors' FLIP tool) without pxh.
// Self-contained on purpose (the standard library only): scripts/flip_bench.sh compiles it
// into its driver of the authors' implementation.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace flip_pairs {

struct Pair {
    std::string name;
    int w = 0, h = 0;
    std::vector<uint8_t> reference, test;
};

inline void put(std::vector<uint8_t>& im, int w, int x, int y, int r, int g, int b) {
    const size_t i = 3 * (size_t(y) * size_t(w) + size_t(x));
    im[i] = uint8_t(r), im[i + 1] = uint8_t(g), im[i + 2] = uint8_t(b);
}

// A vertical edge, dark grey to light grey at x = 32; the test's edge at x = 34, its light
// side warmer (220, 200, 180).
inline Pair edge() {
    Pair p{"edge", 64, 48, {}, {}};
    p.reference.assign(size_t(3 * p.w * p.h), 0);
    p.test = p.reference;
    for (int y = 0; y < p.h; ++y)
        for (int x = 0; x < p.w; ++x) {
            if (x < 32) put(p.reference, p.w, x, y, 30, 30, 30);
            else put(p.reference, p.w, x, y, 220, 220, 220);
            if (x < 34) put(p.test, p.w, x, y, 30, 30, 30);
            else put(p.test, p.w, x, y, 220, 200, 180);
        }
    return p;
}

// Flat grey 128; the test has one white pixel at (20, 15).
inline Pair point() {
    Pair p{"point", 40, 32, std::vector<uint8_t>(size_t(3 * 40 * 32), 128), {}};
    p.test = p.reference;
    put(p.test, p.w, 20, 15, 255, 255, 255);
    return p;
}

// A horizontal grey ramp 0..255 (x * 255 / (w - 1), rounded down); the test's ramp banded to
// 8 levels (value / 32 * 32 + 16).
inline Pair ramp() {
    Pair p{"ramp", 80, 24, {}, {}};
    p.reference.assign(size_t(3 * p.w * p.h), 0);
    p.test = p.reference;
    for (int y = 0; y < p.h; ++y)
        for (int x = 0; x < p.w; ++x) {
            const int v = x * 255 / (p.w - 1), b = v / 32 * 32 + 16;
            put(p.reference, p.w, x, y, v, v, v);
            put(p.test, p.w, x, y, b, b, b);
        }
    return p;
}

// A checkerboard of 4-pixel cells, red (200, 40, 40) and blue (40, 40, 200); the test the same
// board shifted one pixel to the right (its cell boundaries at x = 4k + 1). Its last row and
// column lie in other cells than the ones before them, so the filters' edge clamping shows.
inline Pair checker_shift() {
    Pair p{"checker", 45, 37, {}, {}};
    p.reference.assign(size_t(3 * p.w * p.h), 0);
    p.test = p.reference;
    for (int y = 0; y < p.h; ++y)
        for (int x = 0; x < p.w; ++x) {
            const bool a = ((x / 4) + (y / 4)) % 2 == 0, b = (((x + 3) / 4) + 1 + (y / 4)) % 2 == 0;
            if (a) put(p.reference, p.w, x, y, 200, 40, 40);
            else put(p.reference, p.w, x, y, 40, 40, 200);
            if (b) put(p.test, p.w, x, y, 200, 40, 40);
            else put(p.test, p.w, x, y, 40, 40, 200);
        }
    return p;
}

// The benchmark's 512 x 512 pair: a smooth colour field with a fine checker, and the same
// field shifted half a cell with a slightly different tint (the kind of difference a parallax
// method's picture has from the truth's).
inline Pair bench512() {
    Pair p{"bench512", 512, 512, {}, {}};
    p.reference.assign(size_t(3 * p.w * p.h), 0);
    p.test = p.reference;
    for (int y = 0; y < p.h; ++y)
        for (int x = 0; x < p.w; ++x) {
            const int c0 = ((x / 8) + (y / 8)) % 2, c1 = (((x + 4) / 8) + (y / 8)) % 2;
            put(p.reference, p.w, x, y, 60 + 120 * c0 + x / 8, 50 + y / 4, 200 - 100 * c0);
            put(p.test, p.w, x, y, 60 + 120 * c1 + x / 8, 52 + y / 4, 198 - 100 * c1);
        }
    return p;
}

}  // namespace flip_pairs

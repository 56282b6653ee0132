#include "harness/scene/texture_levels.h"

#include <algorithm>
#include <string>

namespace pxh {

int last_level(int width, int height) {
    int n = std::max(width, height), q = 0;
    while (n > 1) {
        n >>= 1;
        ++q;
    }
    return q;
}

int level_size(int n0, int level) { return std::max(1, n0 >> level); }

AxisCover level_axis_cover(int n0, int n_level, int i) {
    // Units of 1 / n_level level-0 texel: the level texel is [i n0, (i + 1) n0), level-0
    // texel k is [k n_level, (k + 1) n_level).
    const long long lo = (long long)i * n0, hi = (long long)(i + 1) * n0, m = n_level;
    AxisCover c;
    c.first = int(lo / m);
    const long long last = (hi + m - 1) / m - 1;
    for (long long k = c.first; k <= last; ++k)
        c.overlap.push_back(std::min(hi, (k + 1) * m) - std::max(lo, k * m));
    return c;
}

namespace {

// One level from level 0, separably: rows first (W x H -> W_L x H), then columns. Each pass sums
// integer overlaps times heights in double and divides by the axis's total once.
HeightField area_level(const HeightField& f, int level) {
    const int W = f.width, H = f.height;
    const int WL = level_size(W, level), HL = level_size(H, level);
    std::vector<double> rows(size_t(WL) * H);
    for (int i = 0; i < WL; ++i) {
        const AxisCover c = level_axis_cover(W, WL, i);
        for (int y = 0; y < H; ++y) {
            const float* src = f.texels.data() + size_t(y) * W + c.first;
            double sum = 0;
            for (size_t k = 0; k < c.overlap.size(); ++k) sum += double(c.overlap[k]) * src[k];
            rows[size_t(y) * WL + i] = sum / W;
        }
    }
    HeightField out(WL, HL, f.name + " level " + std::to_string(level));
    for (int j = 0; j < HL; ++j) {
        const AxisCover c = level_axis_cover(H, HL, j);
        for (int i = 0; i < WL; ++i) {
            double sum = 0;
            for (size_t k = 0; k < c.overlap.size(); ++k)
                sum += double(c.overlap[k]) * rows[size_t(c.first + int(k)) * WL + i];
            out.at(i, j) = float(sum / H);
        }
    }
    return out;
}

}  // namespace

TextureLevels build_texture_levels(const HeightField& field) {
    TextureLevels tl;
    const int q = last_level(field.width, field.height);
    tl.levels.reserve(size_t(q) + 1);
    tl.levels.push_back(field);
    tl.levels.back().filled.clear();
    for (int L = 1; L <= q; ++L) tl.levels.push_back(area_level(field, L));
    return tl;
}

}  // namespace pxh

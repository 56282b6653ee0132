// Texture levels of a height field and the fetch at a level of detail (docs/conventions.md
// section 10): the area-weighted box levels pxh builds itself, and GL's LINEAR_MIPMAP_LINEAR
// with LINEAR magnification over them, repeat wrapping, texel centres as in section 1.
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "harness/core/vec.h"
#include "harness/scene/heightfield.h"

namespace pxh {

// q = floor(log2(max(W, H))): the last level (1 x 1). 0 for a 1 x 1 field.
int last_level(int width, int height);

// Texels along one axis of level L: max(1, floor(n0 / 2^L)).
int level_size(int n0, int level);

// Which level-0 texels one level texel covers along one axis, and how much of each. Texel i of a
// level n_level texels wide covers [i n0 / n_level, (i + 1) n0 / n_level) in level-0 texel
// units. In units of 1 / n_level of a level-0 texel both ends are integers, so the overlaps are
// exact integers: level-0 texel first + k is covered over overlap[k] of those units, and the
// overlaps sum to n0 (the level texel's width in the same units). The weight of level-0 texel
// first + k is overlap[k] / n0.
struct AxisCover {
    int first = 0;
    std::vector<long long> overlap;
};
AxisCover level_axis_cover(int n0, int n_level, int i);

// Levels 0 ... q of a height field: levels[0] is the field's own texels, levels[L] for L >= 1
// the area-weighted mean of the level-0 texels under each texel (computed in double from level
// 0 directly, rounded once to float). For power-of-two sizes this is the plain 2^L x 2^L box.
struct TextureLevels {
    std::vector<HeightField> levels;
    int last() const { return int(levels.size()) - 1; }  // q
};
TextureLevels build_texture_levels(const HeightField& field);

// Bilinear height of level L at uv (the rule of HeightSampler, on that level's texels).
template <typename T>
T level_bilinear(const TextureLevels& tl, int level, Vec2<T> uv) {
    const HeightField& f = tl.levels[size_t(level)];
    return bilinear_texels(f.texels.data(), f.width, f.height, uv);
}

// GL's LINEAR_MIPMAP_LINEAR fetch with LINEAR magnification at level of detail lambda:
// lambda <= 0 (or NaN): level 0 bilinear; else with l = min(lambda, q), d1 = floor(l),
// tau = l - d1: b_d1 + (b_{d1+1} - b_d1) tau, or b_q alone when d1 = q.
template <typename T>
T level_fetch(const TextureLevels& tl, Vec2<T> uv, T lambda) {
    if (!(lambda > T(0))) return level_bilinear(tl, 0, uv);
    const T l = std::min(lambda, T(tl.last()));
    const T d1f = std::floor(l);
    const int d1 = int(d1f);
    if (d1 >= tl.last()) return level_bilinear(tl, tl.last(), uv);
    const T tau = l - d1f;
    const T b1 = level_bilinear(tl, d1, uv);
    const T b2 = level_bilinear(tl, d1 + 1, uv);
    return b1 + (b2 - b1) * tau;
}

}  // namespace pxh

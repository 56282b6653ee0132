// Height fields (docs/conventions.md section 1): W x H texels in [0,1], bilinear between texel
// centres, repeat wrapping, exactly what GL_LINEAR + GL_REPEAT computes.
#pragma once
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "harness/core/limits.h"  // kMaxImage*: the largest accepted image
#include "harness/core/vec.h"

namespace pxh {

struct HeightField {
    int width = 0, height = 0;
    std::vector<float> texels;    // row-major, row j = 0 is v near 0
    std::vector<uint8_t> filled;  // optional: 1 where a measured field's hole was filled
    std::string name;

    HeightField() = default;
    HeightField(int w, int h, std::string n = {});
    float at(int i, int j) const { return texels[size_t(j) * width + i]; }
    float& at(int i, int j) { return texels[size_t(j) * width + i]; }
    // Texel (i, j) with repeat wrapping for any integer i, j.
    float wrapped(int64_t i, int64_t j) const;
    // Throws InputError(where, ...) unless every texel is finite and in [0,1].
    void validate(const std::string& where) const;
    float min_value() const;
    float max_value() const;
};

inline int64_t wrap_index(int64_t i, int64_t n) {
    if (i >= 0 && i < n) return i;  // the common cases: no division
    if (i < 0 && i >= -n) return i + n;
    if (i >= n && i < 2 * n) return i - n;
    int64_t r = i % n;
    return r < 0 ? r + n : r;
}

inline float HeightField::wrapped(int64_t i, int64_t j) const {
    return at(int(wrap_index(i, width)), int(wrap_index(j, height)));
}

// Float coordinate -> texel index for the bilinear rule: clamped before converting (float indices
// exceed the integer range only for absurd offsets); a NaN coordinate gives texel 0 and the NaN
// propagates through the fraction.
template <typename T>
inline int64_t bilinear_index(T f) {
    if (!(f == f)) return 0;
    constexpr T lim = T(int64_t(1) << 52);
    return int64_t(f < -lim ? -lim : (f > lim ? lim : f));
}

// Bilinear height in precision T of a W x H texel grid (row-major) at uv, with repeat wrapping:
// docs/conventions.md section 1, the one rule every CPU height lookup uses (level 0 through
// HeightSampler, the texture levels through harness/scene/texture_levels.h).
template <typename T>
inline T bilinear_texels(const float* texels, int W, int H, Vec2<T> uv) {
    const T x = uv.x * T(W) - T(0.5), y = uv.y * T(H) - T(0.5);
    const T fx0 = std::floor(x), fy0 = std::floor(y);
    const T fx = x - fx0, fy = y - fy0;
    const int i0 = int(wrap_index(bilinear_index(fx0), W));
    const int j0 = int(wrap_index(bilinear_index(fy0), H));
    const int i1 = i0 + 1 == W ? 0 : i0 + 1, j1 = j0 + 1 == H ? 0 : j0 + 1;
    const float* row0 = texels + size_t(j0) * W;
    const float* row1 = texels + size_t(j1) * W;
    const T h00 = T(row0[i0]), h10 = T(row0[i1]), h01 = T(row1[i0]), h11 = T(row1[i1]);
    const T a = h00 + (h10 - h00) * fx;
    const T b = h01 + (h11 - h01) * fx;
    return a + (b - a) * fy;
}

struct TextureLevels;  // harness/scene/texture_levels.h
template <typename T>
T level_fetch(const TextureLevels& tl, Vec2<T> uv, T lambda);

// Bilinear height in precision T with a fetch counter (one fetch = one filtered lookup, as a
// shader's texture() call). The scene's s and b turn height into surface z = s (h - b). It
// knows the sample's level of detail lambda (lod(): what a shader's pxh_lod() returns; 0 when
// the view gave none), and given texture levels, every height is GL's trilinear fetch at that
// lambda instead (level_fetch, harness/scene/texture_levels.h: the `level` mode of
// docs/conventions.md section 10); a TU that passes levels includes texture_levels.h.
template <typename T>
class HeightSampler {
  public:
    HeightSampler(const HeightField& hf, T scale, T bias) : hf_(&hf), s_(scale), b_(bias) {}
    HeightSampler(const HeightField& hf, T scale, T bias, const TextureLevels* levels, T lambda)
        : hf_(&hf), s_(scale), b_(bias), levels_(levels), lambda_(lambda) {}

    T height(Vec2<T> uv) {
        ++fetches;
        if (levels_) return level_fetch(*levels_, uv, lambda_);
        return bilinear_texels(hf_->texels.data(), hf_->width, hf_->height, uv);
    }
    // Surface z = s (h - b) at uv.
    T z(Vec2<T> uv) { return s_ * (height(uv) - b_); }
    T scale() const { return s_; }
    T bias() const { return b_; }
    T lod() const { return lambda_; }
    const HeightField& field() const { return *hf_; }

    int fetches = 0;

  private:
    const HeightField* hf_;
    T s_, b_;
    const TextureLevels* levels_ = nullptr;
    T lambda_ = 0;
};

}  // namespace pxh

// Method resources: precomputed textures a method declares (a max-mip pyramid, a cone-ratio
// map, ...), built on the CPU once per height field (and per s, b when the resource says it
// depends on them), deterministic (the same bytes for any thread count), shared by every view
// of the field and by both backends, timed (precompute_ms) and sized (aux_bytes).
//
// A method lists them in MethodInfo::resources (describe()). Its C++ twin reads them through
// TextureSampler<T> (GLSL textureLod semantics for the declared format, filter and wrap, each
// fetch counted per texture); its shader declares `uniform sampler2D NAME;` for each and reads
// it with pxh_texture(NAME, uv, level) (methods/common.glsl: counted like pxh_height).
#pragma once
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <tuple>
#include <vector>

#include "harness/core/params.h"
#include "harness/core/vec.h"
#include "harness/scene/heightfield.h"

namespace pxh {

enum class TexelFormat { R32F, RGBA32F };  // 1 or 4 floats per texel
enum class TexFilter { Nearest, Linear };  // within a level (levels: nearest level)
enum class TexWrap { Repeat, Clamp };      // GL_REPEAT, GL_CLAMP_TO_EDGE

inline int channels(TexelFormat f) { return f == TexelFormat::R32F ? 1 : 4; }

// One level: width x height texels of channels() floats, row j = 0 first (as the height field:
// row j covers v in [j/H, (j+1)/H)).
struct ResourceLevel {
    int width = 0, height = 0;
    std::vector<float> texels;
};

// What a builder returns: level 0, then optionally a full or partial mip chain (level k is
// max(1, width >> k) x max(1, height >> k)).
struct ResourceImage {
    std::vector<ResourceLevel> levels;
};

struct ResourceSpec {
    std::string name;  // the shader's sampler2D uniform, "r_" prefix; unique within the method
    TexelFormat format = TexelFormat::R32F;
    TexFilter filter = TexFilter::Nearest;
    TexWrap wrap = TexWrap::Repeat;
    bool depends_on_scale_bias = false;  // built per (s, b) instead of once per field
    // Builds the texels on the CPU from the field (and s, b when it depends on them). Must be a
    // pure function of its inputs: the same bytes whatever the thread count.
    ResourceImage (*build)(const HeightField& hf, double scale, double bias) = nullptr;
    std::string help{};  // one line: what the texels hold
    // A resource that also depends on one integer parameter of its method (e.g. a slice count):
    // the parameter's name, the builder that takes its value (used instead of `build`), and the
    // value a build without the method's parameters uses (the parameter's default). Built once
    // per value (ResourceCache keys it with the value).
    std::string int_param{};
    ResourceImage (*build_with)(const HeightField& hf, double scale, double bias,
                                int value) = nullptr;
    int int_param_default = 0;
    // The value of int_param in `params` (nullptr: the default); 0 for a resource without one.
    int param_value(const ParamValues* params) const;
};

// A built resource: its declaration, its texels (checked against the declaration), the time
// the build took and its size as uploaded (every level, 4 bytes per channel).
struct BuiltResource {
    const ResourceSpec* spec = nullptr;
    std::shared_ptr<const ResourceImage> image;
    double build_ms = 0;
    size_t bytes = 0;
};

// A method's resources for one field at one (s, b), in declaration order.
struct MethodResources {
    std::vector<BuiltResource> items;
    double precompute_ms() const;  // sum of the build times (0 without resources)
    size_t aux_bytes() const;      // sum of the sizes (0 without resources)
};

// Builds one resource now: runs the builder, checks the levels (sizes, texel counts, finite
// values; std::logic_error naming the resource otherwise), times it. `params`: the method's
// parameters, for a resource with an int_param (nullptr: its default).
BuiltResource build_resource(const ResourceSpec& spec, const HeightField& hf, double scale,
                             double bias, const ParamValues* params = nullptr);

// One height field's resources, built on first use and shared afterwards (by every view and
// both backends). Thread-safe. Keyed by the method's resource name (and s, b for resources that
// depend on them), so keep one cache per field and drop it with the field.
class ResourceCache {
  public:
    explicit ResourceCache(const HeightField& hf) : hf_(&hf) {}
    // The resources `specs` declares at (s, b); `method` names the owner (keys and messages);
    // `params` its parameters, for resources with an int_param (nullptr: their defaults).
    MethodResources get(const std::string& method, const std::vector<ResourceSpec>& specs,
                        double scale, double bias, const ParamValues* params = nullptr);
    int builds() const;  // how many builds ran so far

  private:
    const HeightField* hf_;
    mutable std::mutex mutex_;
    std::map<std::tuple<std::string, std::string, double, double, int>, BuiltResource> built_;
    int builds_ = 0;
};

// Reads one resource with GLSL textureLod(sampler, uv, level) semantics for an integer level:
// level clamped to the levels present; nearest: texel floor(uv * size); linear: the bilinear
// blend of the four texels around uv * size - 0.5 (as HeightSampler); wrap per texel index.
// Channels not stored read as GL does (r32f: g = b = 0, a = 1). Counts its fetches.
template <typename T>
class TextureSampler {
  public:
    TextureSampler() = default;
    TextureSampler(const ResourceSpec& spec, const ResourceImage& image)
        : spec_(&spec), image_(&image) {}

    std::array<T, 4> fetch(Vec2<T> uv, int level = 0) {
        ++fetches;
        const int L = int(image_->levels.size());
        const ResourceLevel& lv =
            image_->levels[size_t(level < 0 ? 0 : (level >= L ? L - 1 : level))];
        const T x = uv.x * T(lv.width), y = uv.y * T(lv.height);
        if (spec_->filter == TexFilter::Nearest)
            return texel(lv, index(std::floor(x), lv.width), index(std::floor(y), lv.height));
        const T fx0 = std::floor(x - T(0.5)), fy0 = std::floor(y - T(0.5));
        const T fx = x - T(0.5) - fx0, fy = y - T(0.5) - fy0;
        const int i0 = index(fx0, lv.width), i1 = index(fx0 + T(1), lv.width);
        const int j0 = index(fy0, lv.height), j1 = index(fy0 + T(1), lv.height);
        const auto t00 = texel(lv, i0, j0), t10 = texel(lv, i1, j0);
        const auto t01 = texel(lv, i0, j1), t11 = texel(lv, i1, j1);
        std::array<T, 4> out;
        for (int c = 0; c < 4; ++c) {
            const T a = t00[c] + (t10[c] - t00[c]) * fx;
            const T b = t01[c] + (t11[c] - t01[c]) * fx;
            out[c] = a + (b - a) * fy;
        }
        return out;
    }
    T fetch_r(Vec2<T> uv, int level = 0) { return fetch(uv, level)[0]; }
    const ResourceSpec& spec() const { return *spec_; }

    int fetches = 0;

  private:
    int index(T f, int n) const {
        if (!(f == f)) return 0;  // NaN coordinate: any texel; the NaN propagates elsewhere
        constexpr T lim = T(int64_t(1) << 52);
        const int64_t i = int64_t(f < -lim ? -lim : (f > lim ? lim : f));
        if (spec_->wrap == TexWrap::Clamp) return int(i < 0 ? 0 : (i >= n ? n - 1 : i));
        const int64_t m = i % n;
        return int(m < 0 ? m + n : m);
    }
    std::array<T, 4> texel(const ResourceLevel& lv, int i, int j) const {
        const int ch = channels(spec_->format);
        const float* t = lv.texels.data() + (size_t(j) * size_t(lv.width) + size_t(i)) * size_t(ch);
        if (ch == 1) return {T(t[0]), T(0), T(0), T(1)};
        return {T(t[0]), T(t[1]), T(t[2]), T(t[3])};
    }
    const ResourceSpec* spec_ = nullptr;
    const ResourceImage* image_ = nullptr;
};

// The samplers of one method's resources, in declaration order (index = position in
// MethodInfo::resources).
template <typename T>
struct ResourceSamplers {
    std::vector<TextureSampler<T>> tex;
    TextureSampler<T>& operator[](size_t k) { return tex[k]; }
    int fetches() const {
        int n = 0;
        for (const auto& t : tex) n += t.fetches;
        return n;
    }
};

// The whole mip chain of `base` (level 0 as given) where each texel of level k + 1 combines the
// 2 x 2 texels of level k it covers (and the extra row/column when level k's size is odd) with
// `combine` (e.g. max). Single channel.
ResourceImage reduce_pyramid(ResourceLevel base, float (*combine)(float, float));

}  // namespace pxh

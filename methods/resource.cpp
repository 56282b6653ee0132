#include "methods/resource.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>

namespace pxh {

double MethodResources::precompute_ms() const {
    double ms = 0;
    for (const auto& r : items) ms += r.build_ms;
    return ms;
}

size_t MethodResources::aux_bytes() const {
    size_t b = 0;
    for (const auto& r : items) b += r.bytes;
    return b;
}

int ResourceSpec::param_value(const ParamValues* params) const {
    if (int_param.empty()) return 0;
    return params && params->has(int_param) ? params->get_int(int_param) : int_param_default;
}

BuiltResource build_resource(const ResourceSpec& spec, const HeightField& hf, double scale,
                             double bias, const ParamValues* params) {
    if (!(spec.build_with ? !spec.int_param.empty() : spec.build && spec.int_param.empty()))
        throw std::logic_error("resource '" + spec.name +
                               "' has no builder (or int_param and build_with disagree)");
    const auto t0 = std::chrono::steady_clock::now();
    auto image = std::make_shared<ResourceImage>(
        spec.build_with ? spec.build_with(hf, scale, bias, spec.param_value(params))
                        : spec.build(hf, scale, bias));
    const auto t1 = std::chrono::steady_clock::now();
    auto fail = [&](const std::string& why) {
        throw std::logic_error("resource '" + spec.name + "': " + why);
    };
    if (image->levels.empty()) fail("no level built");
    const ResourceLevel& base = image->levels[0];
    if (base.width < 1 || base.height < 1) fail("level 0 is empty");
    size_t bytes = 0;
    const size_t ch = size_t(channels(spec.format));
    for (size_t k = 0; k < image->levels.size(); ++k) {
        const ResourceLevel& lv = image->levels[k];
        const int w = std::max(1, base.width >> k), h = std::max(1, base.height >> k);
        if (k > 0 && (lv.width != w || lv.height != h))
            fail("level " + std::to_string(k) + " is " + std::to_string(lv.width) + " x " +
                 std::to_string(lv.height) + ", a mip chain needs " + std::to_string(w) + " x " +
                 std::to_string(h));
        if (k > 0 && base.width >> k == 0 && base.height >> k == 0)
            fail("more levels than the mip chain has");
        if (lv.texels.size() != size_t(lv.width) * size_t(lv.height) * ch)
            fail("level " + std::to_string(k) + " holds " + std::to_string(lv.texels.size()) +
                 " floats, not width x height x " + std::to_string(ch));
        for (float v : lv.texels)
            if (!std::isfinite(v)) fail("level " + std::to_string(k) + " has a non-finite texel");
        bytes += lv.texels.size() * sizeof(float);
    }
    BuiltResource out;
    out.spec = &spec;
    out.image = std::move(image);
    out.build_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
    out.bytes = bytes;
    return out;
}

MethodResources ResourceCache::get(const std::string& method,
                                   const std::vector<ResourceSpec>& specs, double scale,
                                   double bias, const ParamValues* params) {
    MethodResources out;
    std::lock_guard<std::mutex> lock(mutex_);
    for (const ResourceSpec& spec : specs) {
        const bool per_view = spec.depends_on_scale_bias;
        const auto key = std::make_tuple(method, spec.name, per_view ? scale : 0.0,
                                         per_view ? bias : 0.0, spec.param_value(params));
        auto it = built_.find(key);
        if (it == built_.end()) {
            it = built_.emplace(key, build_resource(spec, *hf_, scale, bias, params)).first;
            ++builds_;
        }
        out.items.push_back(it->second);
        out.items.back().spec = &spec;
    }
    return out;
}

int ResourceCache::builds() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return builds_;
}

ResourceImage reduce_pyramid(ResourceLevel base, float (*combine)(float, float)) {
    ResourceImage img;
    img.levels.push_back(std::move(base));
    while (img.levels.back().width > 1 || img.levels.back().height > 1) {
        const ResourceLevel& src = img.levels.back();
        ResourceLevel dst;
        dst.width = std::max(1, src.width / 2);
        dst.height = std::max(1, src.height / 2);
        dst.texels.resize(size_t(dst.width) * size_t(dst.height));
        // Rows in parallel; each texel depends on the level below only (thread-count free).
        tbb::parallel_for(0, dst.height, [&](int j) {
            for (int i = 0; i < dst.width; ++i) {
                // Source texels covered: 2i, 2i + 1 (and 2i + 2 for the last column of an odd
                // width); the same for rows. A 1-texel side maps onto itself.
                const int i0 = 2 * i, i1 = std::min(src.width - 1,
                                                    i + 1 == dst.width ? src.width - 1 : 2 * i + 1);
                const int j0 = 2 * j,
                          j1 = std::min(src.height - 1,
                                        j + 1 == dst.height ? src.height - 1 : 2 * j + 1);
                float v = src.texels[size_t(j0) * size_t(src.width) + size_t(i0)];
                for (int jj = j0; jj <= j1; ++jj)
                    for (int ii = i0; ii <= i1; ++ii)
                        v = combine(v, src.texels[size_t(jj) * size_t(src.width) + size_t(ii)]);
                dst.texels[size_t(j) * size_t(dst.width) + size_t(i)] = v;
            }
        });
        img.levels.push_back(std::move(dst));
    }
    return img;
}

}  // namespace pxh

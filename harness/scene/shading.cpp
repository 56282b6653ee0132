#include "harness/scene/shading.h"

#include <algorithm>
#include <cmath>

namespace pxh {

float srgb_encode(float c) {
    c = std::clamp(c, 0.0f, 1.0f);
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

float srgb_decode(float c) {
    c = std::clamp(c, 0.0f, 1.0f);
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

Vec3d light_direction(double elevation_deg, double azimuth_deg) {
    const double e = elevation_deg * M_PI / 180, a = azimuth_deg * M_PI / 180;
    return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

AlbedoLevels build_albedo_levels(const RgbImage& albedo) {
    AlbedoLevels out;
    out.width = albedo.width;
    out.height = albedo.height;
    for (size_t c = 0; c < 3; ++c) {
        HeightField f(albedo.width, albedo.height);
        for (size_t k = 0; k < f.texels.size(); ++k) f.texels[k] = albedo.rgb[3 * k + c];
        out.channel[c] = build_texture_levels(f);
    }
    return out;
}

namespace {

// The central-difference gradient on one level (per tile).
Vec2d level_gradient(const TextureLevels& tl, int level, Vec2d uv) {
    const HeightField& f = tl.levels[size_t(level)];
    const double du = 1.0 / f.width, dv = 1.0 / f.height;
    const double hu1 = level_bilinear(tl, level, Vec2d{uv.x + du, uv.y});
    const double hu0 = level_bilinear(tl, level, Vec2d{uv.x - du, uv.y});
    const double hv1 = level_bilinear(tl, level, Vec2d{uv.x, uv.y + dv});
    const double hv0 = level_bilinear(tl, level, Vec2d{uv.x, uv.y - dv});
    return {(hu1 - hu0) / (2 * du), (hv1 - hv0) / (2 * dv)};
}

}  // namespace

Vec2d height_gradient(const TextureLevels& tl, Vec2d uv, double lambda) {
    if (!(lambda > 0)) return level_gradient(tl, 0, uv);
    const double l = std::min(lambda, double(tl.last()));
    const double d1f = std::floor(l);
    const int d1 = int(d1f);
    if (d1 >= tl.last()) return level_gradient(tl, tl.last(), uv);
    const double tau = l - d1f;
    const Vec2d g1 = level_gradient(tl, d1, uv), g2 = level_gradient(tl, d1 + 1, uv);
    return {g1.x + (g2.x - g1.x) * tau, g1.y + (g2.y - g1.y) * tau};
}

std::array<float, 3> shade_linear(const Material& m, Vec2d uv, double lambda) {
    const Vec2d g = height_gradient(*m.heights, uv, lambda);
    const double nx = -m.scale * g.x, ny = -m.scale * g.y;
    const double len = std::sqrt(nx * nx + ny * ny + 1);
    const double ndotl = (nx * m.light.x + ny * m.light.y + m.light.z) / len;
    const double light = kShadeAmbient + kShadeDiffuse * std::max(0.0, ndotl);
    // NaN lambda (no footprint) reads level 0, as level_fetch does.
    const double la = std::isfinite(lambda) ? lambda + m.albedo_lod : m.albedo_lod;
    std::array<float, 3> c{};
    for (size_t k = 0; k < 3; ++k) c[k] = float(level_fetch(m.albedo->channel[k], uv, la) * light);
    return c;
}

std::vector<float> shaded_image(const Material& m, const std::vector<Vec2d>& uv,
                                const std::vector<double>& lambda,
                                const std::vector<uint8_t>& covered) {
    std::vector<float> out(uv.size() * 3, kShadeBackground);
    for (size_t k = 0; k < uv.size(); ++k) {
        if (k < covered.size() && !covered[k]) continue;
        if (!std::isfinite(uv[k].x) || !std::isfinite(uv[k].y)) continue;
        const std::array<float, 3> c = shade_linear(m, uv[k], k < lambda.size() ? lambda[k] : 0);
        for (size_t i = 0; i < 3; ++i) out[3 * k + i] = srgb_encode(c[i]);
    }
    return out;
}

void quantize_8bit(std::vector<float>& rgb) {
    for (float& v : rgb) v = std::round(std::clamp(v, 0.0f, 1.0f) * 255.0f) / 255.0f;
}

}  // namespace pxh

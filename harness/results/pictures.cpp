#include "harness/results/pictures.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "harness/results/image_file.h"

namespace pxh {
namespace {

constexpr int kCells = 8;   // cells per tile side
constexpr int kGlyph = 11;  // a cell is 11 x 11 font pixels: two 3 x 5 digits, centred

// Digits 0-9, 3 x 5, one row of 3 bits per entry (most significant = left).
constexpr unsigned char kFont[10][5] = {
    {7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7}, {5, 5, 7, 1, 1},
    {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 1, 1, 1}, {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7}};

// Paul Tol's "muted" colours without black, one per cell column.
constexpr float kTint[kCells][3] = {{0.200f, 0.133f, 0.533f}, {0.533f, 0.800f, 0.933f},
                                    {0.267f, 0.667f, 0.600f}, {0.067f, 0.467f, 0.200f},
                                    {0.600f, 0.600f, 0.200f}, {0.867f, 0.800f, 0.467f},
                                    {0.800f, 0.400f, 0.467f}, {0.667f, 0.267f, 0.600f}};

// Whether font pixel (gx, gy) of a cell is ink for the cell's number.
bool ink(int number, int gx, int gy) {
    const int row = gy - 3;  // glyph rows 3..7
    if (row < 0 || row > 4) return false;
    int digit = -1, col = 0;
    if (gx >= 2 && gx <= 4) digit = number / 10, col = gx - 2;
    if (gx >= 6 && gx <= 8) digit = number % 10, col = gx - 6;
    return digit >= 0 && ((kFont[digit][row] >> (2 - col)) & 1);
}

}  // namespace

void albedo(Vec2d uv, float rgb[3]) {
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) {
        rgb[0] = rgb[2] = 1;
        rgb[1] = 0;
        return;
    }
    const double u = (uv.x - std::floor(uv.x)) * kCells, v = (uv.y - std::floor(uv.y)) * kCells;
    const int cx = std::min(int(u), kCells - 1), cy = std::min(int(v), kCells - 1);
    const double fx = u - cx, fy = v - cy;
    const bool light = (cx + cy) % 2 == 0;
    float c[3];
    for (int k = 0; k < 3; ++k)
        c[k] = light ? kTint[cx][k] + (1 - kTint[cx][k]) * 0.55f : kTint[cx][k] * 0.8f;
    const float y = 0.299f * c[0] + 0.587f * c[1] + 0.114f * c[2];
    const bool border = fx < 0.04 || fx > 0.96 || fy < 0.04 || fy > 0.96;
    const int gx = std::min(int(fx * kGlyph), kGlyph - 1),
              gy = std::min(int(fy * kGlyph), kGlyph - 1);
    const float paint = border ? 0.1f : ink(cy * kCells + cx, gx, gy) ? (y > 0.5f ? 0 : 1) : -1;
    for (int k = 0; k < 3; ++k) rgb[k] = paint >= 0 ? paint : c[k];
}

RgbImage checker_albedo(int size) {
    RgbImage img{size, size, std::vector<float>(size_t(size) * size_t(size) * 3)};
    for (int j = 0; j < size; ++j)
        for (int i = 0; i < size; ++i)
            albedo({(i + 0.5) / size, (j + 0.5) / size}, &img.rgb[(size_t(j) * size + i) * 3]);
    return img;
}

RgbImage read_albedo_image(const std::string& path) {
    ImagePixels in;
    std::string why;
    if (!read_image_pixels(path, in, why)) {
        if (why == "holds no pixels" || why.rfind("is larger than", 0) == 0)
            throw std::runtime_error(why);
        throw std::runtime_error("cannot be read as an image (" + why + ")");
    }
    const ImageFileInfo& spec = in.info;
    const bool encoded = !spec.floating;
    RgbImage img{spec.width, spec.height, std::vector<float>(size_t(spec.width) * spec.height * 3)};
    for (size_t k = 0; k < size_t(spec.width) * size_t(spec.height); ++k)
        for (size_t c = 0; c < 3; ++c) {
            const int from = spec.channels >= 3 ? int(c) : 0;
            const float raw = in.px[k * size_t(spec.channels) + size_t(from)];
            const float v = std::isfinite(raw) ? std::clamp(raw, 0.0f, 1.0f) : 0.0f;
            img.rgb[3 * k + c] = encoded ? srgb_decode(v) : v;
        }
    return img;
}

std::vector<float> picture(const std::vector<Vec2d>& uv, int n,
                           const std::vector<uint8_t>& inside) {
    std::vector<float> out(size_t(n) * size_t(n) * 3);
    for (size_t k = 0; k < uv.size() && k < size_t(n) * size_t(n); ++k) {
        if (k < inside.size() && !inside[k]) {
            out[3 * k] = out[3 * k + 1] = out[3 * k + 2] = 0.5f;
            continue;
        }
        albedo(uv[k], &out[3 * k]);
    }
    return out;
}

std::vector<Vec2d> uv_from_errors(const std::vector<Vec2d>& truth_uv,
                                  const std::vector<Vec2d>& errors, int width, int height) {
    std::vector<Vec2d> uv(truth_uv.size());
    for (size_t k = 0; k < uv.size(); ++k)
        uv[k] = {truth_uv[k].x + errors[k].x / width, truth_uv[k].y + errors[k].y / height};
    return uv;
}

void paint_plane(std::vector<float>& rgb, const std::vector<uint8_t>& shows, uint8_t bit) {
    for (size_t k = 0; k < shows.size() && 3 * k + 2 < rgb.size(); ++k)
        if (shows[k] & bit)
            for (size_t c = 0; c < 3; ++c) rgb[3 * k + c] = kPlaneRgb[c];
}

std::vector<float> difference(const std::vector<float>& a, const std::vector<float>& b) {
    std::vector<float> d(a.size());
    for (size_t i = 0; i < a.size(); ++i) d[i] = std::fabs(a[i] - b[i]);
    return d;
}

void write_picture(const std::vector<float>& rgb, int n, const std::string& path, bool as_seen) {
    std::vector<float> img(size_t(n) * size_t(n) * 3);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const size_t to = (size_t(as_seen ? n - 1 - j : j) * size_t(n) + size_t(i)) * 3;
            for (int c = 0; c < 3; ++c)
                img[to + size_t(c)] =
                    std::clamp(rgb[(size_t(j) * n + size_t(i)) * 3 + size_t(c)], 0.0f, 1.0f);
        }
    write_new_image(img, n, n, 3, "uint8", path);
}

}  // namespace pxh

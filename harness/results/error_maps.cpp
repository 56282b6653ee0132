#include "harness/results/error_maps.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "harness/core/params.h"
#include "harness/core/sha256.h"
#include "harness/metrics/columns.h"
#include "harness/results/image_file.h"
#include "harness/scene/view.h"

namespace pxh {
namespace {

// A perceptual ramp (samples of matplotlib's viridis).
constexpr float kRamp[9][3] = {
    {0.267f, 0.005f, 0.329f}, {0.283f, 0.141f, 0.458f}, {0.254f, 0.265f, 0.530f},
    {0.207f, 0.372f, 0.553f}, {0.164f, 0.471f, 0.558f}, {0.128f, 0.567f, 0.551f},
    {0.135f, 0.659f, 0.518f}, {0.478f, 0.821f, 0.318f}, {0.993f, 0.906f, 0.144f}};

void ramp(double t, float rgb[3]) {
    t = std::clamp(t, 0.0, 1.0) * 8;
    const int i = std::min(int(t), 7);
    const float f = float(t - i);
    for (int c = 0; c < 3; ++c) rgb[c] = kRamp[i][c] + (kRamp[i + 1][c] - kRamp[i][c]) * f;
}

const char* kFont = "DejaVuSans";

// An 8-bit RGB picture being drawn (floats 0..1, encoded as 8 bits when written).
struct Canvas {
    int width, height;
    std::vector<float> px;
    Canvas(int w, int h) : width(w), height(h), px(size_t(w) * size_t(h) * 3, 1.0f) {}
    // [x0, x1) x [y0, y1), clipped
    void fill(const float rgb[3], int x0, int x1, int y0, int y1) {
        for (int y = std::max(y0, 0); y < std::min(y1, height); ++y)
            for (int x = std::max(x0, 0); x < std::min(x1, width); ++x)
                for (int c = 0; c < 3; ++c) px[(size_t(y) * width + size_t(x)) * 3 + c] = rgb[c];
    }
    void text(int x, int y, const std::string& s, int size, const float rgb[3]) {
        std::string why;
        if (!image_codec().render_text(px, width, height, x, y, s, size, kFont, rgb, why))
            throw std::runtime_error("error map: cannot draw text '" + s + "': " + why);
    }
};

}  // namespace

void error_colour(double e, float rgb[3]) {
    if (!std::isfinite(e)) {
        rgb[0] = 1;
        rgb[1] = 0;
        rgb[2] = 1;
        return;
    }
    ramp(e <= 0 ? 0.0 : (std::log2(e) + 4) / 8, rgb);
}

ErrorMapBox error_map_box(int n) {
    const int k = std::max(1, (384 + n - 1) / n), side = n * k;
    const int width = std::max(side, 420), top = 28;
    return {(width - side) / 2, top, side};
}

std::string write_error_map(const std::vector<Vec2d>& errors, int n, const std::string& dir,
                            const std::string& stem, const std::string& title,
                            const std::vector<uint8_t>& inside, bool as_seen) {
    namespace fs = std::filesystem;
    make_own_folder(dir);  // inside the run's own partial folder: never through a link
    // Data: N x N x 3 floats.
    std::vector<float> data(size_t(n) * size_t(n) * 3);
    for (size_t at = 0; at < size_t(n) * size_t(n); ++at) {
        const Vec2d e = errors[at];
        data[3 * at] = float(e.x);
        data[3 * at + 1] = float(e.y);
        data[3 * at + 2] = float(std::hypot(e.x, e.y));
    }
    const std::string exr = (fs::path(dir) / (stem + ".exr")).string();
    write_new_image(data, n, n, 3, "float", exr);

    // Picture: the map scaled up (nearest) to at least 384 px, a title above, legend below.
    const ErrorMapBox box = error_map_box(n);
    const int side = box.side, k = side / n, top = box.y0, x0 = box.x0, legend = 64;
    const int width = std::max(side, 420);
    Canvas pic(width, top + side + legend);  // white
    const float black[3] = {0, 0, 0};
    bool outside = false;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const size_t at = size_t(j) * n + i;
            const Vec2d e = errors[at];
            float rgb[3] = {0.5f, 0.5f, 0.5f};  // outside the camera's view: grey
            if (at < inside.size() && !inside[at]) outside = true;
            else error_colour(std::hypot(e.x, e.y), rgb);
            const int row = as_seen ? n - 1 - j : j;
            pic.fill(rgb, x0 + i * k, x0 + (i + 1) * k, top + row * k, top + (row + 1) * k);
        }
    pic.text(6, 19, title, 14, black);
    // Legend: the colour bar from 1/16 to 16 texels (log2), ticks labelled.
    const int bx0 = 30, bx1 = width - 30, by0 = top + side + 10, by1 = by0 + 14;
    for (int x = bx0; x < bx1; ++x) {
        float rgb[3];
        ramp(double(x - bx0) / double(bx1 - bx0 - 1), rgb);
        pic.fill(rgb, x, x + 1, by0, by1);
    }
    const char* labels[] = {"1/16", "1/4", "1", "4", "16"};
    for (int t = 0; t < 5; ++t) {
        const int x = bx0 + int(std::lround(double(t) / 4 * (bx1 - bx0 - 1)));
        pic.fill(black, x, x + 1, by1, by1 + 4);
        pic.text(x - 8, by1 + 17, labels[t], 12, black);
    }
    pic.text(bx0, by1 + 34,
             outside ? "texel error (log; magenta: non-finite; grey: outside)"
                     : "texel error (log scale; magenta: non-finite)",
             12, black);
    const std::string png = (fs::path(dir) / (stem + ".png")).string();
    write_new_image(pic.px, pic.width, pic.height, 3, "uint8", png);
    return stem + ".png";
}

std::string camera_name_part(const ResultRow& r) {
    std::string s;
    for (const CameraKey& k : camera_key_columns()) {
        const double v = r.num(k.name);
        if (std::isnan(v)) continue;
        char part[64];
        std::snprintf(part, sizeof part, "_%s%g", k.tag.c_str(), v);
        s += part;
    }
    return s;
}

ErrorMapName error_map_name(const ResultRow& r, size_t index) {
    const std::string& fmt = r.text("texture_format");
    const std::string what = r.text("backend") + "-" + (fmt.empty() ? r.text("precision") : fmt);
    const std::string& params = r.text("params");
    // The setting's parameters, so two settings of one method are told apart by name: the
    // values of "layers=32;layers_min=off" as "layers-32_layers_min-off"; past kParamsInName
    // characters cut and ended by 8 hex digits of the parameters' sha256 (the index keeps the
    // name unique in any case).
    constexpr size_t kParamsInName = 64;
    std::string ps;
    for (char ch : params) ps += ch == '=' ? '-' : ch == ';' ? '_' : ch;
    if (ps.size() > kParamsInName)
        ps = ps.substr(0, kParamsInName - 9) + "~" + sha256_hex(params).substr(0, 8);
    // A camera's settings and a level mode other than base, when the row has them.
    std::string view = camera_name_part(r);
    const std::string& lod = r.text("lod");
    if (!lod.empty() && lod != "base") view += "_" + lod;
    const std::string& depth = r.text("depth");
    if (!depth.empty() && depth != "base") view += "_depth-" + depth;
    if (!r.cell("cut").empty()) view += "_cut" + r.cell("cut");
    // A base with a radius (a curved one): the plane's names stay as they were before bases.
    const std::string base = r.cell("radius").empty() ? "" : r.text("base");
    if (!base.empty()) view += "_" + base + "R" + r.cell("radius");
    char stem[512];
    std::snprintf(stem, sizeof stem, "%05zu_%s%s%s_%s_t%g_p%g%s_%s", index,
                  r.text("method").c_str(), ps.empty() ? "" : "_", ps.c_str(),
                  r.text("heightfield").c_str(), r.num("theta_deg"), r.num("phi_deg"), view.c_str(),
                  what.c_str());
    ErrorMapName n{stem, ""};
    for (char& ch : n.stem)
        if (!std::isalnum((unsigned char)ch) && ch != '_' && ch != '-' && ch != '.') ch = '_';
    n.title = r.text("method") + (params.empty() ? "" : " " + params) + " | " +
              r.text("heightfield") + " | theta " + format_number(r.num("theta_deg")) + " phi " +
              format_number(r.num("phi_deg")) +
              (std::isnan(r.num("distance")) ? "" : " D " + format_number(r.num("distance"))) +
              (lod.empty() || lod == "base" ? "" : " | lod " + lod) +
              (base.empty() ? "" : " | " + base + " R " + r.cell("radius")) + " | " +
              r.text("backend");
    return n;
}

}  // namespace pxh

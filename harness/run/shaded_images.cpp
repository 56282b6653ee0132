#include "harness/run/shaded_images.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "harness/core/safe_files.h"
#include "harness/metrics/flip.h"
#include "harness/metrics/image_metrics.h"
#include "harness/results/error_maps.h"
#include "harness/results/pictures.h"
#include "harness/run/view_rows.h"

namespace pxh {

namespace fs = std::filesystem;

bool shading_wanted(const Experiment& ex) { return ex.shading.has_value(); }

bool shades_whole_image(const ResultRow& row, int samples) {
    const double r = row.num("resolution");
    return !std::isfinite(r) || int(r) == samples;
}

namespace {

// The material of the view's field: its levels, the run's albedo, s, the light.
Material view_material(const ShadingSpec& sh, const ViewOutput& v) {
    const ResultRow& r = v.rows.front();
    const double w = r.num("width"), h = r.num("height");
    return {v.levels, sh.levels.get(), r.num("scale"),
            light_direction(sh.elevation_deg, sh.azimuth_deg),
            std::log2(double(std::max(sh.levels->width, sh.levels->height)) / std::max(w, h))};
}

// What the shaded images are made of: the view's samples, or under a `samples` subset the
// same rows evaluated over the camera's whole image (ViewOutput::whole).
struct Pixels {
    const std::vector<Vec2d>& truth;
    const std::vector<uint8_t>& inside;
    const std::vector<uint8_t>& truth_hit;
    const std::vector<double>& lambda;
    const std::vector<std::vector<Vec2d>>& errors;
    const std::vector<std::vector<Vec2d>>& shown_uv;
    const std::vector<std::vector<uint8_t>>& cut_shows;
    const std::vector<std::vector<float>>& shaded;
    int n;
};
Pixels pixels_of(const ViewOutput& v, int samples) {
    if (!v.whole)
        return {v.truth,    v.inside,    v.truth_hit, v.lambda, v.errors,
                v.shown_uv, v.cut_shows, v.shaded,    samples};
    const ViewRows& w = *v.whole;
    return {w.truth_uv,  w.inside, w.truth_hit,
            w.lambda,    w.errors, w.shown_uv,
            w.cut_shows, w.shaded, int(std::lround(std::sqrt(double(w.truth_uv.size()))))};
}

// What one row's method shows: its uv per pixel (the truth's plus its wrapped error, or on a
// curved base its own) and where it covers anything.
struct Shown {
    std::vector<Vec2d> uv;
    std::vector<uint8_t> covered;
};
Shown method_shows(const Pixels& v, const ResultRow& row, size_t i, bool curved) {
    Shown s;
    s.uv =
        curved && i < v.shown_uv.size() && !v.shown_uv[i].empty()
            ? v.shown_uv[i]
            : uv_from_errors(v.truth, v.errors[i], int(row.num("width")), int(row.num("height")));
    s.covered.resize(s.uv.size());
    for (size_t k = 0; k < s.uv.size(); ++k)
        s.covered[k] = (k >= v.inside.size() || v.inside[k]) && std::isfinite(s.uv[k].x) &&
                       std::isfinite(s.uv[k].y);
    return s;
}

// The largest difference of two 8-bit images (values / 255), in 8-bit steps.
double max_step_difference(const std::vector<float>& a, const std::vector<float>& b) {
    double worst = 0;
    for (size_t k = 0; k < a.size() && k < b.size(); ++k)
        worst = std::max(worst, std::fabs(double(a[k]) - double(b[k])) * 255.0);
    return std::round(worst);
}

// A [views] cut's plane, the same colour on both sides where it shows (bit 1 truth, 2 method).
void paint_cut(std::vector<float>& srgb, const std::vector<uint8_t>& shows, uint8_t bit) {
    for (size_t k = 0; k < shows.size() && 3 * k + 2 < srgb.size(); ++k)
        if (shows[k] & bit)
            for (size_t c = 0; c < 3; ++c) srgb[3 * k + c] = srgb_encode(kPlaneRgb[c]);
}

// The PNG of a FLIP map in the paper's colours (magma).
void write_flip_map(const std::vector<float>& map, int n, const std::string& path, bool as_seen) {
    const std::vector<uint8_t> bytes = flip_magma_image(map);
    std::vector<float> rgb(bytes.size());
    for (size_t k = 0; k < bytes.size(); ++k) rgb[k] = float(bytes[k]) / 255.0f;
    write_picture(rgb, n, path, as_seen);
}

// Whether the row's shaded images go to DIR/pictures: the [render] montage views and strip.
bool rendered(const Experiment& ex, const ResultRow& row) {
    if (!ex.render || !ex.render->covers(row.text("heightfield"), row.num("phi_deg"))) return false;
    const RenderSpec& r = *ex.render;
    const double theta = row.num("theta_deg");
    const bool montage = std::count(r.theta_deg.begin(), r.theta_deg.end(), theta) > 0;
    return montage || (!r.strip_method.empty() && row.text("method") == r.strip_method &&
                       row.text("params") == r.strip_params);
}

}  // namespace

void write_shaded(const ViewWriteContext& c, ViewOutput& view) {
    const ShadingSpec& sh = *c.ex.shading;
    if (view.rows.empty() || !view.levels) return;
    if (!view.whole && !shades_whole_image(view.rows.front(), c.ex.samples)) return;
    const Pixels v = pixels_of(view, c.ex.samples);
    if (v.errors.size() != view.rows.size()) return;  // not the view's rows: no numbers
    const int n = v.n;
    const Material m = view_material(sh, view);
    const bool curved = !v.truth_hit.empty();
    const bool as_seen = !camera_entry(c.ex.camera, "camera").parallel;
    std::vector<uint8_t> truth_covered = v.inside;
    if (truth_covered.empty()) truth_covered.assign(v.truth.size(), 1);
    if (curved)
        for (size_t k = 0; k < truth_covered.size() && k < v.truth_hit.size(); ++k)
            truth_covered[k] &= v.truth_hit[k];
    std::vector<float> truth_img = shaded_image(m, v.truth, v.lambda, truth_covered);
    quantize_8bit(truth_img);
    const fs::path dir = c.dir / "pictures";
    std::map<std::string, std::string> truth_files;  // per cut plane ("" without one)
    for (size_t i = 0; i < view.rows.size(); ++i) {
        // a failed row (measured, or over the whole image): no image, no numbers
        if (view.errors[i].empty() || v.errors[i].empty()) continue;
        ResultRow& row = view.rows[i];
        const Shown s = method_shows(v, row, i, curved);
        std::vector<float> img = shaded_image(m, s.uv, v.lambda, s.covered);
        quantize_8bit(img);
        // A backend that shaded its image itself (GLSL): its image, and how far the CPU twin's
        // shading of the same uv lies from it.
        if (i < v.shaded.size() && v.shaded[i].size() == img.size()) {
            row.set("shade_cpu_diff_max", max_step_difference(v.shaded[i], img));
            img = v.shaded[i];
        }
        std::vector<float> truth_cut;
        const bool cut = i < v.cut_shows.size() && !v.cut_shows[i].empty();
        if (cut) {
            truth_cut = truth_img;
            paint_cut(truth_cut, v.cut_shows[i], 1);
            paint_cut(img, v.cut_shows[i], 2);
        }
        const std::vector<float>& truth_shown = cut ? truth_cut : truth_img;
        std::vector<uint8_t> mask(s.covered.size());
        for (size_t k = 0; k < mask.size(); ++k)
            mask[k] = (k >= v.inside.size() || v.inside[k]) && (s.covered[k] || truth_covered[k]);
        const bool files = rendered(c.ex, row);
        std::vector<float> map;
        add_flip({img, truth_shown, n, sh.ppd, mask}, row, files ? &map : nullptr);
        if (!files) continue;
        make_own_folder(dir);
        std::string& truth_file = truth_files[cut ? row.cell("cut") : ""];
        if (truth_file.empty()) {
            truth_file = "shaded_" + truth_picture_name(row);
            write_picture(truth_shown, n, (dir / truth_file).string(), as_seen);
        }
        const std::string stem = error_map_name(row, view.first + i).stem;
        write_picture(img, n, (dir / (stem + "_shaded.png")).string(), as_seen);
        write_flip_map(map, n, (dir / (stem + "_flip.png")).string(), as_seen);
        row.set_text("shaded", "pictures/" + stem + "_shaded.png");
        row.set_text("shaded_truth", "pictures/" + truth_file);
        row.set_text("flip_map", "pictures/" + stem + "_flip.png");
    }
}

}  // namespace pxh

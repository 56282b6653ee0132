#include "harness/run/view_writers.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <map>

#include "harness/core/safe_files.h"
#include "harness/metrics/image_metrics.h"
#include "harness/results/error_maps.h"
#include "harness/results/pictures.h"
#include "harness/run/shaded_images.h"

namespace pxh {

namespace fs = std::filesystem;

namespace {

// --maps (maps = true): one error map per row (EXR + PNG) under DIR/maps, named in the row's
// map column.
bool maps_wanted(const Experiment& ex) { return ex.maps; }

// A camera's map as its pictures are: outside pixels grey, rows as the viewer sees them.
void write_maps(const ViewWriteContext& c, ViewOutput& v) {
    const bool as_seen = !camera_entry(c.ex.camera, "camera").parallel;
    // A curved base: grey also where the truth shows no surface (no error there); magenta stays
    // for the method's discards where the truth shows surface.
    std::vector<uint8_t> both;
    if (!v.truth_hit.empty()) {
        both = v.truth_hit;
        for (size_t k = 0; k < both.size() && k < v.inside.size(); ++k) both[k] &= v.inside[k];
    }
    const std::vector<uint8_t>& mask = both.empty() ? v.inside : both;
    for (size_t i = 0; i < v.rows.size(); ++i) {
        if (v.errors[i].empty()) continue;
        const ErrorMapName name = error_map_name(v.rows[i], v.first + i);
        v.rows[i].set_text(
            "map", "maps/" + write_error_map(v.errors[i], c.ex.samples, (c.dir / "maps").string(),
                                             name.stem, name.title, mask, as_seen));
    }
}

// The samples whose uv is finite (what a method shows on a curved base).
std::vector<uint8_t> shown_mask(const std::vector<Vec2d>& uv) {
    std::vector<uint8_t> m(uv.size());
    for (size_t k = 0; k < uv.size(); ++k) m[k] = std::isfinite(uv[k].x) && std::isfinite(uv[k].y);
    return m;
}

// [render]: for every row of a render view, its picture against the truth's (the image
// metrics); for the montage views and the strip's setting, the pictures under DIR/pictures.
bool pictures_wanted(const Experiment& ex) { return ex.render.has_value(); }

void write_pictures(const ViewWriteContext& c, ViewOutput& v) {
    const RenderSpec& r = *c.ex.render;
    std::vector<ResultRow>& rows = v.rows;
    if (rows.empty() || !r.covers(rows[0].text("heightfield"), rows[0].num("phi_deg"))) return;
    const double theta = rows[0].num("theta_deg");
    const bool montage = std::count(r.theta_deg.begin(), r.theta_deg.end(), theta) > 0;
    const int n = c.ex.samples;
    // A camera's image as the viewer sees it (outside pixels grey); the grid in texture space.
    const bool as_seen = !camera_entry(c.ex.camera, "camera").parallel;
    // On a curved base each side shows surface only where it is hit: background elsewhere.
    const bool curved = !v.truth_hit.empty();
    const std::vector<float> truth_pic = picture(v.truth, n, curved ? v.truth_hit : v.inside);
    const fs::path dir = c.dir / "pictures";
    // The truth's picture per cut plane ("" without one), written once, when the first row of
    // the view that needs it does.
    std::map<std::string, std::string> truth_files;
    for (size_t i = 0; i < rows.size(); ++i) {
        if (v.errors[i].empty()) continue;  // a failed row: no picture, no numbers
        ResultRow& row = rows[i];
        auto pic = curved && i < v.shown_uv.size() && !v.shown_uv[i].empty()
                       ? picture(v.shown_uv[i], n, shown_mask(v.shown_uv[i]))
                       : picture(uv_from_errors(v.truth, v.errors[i], int(row.num("width")),
                                                int(row.num("height"))),
                                 n, v.inside);
        // With a cut plane, what the depth test shows: the plane where it is in front.
        const std::vector<uint8_t>* shows =
            i < v.cut_shows.size() && !v.cut_shows[i].empty() ? &v.cut_shows[i] : nullptr;
        std::vector<float> truth_cut;
        if (shows) {
            truth_cut = truth_pic;
            paint_plane(truth_cut, *shows, 1);
            paint_plane(pic, *shows, 2);
        }
        const std::vector<float>& truth_shown = shows ? truth_cut : truth_pic;
        apply_image_metrics({pic, truth_shown, n}, row);
        const bool strip = !r.strip_method.empty() && row.text("method") == r.strip_method &&
                           row.text("params") == r.strip_params;
        if (!montage && !strip) continue;
        make_own_folder(dir);
        std::string& truth_file = truth_files[shows ? row.cell("cut") : ""];
        if (truth_file.empty()) {
            truth_file = truth_picture_name(row);
            write_picture(truth_shown, n, (dir / truth_file).string(), as_seen);
        }
        const std::string stem = error_map_name(row, v.first + i).stem;
        write_picture(pic, n, (dir / (stem + ".png")).string(), as_seen);
        write_picture(difference(pic, truth_shown), n, (dir / (stem + "_diff.png")).string(),
                      as_seen);
        row.set_text("picture", "pictures/" + stem + ".png");
        row.set_text("picture_diff", "pictures/" + stem + "_diff.png");
        row.set_text("picture_truth", "pictures/" + truth_file);
        row.set_text("picture_use", montage && strip ? "montage strip"
                                    : montage        ? "montage"
                                                     : "strip");
    }
}

}  // namespace

std::string truth_picture_name(const ResultRow& r) {
    char name[512];
    std::snprintf(name, sizeof name, "truth_%s_t%g_p%g", r.text("heightfield").c_str(),
                  r.num("theta_deg"), r.num("phi_deg"));
    std::string s = name + camera_name_part(r);
    if (const std::string radius = r.cell("radius"); !radius.empty())  // a curved base's
        s += "_" + r.text("base") + "R" + radius;
    if (const std::string cut = r.cell("cut"); !cut.empty()) s += "_cut" + cut;
    for (char& ch : s)
        if (!std::isalnum((unsigned char)ch) && ch != '_' && ch != '-' && ch != '.') ch = '_';
    return s + ".png";
}

const std::vector<ViewWriter>& view_writers() {
    static const std::vector<ViewWriter> writers = {
        {"maps", &maps_wanted, &write_maps},
        {"pictures", &pictures_wanted, &write_pictures},
        {"shading", &shading_wanted, &write_shaded},
    };
    return writers;
}

std::vector<const ViewWriter*> wanted_view_writers(const Experiment& ex) {
    std::vector<const ViewWriter*> out;
    for (const ViewWriter& w : view_writers())
        if (w.wanted(ex)) out.push_back(&w);
    return out;
}

RunOptions::ViewHook view_writers_into(const Experiment& ex, const fs::path& dir) {
    const std::vector<const ViewWriter*> writers = wanted_view_writers(ex);
    if (writers.empty()) return {};
    return [&ex, dir, writers](ViewOutput& view) {
        for (const ViewWriter* w : writers) w->write({ex, dir}, view);
    };
}

}  // namespace pxh

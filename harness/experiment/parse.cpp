// Reading an experiment file: the file itself (a regular UTF-8 file, TOML), its top-level
// keys (the backends read theirs), [views] (the view sweep's keys; the camera reads its own),
// [light] and [render]; the entries are read by heightfield_entries.cpp and
// method_entries.cpp. Every table's unread keys are errors at their FILE:LINE.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "harness/backends/backend.h"
#include "harness/core/error.h"
#include "harness/core/registry.h"
#include "harness/core/safe_files.h"
#include "harness/experiment/entries.h"
#include "harness/metrics/row.h"
#include "harness/results/pictures.h"
#include "harness/scene/base_surface.h"
#include "harness/scene/view.h"
#include "harness/truth/curved_tracer.h"
#include "harness/truth/tracer.h"
#include "harness/truth/travel_limit.h"

namespace pxh {

namespace fs = std::filesystem;

void check_safe_name(const std::string& name, const std::string& where, const std::string& what,
                     bool folder) {
    std::string problem;
    if (name.empty()) problem = "is empty";
    else if (name.size() > 100) problem = "is longer than 100 characters";
    else if (name.find('/') != std::string::npos || name.find('\\') != std::string::npos)
        problem = "contains '/' or '\\'";
    else if (std::any_of(name.begin(), name.end(),
                         [](unsigned char c) { return c < 0x20 || c == 0x7f; }))
        problem = "contains control characters";
    else if (folder && name[0] == '.') problem = "starts with '.'";
    if (!problem.empty())
        throw InputError(where, what + " '" + name + "' " + problem + ": it names " +
                                    (folder ? "the output folder" : "files") +
                                    ", so it must be a plain file name");
}

void warn(Experiment& ex, const std::string& text) { ex.warnings.push_back(one_line(text)); }

// A number exactly, for messages about values that print alike.
std::string exactly(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
}

// Distinct values that results.csv would print alike (its cells keep 10 significant digits)
// would make rows whose keys are the same: refused at `where`, naming both.
void refuse_alike(const std::vector<double>& values, const std::string& key,
                  const std::string& where) {
    for (size_t i = 0; i < values.size(); ++i)
        for (size_t j = i + 1; j < values.size(); ++j)
            if (values[i] != values[j] &&
                format_cell_number(values[i]) == format_cell_number(values[j]))
                throw InputError(where, key + " values " + exactly(values[i]) + " and " +
                                            exactly(values[j]) + " both print as " +
                                            format_cell_number(values[i]) +
                                            " in results.csv (10 significant digits): their rows "
                                            "would share their keys; give values that differ "
                                            "there");
}

namespace {

std::string count_text(size_t n) { return n == SIZE_MAX ? "more than 2^64" : std::to_string(n); }

}  // namespace

void check_entry_rows(size_t& total, const RowProduct& rows, const std::string& where,
                      const std::string& entry, const ParseLimits& lim) {
    const size_t before = total;
    total = rows.value > SIZE_MAX - before ? SIZE_MAX : before + rows.value;
    const std::string also =
        before ? " (" + std::to_string(before) + " more from the entries before it)" : "";
    if (total > lim.max_rows)
        throw InputError(where, "this " + entry + " entry would write " + count_text(rows.value) +
                                    " rows (" + rows.text + ")" + also + " > --max-rows " +
                                    std::to_string(lim.max_rows) +
                                    ": refused before expanding it (raise --max-rows N)");
    if (total > lim.max_memory / kBytesPerRow)
        throw InputError(
            where, "this " + entry + " entry would write " + count_text(rows.value) + " rows (" +
                       rows.text + ")" + also + ", whose " + std::to_string(kBytesPerRow) +
                       " bytes each need more than --max-memory " + format_bytes(lim.max_memory) +
                       ": refused before expanding it (raise --max-memory SIZE)");
}

size_t variants_per_setting(const Experiment& ex, const ParseLimits& lim, bool glsl_only) {
    const auto& backends = lim.backends.empty() ? ex.backends : lim.backends;
    const BackendSettings settings = backend_settings(ex);
    size_t n = 0;
    for (const auto& b : backends)
        if (!glsl_only || b == "glsl") n += backend_variants(b, settings).size();
    return std::max<size_t>(n, 1);
}

BackendSettings backend_settings(const Experiment& ex) { return ex.backend; }

namespace {

// The experiment's default name, from its file name: made safe rather than refused.
std::string safe_default_name(const std::string& stem) {
    std::string out;
    for (unsigned char c : stem) out += (c < 0x20 || c == 0x7f || c == '\\') ? '_' : char(c);
    while (!out.empty() && out[0] == '.') out[0] = '_';
    if (out.size() > 100) out.resize(100);
    return out.empty() ? "experiment" : out;
}

// The experiment's own top-level keys: name, sizes, backends, flags, the reference (the
// backends read theirs).
void parse_settings(const ParamDict& root, Experiment& ex) {
    if (auto n = root.string("name")) {
        ex.name = *n;
        check_safe_name(ex.name, root.where("name"), "experiment name", true);
    }
    root.string("description");
    ex.samples = root.integer("samples", ex.samples, 1, kMaxSamples);
    ex.backends = root.strings("backends", ex.backends);
    for (const auto& b : ex.backends) check_backend_name(b, root.where("backends"));
    if (auto v = root.number("sweep_dt_deg")) {
        ex.sweep_dt_deg = *v;
        if (!(ex.sweep_dt_deg > 0 && ex.sweep_dt_deg < 10))
            throw InputError(root.where("sweep_dt_deg"), "sweep_dt_deg must lie in (0, 10)");
    }
    ex.maps = root.boolean("maps", ex.maps);
    ex.exclude_filled = root.boolean("exclude_filled", ex.exclude_filled);
    ex.ground_truth = root.string("ground_truth", ex.ground_truth);
    const auto known = tracer_names();
    if (std::find(known.begin(), known.end(), ex.ground_truth) == known.end())
        throw InputError(root.where("ground_truth"), "unknown ground_truth '" + ex.ground_truth +
                                                         "' (known: " + join_names(known) + ")");
    if (auto c = root.string("truth_check")) {
        if (*c != "all" && *c != "subset" && *c != "none")
            throw InputError(root.where("truth_check"),
                             "unknown truth_check '" + *c +
                                 "' (known: all, subset, none: which rays of each view the "
                                 "truth's cross-check traces for the gt_agree_* columns)");
        ex.truth_check = *c;
    }
}

// [views] theta_deg: in degrees, [0, 90), increasing, each once (warned and fixed otherwise).
void parse_theta(const ParamDict& vt, Experiment& ex) {
    ex.theta_deg = vt.angles("theta_deg", {});
    const std::string theta_where = vt.where("theta_deg");
    for (double t : ex.theta_deg)
        if (!(t >= 0 && t < 90))
            throw InputError(theta_where,
                             "theta_deg = " + format_number(t) +
                                 " is impossible: the polar angle must lie in [0, 90)");
    const bool all_small =
        std::all_of(ex.theta_deg.begin(), ex.theta_deg.end(), [](double t) { return t < 1.6; });
    const bool all_whole = std::all_of(ex.theta_deg.begin(), ex.theta_deg.end(),
                                       [](double t) { return t == std::floor(t); });
    if (all_small && !all_whole)
        warn(ex, theta_where +
                     ": theta_deg values are all below 1.6 and not all whole "
                     "numbers: they look like radians, but theta_deg is in degrees");
    // Sweeps (sliding, shimmering) pair consecutive views: increasing, each view once.
    if (!std::is_sorted(ex.theta_deg.begin(), ex.theta_deg.end()) ||
        std::adjacent_find(ex.theta_deg.begin(), ex.theta_deg.end()) != ex.theta_deg.end()) {
        const bool sorted = std::is_sorted(ex.theta_deg.begin(), ex.theta_deg.end());
        const size_t before = ex.theta_deg.size();
        std::sort(ex.theta_deg.begin(), ex.theta_deg.end());
        ex.theta_deg.erase(std::unique(ex.theta_deg.begin(), ex.theta_deg.end()),
                           ex.theta_deg.end());
        const size_t dropped = before - ex.theta_deg.size();
        std::string what = sorted ? "" : "is not in increasing order (sorted";
        if (dropped)
            what += std::string(sorted ? "repeats values (" : ", ") + std::to_string(dropped) +
                    " duplicate(s) dropped";
        warn(ex, theta_where + ": theta_deg " + what +
                     "): views are measured in increasing theta, each once");
    }
    refuse_alike(ex.theta_deg, "theta_deg", theta_where);
}

// [views] phi_deg: normalised into [0, 360), each once (warned).
void parse_phi(const ParamDict& vt, Experiment& ex) {
    ex.phi_deg = vt.angles("phi_deg", ex.phi_deg);
    const std::string phi_where = vt.where("phi_deg");
    std::string changed;
    for (double& p : ex.phi_deg) {
        if (!std::isfinite(p)) throw InputError(phi_where, "phi_deg must be finite");
        if (p >= 0 && p < 360) continue;
        double q = std::fmod(p, 360.0);
        if (q < 0) q += 360;
        if (q >= 360) q = 0;  // -1e-20 + 360 rounds to 360
        changed += (changed.empty() ? "" : ", ") + format_number(p) + " -> " + format_number(q);
        p = q;
    }
    if (!changed.empty()) warn(ex, phi_where + ": phi_deg outside [0, 360) normalised: " + changed);
    std::vector<double> unique;
    for (double p : ex.phi_deg)
        if (std::find(unique.begin(), unique.end(), p) == unique.end()) unique.push_back(p);
    if (unique.size() != ex.phi_deg.size())
        warn(ex, phi_where + ": phi_deg repeats an azimuth (" +
                     std::to_string(ex.phi_deg.size() - unique.size()) +
                     " duplicate(s) dropped): each view is measured once");
    ex.phi_deg = std::move(unique);
    refuse_alike(ex.phi_deg, "phi_deg", phi_where);
    for (double p : ex.phi_deg)
        if (format_cell_number(p) == "360")
            throw InputError(phi_where, "phi_deg = " + exactly(p) +
                                            " prints as 360 in results.csv (10 significant "
                                            "digits), the azimuth of phi 0: give 0, or a value "
                                            "that prints below 360");
}

// The camera's settings each once: a repeated value of one of its keys (distance = [2, 2, 3])
// gives settings that repeat, dropped with a warning as repeated angles are; distinct values
// that print alike in results.csv are refused at their key.
void dedupe_camera_settings(const ParamDict& vt, Experiment& ex) {
    std::vector<CameraSetting> unique;
    size_t dropped = 0;
    for (const CameraSetting& c : ex.camera_settings) {
        bool repeat = false;
        for (const CameraSetting& u : unique) {
            bool same = true, alike = true;
            for (size_t k = 0; k < c.values.size(); ++k) {
                same = same && c.values[k].second == u.values[k].second;
                alike = alike && format_cell_number(c.values[k].second) ==
                                     format_cell_number(u.values[k].second);
            }
            if (same) {
                repeat = true;
                break;
            }
            if (alike)
                for (size_t k = 0; k < c.values.size(); ++k)
                    if (c.values[k].second != u.values[k].second)
                        refuse_alike({c.values[k].second, u.values[k].second}, c.values[k].first,
                                     vt.where(c.values[k].first));
        }
        if (repeat) ++dropped;
        else unique.push_back(c);
    }
    if (dropped) {
        std::string keys;
        for (const auto& [k, v] : ex.camera_settings.front().values)
            keys += (keys.empty() ? "" : ", ") + k;
        warn(ex, vt.where() + ": camera '" + ex.camera + "' settings repeat (" +
                     std::to_string(dropped) + " duplicate(s) of " + keys +
                     " dropped): each view is measured once");
    }
    ex.camera_settings = std::move(unique);
}

// [views]: the view sweep (theta_deg, phi_deg) and the camera's name read here; the camera
// reads its own keys (made once here for that; the runner makes one per view).
void parse_views(const ParamDict& vt, Experiment& ex) {
    if (!vt.has("theta_deg")) throw InputError(vt.where(), "[views] needs theta_deg");
    parse_theta(vt, ex);
    if (vt.has("phi_deg")) parse_phi(vt, ex);
    ex.camera = vt.string("camera", ex.camera);
    const auto known = camera_names();
    if (std::find(known.begin(), known.end(), ex.camera) == known.end())
        throw InputError(vt.where("camera"),
                         "unknown camera '" + ex.camera + "' (known: " + join_names(known) + ")");
    ex.cuts = vt.numbers("cut", {});
    for (size_t i = 0; i < ex.cuts.size(); ++i) {
        if (!std::isfinite(ex.cuts[i]))
            throw InputError(vt.where("cut"), "cut must be finite (a height in height-map units)");
        for (size_t j = 0; j < i; ++j)
            if (ex.cuts[j] == ex.cuts[i])
                throw InputError(vt.where("cut"),
                                 "cut " + format_number(ex.cuts[i]) + " is given twice");
    }
    ex.camera_params = vt;
    const size_t before = vt.asked().size();
    ex.camera_settings = Camera::settings(ex.camera, vt, vt.where(), ex.samples);
    dedupe_camera_settings(vt, ex);
    const auto asked = vt.asked();
    const std::vector<std::string> own(asked.begin() + long(before), asked.end());
    vt.report_unused([&](const std::string& key, const std::string& all) {
        return "unknown key '" + key + "' in [views] (known: " + all + "; camera '" + ex.camera +
               "' reads " + (own.empty() ? "no keys of its own" : join_names(own)) + ")";
    });
}

void parse_light(const ParamDict& lt, Experiment& ex) {
    LightSpec l;
    l.theta_deg = lt.number("theta_deg", l.theta_deg);
    l.phi_deg = lt.number("phi_deg", l.phi_deg);
    l.layers_min = lt.number("layers_min", l.layers_min);
    l.layers_max = lt.number("layers_max", l.layers_max);
    lt.report_unused();
    if (!(l.theta_deg >= 0 && l.theta_deg < 90))
        throw InputError(lt.where(), "light theta_deg = " + format_number(l.theta_deg) +
                                         " is impossible: it must lie in [0, 90)");
    if (!std::isfinite(l.phi_deg)) throw InputError(lt.where(), "light phi_deg must be finite");
    if (!(l.layers_min >= 1 && l.layers_max >= l.layers_min && l.layers_max <= 4096))
        throw InputError(lt.where(), "light layers need 1 <= layers_min <= layers_max <= 4096");
    ex.light = l;
}

// [shading]: the albedo (checker, or an image file relative to the experiment), the light and
// FLIP's pixels per degree; the albedo file is read here, so a bad one is an error at its line.
void parse_shading(const ParamDict& t, Experiment& ex) {
    ShadingSpec s;
    s.albedo = t.string("albedo", s.albedo);
    s.albedo_size = t.integer("albedo_size", s.albedo_size, 1, 8192);
    s.elevation_deg = t.number("elevation_deg", s.elevation_deg);
    s.azimuth_deg = t.number("azimuth_deg", s.azimuth_deg);
    s.ppd = t.number("ppd", s.ppd);
    t.report_unused();
    if (!(s.elevation_deg >= 0 && s.elevation_deg <= 90))
        throw InputError(
            t.where("elevation_deg"),
            "[shading] elevation_deg = " + format_number(s.elevation_deg) + " must lie in [0, 90]");
    if (!std::isfinite(s.azimuth_deg))
        throw InputError(t.where("azimuth_deg"), "[shading] azimuth_deg must be finite");
    // FLIP's feature filters vanish in float below about 1.7 pixels per degree (flip.h)
    if (!(s.ppd >= 2 && s.ppd <= 1000))
        throw InputError(t.where("ppd"), "[shading] ppd = " + format_number(s.ppd) +
                                             " must lie in [2, 1000] pixels per degree");
    if (s.albedo == "checker") {
        s.image = std::make_shared<const RgbImage>(checker_albedo(s.albedo_size));
    } else {
        if (t.has("albedo_size"))
            throw InputError(t.where("albedo_size"),
                             "[shading] albedo_size is the checker's size: an albedo file has "
                             "its own");
        fs::path fp = s.albedo;
        if (fp.is_relative()) fp = fs::path(ex.path).parent_path() / fp;
        try {
            s.image = std::make_shared<const RgbImage>(read_albedo_image(fp.string()));
        } catch (const std::exception& e) {
            throw InputError(t.where("albedo"),
                             "[shading] albedo file '" + fp.string() + "' " + e.what());
        }
    }
    s.levels = std::make_shared<const AlbedoLevels>(build_albedo_levels(*s.image));
    ex.shading = s;
}

// [render], read after the fields and methods it names: every name, angle and method must be
// one the experiment has.
void parse_render(const ParamDict& t, Experiment& ex) {
    for (const char* k : {"heightfields", "theta_deg"})
        if (!t.has(k)) throw InputError(t.where(), std::string("[render] needs ") + k);
    RenderSpec r;
    r.heightfields = t.strings("heightfields", {});
    const std::optional<double> phi = t.number("phi_deg");
    r.theta_deg = t.numbers("theta_deg", {});
    const std::optional<std::string> strip = t.string("strip_method");
    t.report_unused();
    for (const auto& f : r.heightfields)
        if (std::none_of(ex.heightfields.begin(), ex.heightfields.end(),
                         [&](const HeightfieldSpec& h) { return h.name == f; }))
            throw InputError(t.where("heightfields"), "[render] heightfield '" + f +
                                                          "' is no [[heightfields]] entry's name");
    auto in = [](const std::vector<double>& v, double x) {
        return std::find(v.begin(), v.end(), x) != v.end();
    };
    r.phi_deg = phi.value_or(ex.phi_deg.front());
    if (phi && !in(ex.phi_deg, r.phi_deg))
        throw InputError(t.where("phi_deg"), "[render] phi_deg = " + format_number(r.phi_deg) +
                                                 " is not one of [views] phi_deg");
    for (double th : r.theta_deg)
        if (!in(ex.theta_deg, th))
            throw InputError(t.where("theta_deg"), "[render] theta_deg = " + format_number(th) +
                                                       " is not one of [views] theta_deg");
    if (strip) {
        r.strip_method = *strip;
        const auto m = std::find_if(ex.methods.begin(), ex.methods.end(), [&](const MethodSpec& s) {
            return s.method->name == r.strip_method;
        });
        if (m == ex.methods.end())
            throw InputError(t.where("strip_method"), "[render] strip_method '" + r.strip_method +
                                                          "' is no [[methods]] entry");
        r.strip_params = m->params.canonical();
    }
    ex.render = r;
}

// Every eye ray (views, sweep companions) and light ray within the ground truths' travel
// limit (kMaxRayTravelTiles, harness/truth/travel_limit.h), reported at the field's entry.
void check_ray_travel(const Experiment& ex) {
    for (const HeightfieldSpec& h : ex.heightfields) {
        auto check = [&](double theta, const std::string& what) {
            if (const std::string why = ray_travel_problem(h.scale, theta); !why.empty())
                throw InputError(h.where, what + why);
        };
        for (double t : ex.theta_deg) {
            check(t, "");
            if (ex.sweep_dt_deg > 0 && t + ex.sweep_dt_deg < 90)
                check(t + ex.sweep_dt_deg, "sweep companion view: ");
        }
        if (ex.light) check(ex.light->theta_deg, "light: ");
        // A camera whose rays are not parallel: its inside pixels look up to 89 degrees.
        if (!camera_entry(ex.camera, "camera").parallel)
            check(89.0, "camera '" + ex.camera + "': its most grazing inside pixel: ");
    }
}

}  // namespace

void check_camera_samples(const Experiment& ex, const std::string& where) {
    const CameraEntry& cam = camera_entry(ex.camera, "camera");
    if (!cam.samples_problem) return;
    bool neighbours = false;  // a setting takes the GPU's derivatives between fragments
    for (const MethodSpec& m : ex.methods) neighbours = neighbours || m.lod == LodMode::implicit;
    for (const CameraSetting& c : ex.camera_settings)
        if (const std::string why = cam.samples_problem(c, ex.samples, neighbours); !why.empty())
            throw InputError(where.empty() ? ex.camera_params.where() : where, why);
}

namespace {

// Every view of the camera (its settings x theta, the companion views' too) must see every
// slab it looks at (the perspective camera: its eye above it): an InputError at the camera's
// first key of [views] (or [views]) naming the field otherwise.
// Every theta a run traces: the views' and, with sweep_dt_deg, each one's companion dt away
// (below when theta + dt would reach 90).
std::vector<double> measured_thetas(const Experiment& ex) {
    std::vector<double> out;
    for (double t : ex.theta_deg) {
        out.push_back(t);
        if (ex.sweep_dt_deg > 0)
            out.push_back(t + ex.sweep_dt_deg < 90 ? t + ex.sweep_dt_deg : t - ex.sweep_dt_deg);
    }
    return out;
}

void check_camera_scenes(const Experiment& ex) {
    const CameraEntry& cam = camera_entry(ex.camera, "camera");
    if (!cam.scene_problem) return;
    const auto keys = ex.camera_settings.front().values;
    const std::string where =
        keys.empty() ? ex.camera_params.where() : ex.camera_params.where(keys.front().first);
    for (const HeightfieldSpec& h : ex.heightfields)
        for (const CameraSetting& c : ex.camera_settings)
            for (double th : measured_thetas(ex))
                if (const std::string why =
                        cam.scene_problem(c, {th, 0, ex.samples}, h.scale, h.bias);
                    !why.empty())
                    throw InputError(where, "heightfield '" + h.name +
                                                "' (s = " + format_number(h.scale) +
                                                ", b = " + format_number(h.bias) + "): " + why);
}

// Every inside pixel of a perspective view must lie within the exact tracer's reach of its field
// (kMaxSampleCells: far eyes put samples so far out that the walk's exit lines stop moving):
// an InputError at the camera's first key of [views] naming the field and the setting.
// Float rows lose accuracy with distance (float spaces uv more coarsely far from the origin):
// warned once per field where float's spacing there reaches 1/16 texel (the rows say it too:
// harness/run/runner.cpp).
void check_camera_reach(Experiment& ex) {
    const CameraEntry& camera = camera_entry(ex.camera, ex.camera_params.where());
    if (!camera.reach) return;  // its samples stay within the tile
    const auto keys = ex.camera_settings.front().values;
    const std::string where =
        keys.empty() ? ex.camera_params.where() : ex.camera_params.where(keys.front().first);
    for (const HeightfieldSpec& h : ex.heightfields) {
        const FieldSize size = field_size(h);
        bool warned = false;
        for (const CameraSetting& c : ex.camera_settings)
            for (double th : measured_thetas(ex)) {
                // |P - C| at any phi (it turns the image about C), then |P.x|, |P.y|.
                const double reach = 0.5 + camera.reach(c, {th, 0, ex.samples});
                // "distance 1e+15, fov_deg 45, resolution 32 at theta 30"
                std::string view;
                for (const auto& [key, value] : c.values)
                    view += (view.empty() ? "" : ", ") + key + " " + format_number(value);
                view += " at theta " + format_number(th);
                if (const std::string why = reach_problem(reach, int(size.width), int(size.height));
                    !why.empty())
                    throw InputError(where, "heightfield '" + h.name + "': " + view + " " + why);
                const float far = float(reach);
                const double gap = (double(std::nextafter(far, 2 * far)) - double(far)) *
                                   double(std::max(size.width, size.height));
                if (!warned && gap >= 1.0 / 16) {
                    warned = true;
                    warn(ex, where + ": heightfield '" + h.name + "': " + view +
                                 " puts inside pixels up to " + format_number(reach) +
                                 " tiles from the origin, where float spaces uv " +
                                 format_number(gap) +
                                 " texels apart: the float rows (CPU float, GLSL) lose "
                                 "accuracy with distance from there on (their rows say so "
                                 "in 'error'); the double rows do not");
                }
            }
    }
}

// What is not measured on a curved base yet (docs/conventions.md section 12): true shadows
// ([light]); the Embree reference (ground_truth = "embree": a curved base's truth is the curved
// walk whatever the file names, so a row labelled embree would carry the walk's numbers). And
// the precision bound on the radius (kMaxBaseRadiusCells, harness/truth/curved_tracer.h).
// Refused, naming the entry (the ground_truth key for Embree).
void check_curved_bases(const Experiment& ex, const std::string& ground_truth_where) {
    for (const HeightfieldSpec& h : ex.heightfields) {
        if (!base_entry(h.base).curved) continue;
        const std::string on = "on a curved base (base = \"" + h.base + "\")";
        if (ex.light)
            throw InputError(h.where, "[light] (true shadows) is not traced " + on + " yet");
        if (ex.ground_truth == "embree")
            throw InputError(ground_truth_where.empty() ? h.where : ground_truth_where,
                             "ground_truth = \"embree\" does not apply to heightfield '" + h.name +
                                 "' " + on +
                                 ": its truth is the curved walk (Embree traces the "
                                 "plane's relief only), whose rows say ground_truth = exact; "
                                 "remove ground_truth or set it to \"exact\"");
        const FieldSize size = field_size(h);
        if (const std::string why =
                base_radius_problem(h.base, h.radius, int(size.width), int(size.height));
            !why.empty())
            throw InputError(h.where, "heightfield '" + h.name + "': " + why);
    }
}

// The curved truth's work of every view of a curved base (curved_walk_estimate, the walk's
// steps through each ray's chord of the relief's shell), within kMaxCurvedWalkSteps: an
// InputError at the field's entry naming the view and the estimate otherwise. Run after
// --samples too (the estimate grows with the rays).
void check_curved_walk(const Experiment& ex) {
    // each view's ray count, made once (a view does not depend on the field)
    std::vector<size_t> view_rays;
    for (const HeightfieldSpec& h : ex.heightfields) {
        if (!base_entry(h.base).curved) continue;
        const auto base = make_base(h.base, h.radius);
        const FieldSize size = field_size(h);
        size_t v = 0;
        for (const CameraSetting& c : ex.camera_settings)
            for (double th : measured_thetas(ex))
                for (double phi : ex.phi_deg) {
                    const auto cam = Camera::create(ex.camera, c, {th, phi, ex.samples});
                    if (v == view_rays.size()) view_rays.push_back(cam->view().size());
                    const size_t rays = view_rays[v++];
                    const double walks = curved_walks(ex.truth_check, rays);
                    const CurvedWalkEstimate e =
                        curved_walk_estimate(*base, h.scale, h.bias, int(size.width),
                                             int(size.height), *cam, rays, 0.25, walks);
                    const std::string said =
                        "the truth, and the check walk at half the step on " +
                        std::string(ex.truth_check == "all"    ? "every ray (truth_check = \"all\")"
                                    : ex.truth_check == "none" ? "no ray (truth_check = \"none\")"
                                                               : "one ray in 16 (truth_check = "
                                                                 "\"subset\")") +
                        ": " + format_number(walks) + " walks";
                    if (const std::string why = curved_walk_problem(e, said); !why.empty()) {
                        std::string view = c.label();
                        view += (view.empty() ? "" : " ") + std::string("theta ") +
                                format_number(th) + " phi " + format_number(phi);
                        throw InputError(h.where, "heightfield '" + h.name + "' (base " + h.base +
                                                      " radius " + format_number(h.radius) +
                                                      ", s = " + format_number(h.scale) + ") at " +
                                                      view + ": " + why);
                    }
                }
    }
}

}  // namespace

Experiment parse_experiment(const std::string& text, const std::string& path,
                            const ParseLimits& limits) {
    // run.json records the path and the text: both must be UTF-8, checked before any work.
    if (const std::string why = utf8_problem(path); !why.empty())
        throw InputError(path,
                         "the experiment file's name is not UTF-8 (" + why + "): rename the file");
    if (const std::string why = utf8_problem(text); !why.empty())
        throw InputError(path + ":" + why.substr(5, why.find(',') - 5),
                         why.substr(why.find(',') + 2) +
                             " (experiment files are UTF-8 text: re-save it as UTF-8)");
    const ParamDict root = ParamDict::parse(text, path, "the experiment");
    Experiment ex;
    ex.path = path;
    ex.text = text;
    ex.name = safe_default_name(fs::path(path).stem().string());
    parse_settings(root, ex);
    read_backend_settings(root, ex.backend);
    const auto views = root.table("views", "[views]", "missing [views] table (theta_deg = [...])");
    if (!views) throw InputError(path, "missing [views] table (theta_deg = [...])");
    const auto light = root.table("light", "[light]", "'light' must be a table ([light])");
    const auto render = root.table("render", "[render]", "'render' must be a table ([render])");
    const auto shading =
        root.table("shading", "[shading]", "'shading' must be a table ([shading])");
    const auto heightfields = root.tables("heightfields", "[[heightfields]]");
    const auto methods = root.tables("methods", "[[methods]]");
    root.report_unused();
    parse_views(*views, ex);
    if (light) parse_light(*light, ex);
    LargeScales large_scales;
    ParseState state{limits, 0, 0, {}};
    for (const auto& e : heightfields) parse_heightfield(e, ex, large_scales, state);
    warn_large_scales(large_scales, ex);
    check_heightfield_names(ex);
    for (const auto& e : methods) parse_method(e, ex, state);
    if (render) parse_render(*render, ex);
    if (shading) parse_shading(*shading, ex);
    check_curved_bases(ex, root.has("ground_truth") ? root.where("ground_truth") : "");
    check_ray_travel(ex);
    check_camera_scenes(ex);
    check_camera_samples(ex, "");
    check_camera_reach(ex);
    check_curved_walk(ex);
    return ex;
}

Experiment load_experiment(const std::string& path, const ParseLimits& limits) {
    std::error_code ec;
    const auto st = fs::status(path, ec);  // follows symlinks
    if (!fs::exists(st)) throw InputError(path, "no such file");
    if (fs::is_directory(st)) throw InputError(path, "is a directory, not an experiment file");
    // A FIFO or device would block or never end: only regular files are read.
    if (!fs::is_regular_file(st))
        throw InputError(path,
                         "not a regular file (a FIFO, socket or device?): an experiment "
                         "must be a regular file");
    std::ifstream f(path, std::ios::binary);
    if (!f) throw InputError(path, "cannot open");
    std::stringstream ss;
    ss << f.rdbuf();
    Experiment ex = parse_experiment(ss.str(), path, limits);
    for (const auto& w : ex.warnings) std::cerr << "pxh: warning: " << one_line(w) << "\n";
    return ex;
}

Experiment load_run_experiment(const std::string& path, const RunOverrides& o) {
    Experiment ex = load_experiment(path, {o.max_rows, o.max_memory, o.backends});
    ex.maps = ex.maps || o.maps;
    if (!o.only.empty()) apply_only(ex, o.only);
    if (o.samples) ex.samples = *o.samples;
    check_plugin_backends(ex, o.backends);
    check_camera_samples(ex, o.samples ? "--samples" : "");
    if (o.samples) check_curved_walk(ex);
    for (const std::string& w : skipped_settings(ex, o.backends)) {  // said, never silent
        std::cerr << "pxh: warning: " << w << "\n";
        ex.warnings.push_back(w);
    }
    check_run_size(ex, o.backends, o.max_rows, o.max_memory);
    return ex;
}

}  // namespace pxh

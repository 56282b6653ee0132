// The figures: data/*.csv (what the plots draw, with each series' keys as separate fields)
// and harness/report/plot_report.py, which only draws them.
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <iostream>
#include <set>
#include <sstream>
#include <tuple>

#include "harness/core/error.h"
#include "harness/core/shipped_files.h"
#include "harness/metrics/columns.h"
#include "harness/report/report_data.h"
#include "harness/results/error_maps.h"
#include "harness/scene/view.h"

extern char** environ;

namespace pxh {

namespace fs = std::filesystem;

namespace {

// The keys of a series, as CSV fields: method, params, backend, precision, texture_format.
// A level mode other than base is part of the setting: the plotter sees it as one more
// parameter (params "layers=32;lod=level"), so it names the series in legends.
std::string params_field(const ResultRow& r) {
    std::string p = r.text("params");
    for (const char* key : {"lod", "depth", "cut"}) {
        const std::string v = r.cell(key);
        if (!v.empty() && v != "base") p += (p.empty() ? "" : ";") + std::string(key) + "=" + v;
    }
    return p;
}

const char* const kKeyHeader = "method,params,backend,precision,texture_format";
std::string key_fields(const ResultRow& r) {
    std::string out = csv_quote(r.text("method")) + "," + csv_quote(params_field(r));
    for (const char* k : {"backend", "precision", "texture_format"})
        out += "," + csv_quote(r.text(k));
    return out;
}

// A row's camera view as CSV fields: its view (view_of: "distance=4 fov_deg=45 resolution=256",
// empty for a camera without keys), the part of pxh run's file names that tells views apart
// (camera_name_part: "_d4_f45_r256") and its level mode; the plotter groups pictures and maps
// by the view, names its files by the tag and titles their panels with both.
const char* const kViewHeader = "camera_view,camera_tag,lod";
std::string view_fields(const ReportData& d, const ResultRow& r) {
    return csv_quote(d.view_of(r)) + "," + csv_quote(d.tag_of(r)) + "," + csv_quote(r.text("lod"));
}

// A picture or map path of row i (column c): relative to the results folder and inside it, no
// part of it a symbolic link (a path that leaves the folder is refused: the plotter would read
// whatever it names). A missing file is left to the plotter (a blank tile, with a warning).
const std::string& inside_path(const ReportData& d, size_t i, const char* c) {
    const std::string& rel = d.row(i).text(c);
    if (rel.empty()) return rel;
    const auto bad = [&](const std::string& why) {
        return InputError(d.file.path + ":" + std::to_string(d.file.lines[i]),
                          std::string("column ") + c + ": '" + rel + "' " + why);
    };
    const fs::path p(rel);
    if (p.is_absolute()) throw bad("is an absolute path; pictures lie inside the results folder");
    fs::path at(d.dir);
    for (const auto& part : p) {
        if (part == "..") throw bad("leaves the results folder ('..')");
        at /= part;
        struct stat st {};
        if (::lstat(at.c_str(), &st) != 0) return rel;  // missing: the plotter says so
        if (S_ISLNK(st.st_mode))
            throw bad("passes through a symbolic link (" + at.string() + "); refused");
    }
    return rel;
}

// data/vs_theta.csv: error and sweeps against θ per field, series and camera view (means over
// φ; a camera run's views apart: a mean over distances mixes errors orders of magnitude apart),
// with a camera view's pixel error.
void vs_theta(const ReportData& d) {
    using Key = std::tuple<std::string, std::string, double, std::string>;
    std::map<Key, std::array<Mean, 6>> acc;
    std::map<Key, size_t> first;
    std::map<Key, std::vector<std::string>> phis;  // the azimuths each mean is over
    std::vector<Key> order;
    for (size_t i : d.ok) {
        const ResultRow& r = d.row(i);
        const Key key{field_of(r), series_of(r), r.num("theta_deg"), d.view_of(r)};
        if (!acc.count(key)) {
            order.push_back(key);
            first[key] = i;
        }
        auto& p = phis[key];
        if (std::find(p.begin(), p.end(), r.cell("phi_deg")) == p.end())
            p.push_back(r.cell("phi_deg"));
        auto& a = acc[key];
        a[0].add(r.num("err_p50"));
        a[1].add(r.num("err_p95"));
        a[2].add(r.num("sliding"));
        a[3].add(r.num("shimmering"));
        if (!camera_name_part(r).empty()) {  // orthographic rows: a fixed multiple of texels
            a[4].add(r.num("err_px_p50"));
            a[5].add(r.num("err_px_p95"));
        }
    }
    std::ostringstream o;
    o << "heightfield,series," << kKeyHeader
      << ",theta_deg,err_p50,err_p95,sliding,shimmering,"
         "phi_deg_list,camera_view,camera_tag,err_px_p50,err_px_p95\n";
    for (const auto& k : order) {
        const auto& a = acc[k];
        o << csv_quote(std::get<0>(k)) << "," << csv_quote(std::get<1>(k)) << ","
          << key_fields(d.row(first[k])) << "," << csv_num(std::get<2>(k)) << ","
          << csv_num(a[0].get()) << "," << csv_num(a[1].get()) << "," << csv_num(a[2].get()) << ","
          << csv_num(a[3].get());
        std::string pl;
        for (const auto& p : phis[k]) pl += (pl.empty() ? "" : ";") + p;
        o << "," << csv_quote(pl) << "," << csv_quote(std::get<3>(k)) << ","
          << csv_quote(d.tag_of(d.row(first[k]))) << "," << csv_num(a[4].get()) << ","
          << csv_num(a[5].get()) << "\n";
    }
    d.write("data/vs_theta.csv", o.str());
}

// data/vs_distance.csv, when some row has a camera distance and the run has more than one:
// texel and pixel error (p50 and p95, the statistics error_vs_theta draws) against the eye's
// distance per field, view angle and series (means over phi and fov_deg).
void vs_distance(const ReportData& d) {
    std::set<double> distances;
    for (size_t i : d.ok)
        if (std::isfinite(d.row(i).num("distance"))) distances.insert(d.row(i).num("distance"));
    if (distances.size() < 2) return;
    using Key = std::tuple<std::string, double, std::string, double>;
    std::map<Key, std::array<Mean, 5>> acc;
    std::map<Key, size_t> first;
    std::vector<Key> order;
    for (size_t i : d.ok) {
        const ResultRow& r = d.row(i);
        if (!std::isfinite(r.num("distance"))) continue;
        const Key key{field_of(r), r.num("theta_deg"), series_of(r), r.num("distance")};
        if (!acc.count(key)) {
            order.push_back(key);
            first[key] = i;
        }
        auto& a = acc[key];
        a[0].add(r.num("err_p50"));
        a[1].add(r.num("err_p95"));
        a[2].add(r.num("err_px_p50"));
        a[3].add(r.num("err_px_p95"));
        a[4].add(r.num("lod_mean"));
    }
    std::ostringstream o;
    o << "heightfield,theta_deg,series," << kKeyHeader
      << ",distance,err_p50,err_p95,err_px_p50,err_px_p95,lod_mean\n";
    for (const auto& k : order) {
        const auto& a = acc[k];
        o << csv_quote(std::get<0>(k)) << "," << csv_num(std::get<1>(k)) << ","
          << csv_quote(std::get<2>(k)) << "," << key_fields(d.row(first[k])) << ","
          << csv_num(std::get<3>(k));
        for (const Mean& m : a) o << "," << csv_num(m.get());
        o << "\n";
    }
    d.write("data/vs_distance.csv", o.str());
}

// data/maps.csv: the error maps, every field x azimuth x series x θ (a montage per field and
// azimuth); paths relative to the results folder (as results.csv has them), so the folder can
// move.
// map_x0, map_y0, map_side: where the map lies in its PNG (error_map_box), without pxh run's
// title and colour bar: the montage draws one colour bar for all its tiles. With it
// data/error_scale.csv, the colour scale every map was drawn with (error_colour).
void maps(const ReportData& d) {
    std::ostringstream o;
    o << "heightfield,phi_deg,series," << kKeyHeader << ",theta_deg,map,map_x0,map_y0,map_side,"
      << kViewHeader << "\n";
    int n = 0;
    for (size_t i : d.ok) {
        const ResultRow& r = d.row(i);
        const std::string& map = inside_path(d, i, "map");
        if (map.empty()) continue;
        const double samples = r.num("samples");
        const ErrorMapBox box = std::isfinite(samples) && samples >= 1 && samples <= 1 << 16
                                    ? error_map_box(int(samples))
                                    : ErrorMapBox{0, 0, 0};
        o << csv_quote(field_of(r)) << "," << csv_quote(r.cell("phi_deg")) << ","
          << csv_quote(series_of(r)) << "," << key_fields(r) << ","
          << csv_quote(r.cell("theta_deg")) << "," << csv_quote(map) << "," << box.x0 << ","
          << box.y0 << "," << box.side << "," << view_fields(d, r) << "\n";
        ++n;
    }
    if (!n) return;
    d.write("data/maps.csv", o.str());
    std::ostringstream scale;
    scale << "log2_texels,r,g,b\n";
    for (int k = 0; k <= 256; ++k) {
        const double l2 = -4 + 8.0 * k / 256;
        float rgb[3];
        error_colour(std::exp2(l2), rgb);
        scale << csv_num(l2) << "," << csv_num(rgb[0]) << "," << csv_num(rgb[1]) << ","
              << csv_num(rgb[2]) << "\n";
    }
    d.write("data/error_scale.csv", scale.str());
}

// The costs a figure draws error against: fetches, then the time in each time_unit of the
// rows (columns time[UNIT], time_min[UNIT], time_max[UNIT], pareto_time[UNIT]).
std::vector<std::string> cost_names(const ReportData& d) {
    std::vector<std::string> c{"fetches_mean"};
    for (const std::string& u : d.time_units) c.push_back("time[" + u + "]");
    return c;
}
std::vector<double> costs_of(const ReportData& d, const Acc& a) {
    std::vector<double> c{a.fetches.get()};
    for (const std::string& u : d.time_units) c.push_back(a.time_in(u));
    return c;
}
std::string pareto_name(const std::string& cost) {
    return cost == "fetches_mean" ? "pareto_fetches" : "pareto_" + cost;
}

// Pareto flags per series and cost: "1" on its group's front, "0" off it, "" when the point
// has no such cost; over exactly the points the plot draws in that panel.
std::vector<std::vector<const char*>> pareto_flags(const ReportData& d,
                                                   const std::vector<std::vector<double>>& cost,
                                                   const std::vector<double>& err) {
    std::map<std::string, std::vector<size_t>> by_group;  // group -> series indices
    for (size_t i = 0; i < d.series_order.size(); ++i)
        by_group[d.series.at(d.series_order[i]).group].push_back(i);
    const size_t costs = cost_names(d).size();
    std::vector<std::vector<const char*>> flag(d.series_order.size(),
                                               std::vector<const char*>(costs, ""));
    for (const auto& [group, members] : by_group)
        for (size_t c = 0; c < costs; ++c) {
            std::vector<double> gc, ge;
            for (size_t i : members) {
                gc.push_back(cost[i][c]);
                ge.push_back(err[i]);
            }
            const auto front = pareto(gc, ge);
            for (size_t k = 0; k < members.size(); ++k)
                flag[members[k]][c] =
                    std::isfinite(gc[k]) && std::isfinite(ge[k]) ? (front[k] ? "1" : "0") : "";
        }
    return flag;
}

// data/cost_vs_error.csv: per series, error against each cost, with the Pareto fronts.
void cost_vs_error(const ReportData& d) {
    const size_t n = d.series_order.size();
    std::vector<std::vector<double>> cost(n);
    std::vector<double> err(n);
    for (size_t i = 0; i < n; ++i) {
        const Series& s = d.series.at(d.series_order[i]);
        cost[i] = costs_of(d, s.all);
        err[i] = s.all.err_mean.get();
    }
    const auto flag = pareto_flags(d, cost, err);
    std::ostringstream o;
    o << "series,setting,method,group,err_mean,err_p95";
    for (const std::string& c : cost_names(d)) o << "," << csv_quote(c);
    for (const std::string& c : cost_names(d)) o << "," << csv_quote(pareto_name(c));
    o << ",params,backend,precision,texture_format\n";
    for (size_t i = 0; i < n; ++i) {
        const Series& s = d.series.at(d.series_order[i]);
        const ResultRow& r = d.row(s.first_row);
        o << csv_quote(d.series_order[i]) << "," << csv_quote(s.setting) << ","
          << csv_quote(s.method) << "," << csv_quote(s.group) << "," << csv_num(err[i]) << ","
          << csv_num(s.all.err_p95.get());
        for (double c : cost[i]) o << "," << csv_num(c);
        for (const char* f : flag[i]) o << "," << f;
        o << "," << csv_quote(params_field(r));
        for (const char* k : {"backend", "precision", "texture_format"})
            o << "," << csv_quote(r.text(k));
        o << "\n";
    }
    d.write("data/cost_vs_error.csv", o.str());
}

// data/cost_vs_error_bands.csv: per angle band and series, the means over the series' rows in
// that band, with Pareto flags per (band, group, cost) over exactly those points: a figure
// panel per band draws one group's points of that band and its front. A camera run: the same
// per camera view (columns camera_view, camera_tag; fronts per view), a figure each.
void cost_vs_error_bands(const ReportData& d) {
    const size_t n = d.series_order.size();
    const std::vector<std::string> names = cost_names(d);
    std::ostringstream o;
    o << "band,band_lo,band_hi,band_label,series,setting,group,err_mean,err_p95";
    for (const std::string& c : names) o << "," << csv_quote(c);
    for (const std::string& c : names) o << "," << csv_quote(pareto_name(c));
    o << "," << kKeyHeader;
    for (const std::string& u : d.time_units)
        o << "," << csv_quote("time_min[" + u + "]") << "," << csv_quote("time_max[" + u + "]");
    if (d.has_views()) o << ",camera_view,camera_tag";
    o << "\n";
    const std::vector<std::string> views =
        d.has_views() ? d.view_order : std::vector<std::string>{""};
    for (const std::string& view : views) {
        const std::map<std::string, Series>& sers =
            d.has_views() ? d.views.at(view).series : d.series;
        for (size_t b : d.present_bands()) {
            std::vector<std::vector<double>> cost(n, std::vector<double>(names.size(), NAN));
            std::vector<double> err(n, NAN);
            for (size_t i = 0; i < n; ++i) {
                auto it = sers.find(d.series_order[i]);
                if (it == sers.end() || !it->second.band.count(b)) continue;
                const Acc& a = it->second.band.at(b);
                cost[i] = costs_of(d, a);
                err[i] = a.err_mean.get();
            }
            const auto flag = pareto_flags(d, cost, err);
            for (size_t i = 0; i < n; ++i) {
                auto it = sers.find(d.series_order[i]);
                if (it == sers.end() || !it->second.band.count(b)) continue;
                const Series& s = it->second;
                o << b << "," << csv_num(d.bands.lo(b)) << "," << csv_num(d.bands.hi(b)) << ","
                  << csv_quote(d.bands.label(b)) << "," << csv_quote(d.series_order[i]) << ","
                  << csv_quote(s.setting) << "," << csv_quote(s.group) << "," << csv_num(err[i])
                  << "," << csv_num(s.band.at(b).err_p95.get());
                for (double c : cost[i]) o << "," << csv_num(c);
                for (const char* f : flag[i]) o << "," << f;
                const Acc& a = s.band.at(b);
                o << "," << key_fields(d.row(s.first_row));
                for (const std::string& u : d.time_units) {
                    const TimeMeans* t = a.times_in(u);
                    o << "," << csv_num(t ? t->min.get() : NAN) << ","
                      << csv_num(t ? t->max.get() : NAN);
                }
                if (d.has_views())
                    o << "," << csv_quote(view) << "," << csv_quote(d.tag_of(d.row(s.first_row)));
                o << "\n";
            }
        }
    }
    d.write("data/cost_vs_error_bands.csv", o.str());
}

// data/pictures.csv: the rows with pictures ([render] views), paths relative to the results
// folder; the plot script draws a montage per field and montage view, a strip per field.
void pictures(const ReportData& d) {
    std::ostringstream o;
    o << "heightfield,theta_deg,phi_deg,series," << kKeyHeader
      << ",img_psnr_db,img_ssim,picture,picture_diff,picture_truth,picture_use," << kViewHeader;
    // the camera's keys as numbers too (empty on a row without them)
    for (const CameraKey& k : camera_key_columns()) o << "," << csv_quote(k.name);
    // the [views] cut whose plane the pictures show (empty: none), the curved base and radius,
    // the depth mode (a montage's tiles of one setting told apart by it)
    o << ",cut,base,radius,depth\n";
    int n = 0;
    for (size_t i : d.all_ok) {  // every depth mode and cut: the pictures differ
        const ResultRow& r = d.row(i);
        for (const char* c : {"picture", "picture_diff", "picture_truth"}) inside_path(d, i, c);
        if (r.text("picture").empty()) continue;
        o << csv_quote(r.text("heightfield")) << "," << csv_quote(r.cell("theta_deg")) << ","
          << csv_quote(r.cell("phi_deg")) << "," << csv_quote(series_of(r)) << "," << key_fields(r)
          << "," << csv_num(r.num("img_psnr_db")) << "," << csv_num(r.num("img_ssim"));
        for (const char* c : {"picture", "picture_diff", "picture_truth", "picture_use"})
            o << "," << csv_quote(r.text(c));
        o << "," << view_fields(d, r);
        for (const CameraKey& k : camera_key_columns()) o << "," << csv_num(r.num(k.name));
        o << "," << csv_num(r.num("cut")) << "," << csv_quote(r.text("base")) << ","
          << csv_num(r.num("radius")) << "," << csv_quote(r.text("depth")) << "\n";
        ++n;
    }
    if (n) d.write("data/pictures.csv", o.str());
}

// images.md: PSNR / SSIM of each series' picture against the truth's in the montage views.
void images_table(const ReportData& d) {
    std::vector<std::string> views;  // "FIELD θ=T φ=P"
    std::map<std::string, std::map<std::string, std::string>> cell;
    for (size_t i : d.all_ok) {
        const ResultRow& r = d.row(i);
        if (r.text("picture_use").find("montage") == std::string::npos) continue;
        const std::string cam = d.view_of(r);
        const std::string v = r.text("heightfield") + " θ=" + r.cell("theta_deg") +
                              " φ=" + r.cell("phi_deg") + (cam.empty() ? "" : " " + cam);
        if (std::find(views.begin(), views.end(), v) == views.end()) views.push_back(v);
        const double p = r.num("img_psnr_db");
        cell[series_of(r)][v] =
            (std::isinf(p) ? std::string("∞") : fmt(p, 1)) + " / " + fmt(r.num("img_ssim"), 3);
    }
    if (views.empty()) return;
    TextTable tt;
    tt.header = {"method"};
    for (const auto& v : views) tt.header.push_back(v + " PSNR dB / SSIM");
    tt.align = "l" + std::string(views.size(), 'r');
    // a setting's series with the same cells are one row naming all their groups
    for (const auto& set : d.setting_order) {
        std::vector<std::vector<std::string>> rows;
        std::vector<std::string> groups;
        for (const auto& s : d.settings.at(set).series) {
            if (!cell.count(s)) continue;
            std::vector<std::string> row;
            for (const auto& v : views) row.push_back(cell[s].count(v) ? cell[s][v] : "-");
            size_t i = 0;
            while (i < rows.size() && rows[i] != row) ++i;
            if (i == rows.size()) {
                rows.push_back(row);
                groups.emplace_back();
            }
            groups[i] += (groups[i].empty() ? "" : " = ") + d.series.at(s).group;
        }
        for (size_t i = 0; i < rows.size(); ++i) {
            rows[i].insert(rows[i].begin(), set + " [" + groups[i] + "]");
            tt.rows.push_back(rows[i]);
        }
    }
    tt.notes = d.notes(false);
    tt.notes.push_back(
        "The experiment's [render] views: a numbered checkerboard seen through the method's uv "
        "against the same texture seen through the true uv. PSNR with peak 1 over RGB (∞: "
        "identical pictures); SSIM as Wang et al. 2004 (11 x 11 Gaussian window, sigma 1.5, "
        "K1 = 0.01, K2 = 0.03) on the luma, mean over the valid windows.");
    d.write("images.md", tt.markdown());
}

}  // namespace

void write_plot_data(const ReportData& d) {
    pictures(d);
    images_table(d);
    vs_theta(d);
    vs_distance(d);
    cost_vs_error(d);
    cost_vs_error_bands(d);
    maps(d);
}

// plot_report.py (shipped beside the binary: harness/core/shipped_files.h) on the report folder,
// run by /usr/bin/python3 from an argument vector (no shell: any folder name is passed as it
// is); waits and checks its exit status.
namespace {
const char* const kPython = "/usr/bin/python3";
const char* const kPlotAdvice =
    "; the tables are written. Is python3-matplotlib installed? (./run.sh installs it)";
}  // namespace

Plotter::Plotter(const OwnedFolder& folder, double figure_width, const std::string& formats)
    : folder_(folder), staging_(folder.staging()), script_(shipped_file("plot_report.py")) {
    std::vector<std::string> args = {kPython,
                                     script_,
                                     folder.dir().string(),
                                     "--into",
                                     staging_.string(),
                                     "--width",
                                     csv_num(figure_width),
                                     "--formats",
                                     formats};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    std::cout << std::flush;
    if (const int e = posix_spawn(&pid_, kPython, nullptr, nullptr, argv.data(), environ)) {
        folder_.discard(staging_);
        throw std::runtime_error(std::string("cannot start ") + kPython + ": " + std::strerror(e) +
                                 kPlotAdvice);
    }
}

int Plotter::wait_status() {
    int status = 0;
    while (waitpid(pid_, &status, 0) < 0)
        if (errno != EINTR) {
            pid_ = 0;
            throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
        }
    pid_ = 0;
    return status;
}

void Plotter::finish() {
    const int status = wait_status();
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
        try {
            folder_.adopt(staging_);
        } catch (...) {  // a name taken by a file of the user's: what is left is not taken
            folder_.discard(staging_);
            throw;
        }
        return;
    }
    folder_.discard(staging_);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 2)  // it said why on one line
        throw InputError(script_, "refused its input (the line above); the tables are written");
    throw std::runtime_error(std::string("plotting failed (") + kPython + " " + script_ + ": " +
                             (WIFEXITED(status)
                                  ? "exit status " + std::to_string(WEXITSTATUS(status))
                                  : "killed by signal " + std::to_string(WTERMSIG(status))) +
                             ")" + kPlotAdvice);
}

Plotter::~Plotter() {
    if (pid_ <= 0) return;
    try {  // a table failed while the figures were drawn: the drawing ends before pxh does
        (void)wait_status();
        folder_.discard(staging_);
    } catch (const std::exception&) {
    }
}

}  // namespace pxh

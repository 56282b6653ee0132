// What `pxh report` computes from results.csv before writing anything: the typed rows, split
// by status, and per series (setting x backend/precision or format) and angle band the means
// every table and figure draws on. Internal to harness/report.
#pragma once
#include <sys/types.h>

#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "harness/core/safe_files.h"
#include "harness/report/bands.h"
#include "harness/report/report.h"
#include "harness/report/text_table.h"
#include "harness/results/results.h"

namespace pxh {

struct BudgetMetric {
    const char* name;    // --budget-metric
    const char* column;  // results.csv column, averaged over the rows of a band
    const char* header;
    const char* meaning;
    std::vector<double> budgets;
};
const BudgetMetric& budget_metric(const std::string& name);  // InputError when unknown

// A time's means over rows of one time_unit: the median, and the repeats' range.
struct TimeMeans {
    Mean time, min, max;
};

// Means over the ok rows of a series (or setting), overall or in one band. budget: the
// --budget-metric's column; px_budget: err_px_p95 (the pixel budget of camera runs).
struct Acc {
    Mean err_mean, err_p50, err_p95, fetches, sliding, shimmering, budget;
    Mean px_mean, px_p95, sliding_dist, shimmering_dist, px_budget;
    std::map<std::string, TimeMeans> time;  // by time_unit (a series has one: its backend's)
    double worst_p95 = NAN;
    bool nonfinite = false;  // some row had samples with NaN/Inf output
    void add(const ResultRow& r, const char* budget_column);
    // The mean time in this unit (NaN when no row of it was timed in it); and its range.
    double time_in(const std::string& unit) const;
    const TimeMeans* times_in(const std::string& unit) const;
};

struct Series {
    std::string setting, method, group;
    size_t first_row = 0;  // its first row: the keys (method, params, backend, ...) as data
    Acc all;
    std::map<size_t, Acc> band;
};

struct Setting {
    std::vector<std::string> series;  // its series, in order of appearance
    std::map<size_t, Acc> band;       // all its ok rows of a band pooled (fetches, time)
    std::set<size_t> failed_bands;    // bands where one of its rows failed
};

// The rows of one camera view (every field pooled, or one field): their series and settings,
// as ReportData::series / settings hold them for all the rows.
struct Part {
    std::map<std::string, Series> series;
    std::map<std::string, Setting> settings;
};

struct ReportData {
    std::string dir;            // the results folder
    std::filesystem::path out;  // DIR/report
    Bands bands;
    const BudgetMetric& metric;
    ResultsFile file;
    // Row indices by status. all_ok: every ok row (the metric families' tables and figures);
    // ok: those the texel tables and figures (summary, fields, budget, sweep, precision,
    // vs_theta, ...) draw on: where a key that cannot change the texel error varies (the depth
    // mode, the cut: ColumnSpec::affects), the rows at its first value only, so the same
    // texel numbers are not repeated once per value (`filtered` names those keys and values).
    std::vector<size_t> all_ok, ok, failed;
    std::vector<std::pair<std::string, std::string>> filtered;
    // The context keys of the run: every camera key some row has (distance, fov_deg, ...), and
    // every other axis key that is neither a series, field nor sweep key (base, radius, samples,
    // camera, ground_truth, a component's own keys) whose value varies between the rows. A
    // row's view (view_of) is its values of them; the tables and figures are one per view,
    // never a mean across views (a mean over bases or distances mixes errors that differ by
    // orders of magnitude).
    std::vector<std::string> context_keys;
    // "base=cylinder radius=2 distance=4": the row's context key values ("" for none).
    std::string view_of(const ResultRow& r) const;
    // The part of a file name that tells the row's view apart: pxh run's camera part
    // (camera_name_part: "_d4_f45_r256") and "_KEY-VALUE" for the other context keys.
    std::string tag_of(const ResultRow& r) const;
    std::vector<std::string> series_order, setting_order;
    std::map<std::string, Series> series;
    std::map<std::string, Setting> settings;
    // The same means per height field (field_of: "bricks s=0.05 b=1"), in order of appearance:
    // field -> series -> its rows on that field.
    std::vector<std::string> field_order;
    std::map<std::string, std::map<std::string, Series>> field_series;
    // The views of the ok rows (view_of), ascending by their keys' values (numbers as
    // numbers); one "" when the run has no context key (its tables are as they always were).
    std::vector<std::string> view_order;
    std::map<std::string, Part> views;                               // view -> its rows
    std::map<std::string, std::map<std::string, Part>> field_views;  // field -> view -> rows
    bool has_views() const { return view_order.size() > 1 || !view_order.front().empty(); }
    // Some ok row of a camera view (view_of not empty) has a pixel error (err_px_mean): the
    // tables show it beside the texel error and budget.md ranks by it. (Orthographic rows have
    // one too, err * N / W, but a fixed multiple of the texel error says nothing new: their
    // tables stay as they were.)
    bool pixel_error = false;
    // "distance = 4, fov_deg = 45, resolution = 256": a view as a table's heading (the key's
    // short label: "R = 2" for radius).
    static std::string view_title(const std::string& view);
    // Every backend/precision or format of the report, in order of appearance.
    std::vector<std::string> group_order;
    // Every time_unit of the ok rows, in order of appearance: a cost column or panel each.
    std::vector<std::string> time_units;
    // The compact LaTeX name of each setting of setting_order (one-to-one): the method, and
    // in parentheses the values of the fewest parameters that tell its settings apart
    // ("pom (32)", "pom (adaptive)"; letters "(a)", "(b)" when those values are long); the
    // method alone when it has one setting. legend.md/.tex map each back to its parameters.
    std::map<std::string, std::string> tex_label;

    // Reads DIR/results.csv (once, typed) and computes the means.
    ReportData(const std::string& dir, const ReportOptions& o);
    const ResultRow& row(size_t i) const { return file.rows[i]; }
    std::vector<size_t> present_bands() const;
    // The notes every table carries: failed rows, and with band columns single-view bands.
    std::vector<std::string> notes(bool with_bands = true) const;
    // Writes OUT/rel and says so (OwnedFolder::write).
    void write(const std::string& rel, const std::string& text) const;
    // DIR/report/, pxh report's own folder (harness/core/safe_files.h: OwnedFolder).
    OwnedFolder folder() const { return OwnedFolder(out, "pxh report"); }

    // A group as LaTeX tables name it: the backend alone ("glsl") when the report has one
    // precision / texture format of that backend, else the whole group ("glsl/r16").
    std::string short_group(const std::string& group) const;

    // `rows` less those of a key that cannot change `family` (ColumnSpec::affects) at any but
    // its first value; each key so held and its value appended to `held`.
    std::vector<size_t> held_rows(std::vector<size_t> rows, const std::string& family,
                                  std::vector<std::pair<std::string, std::string>>* held) const;

  private:
    void find_context();
    void filter_rows();
    void assign_bands();
    void collect();
    void name_settings();
};

// The compact labels of name_settings, for any list of settings (method, params as
// results.csv writes them: "k=v;k=v"), in the same order.
std::vector<std::string> compact_labels(
    const std::vector<std::pair<std::string, std::string>>& settings);

// Indices of the points on the lower-left Pareto front of (cost, error).
std::vector<bool> pareto(const std::vector<double>& cost, const std::vector<double>& err);

// The tables (harness/report/tables.cpp) and the figures' data and drawing (figures.cpp).
void write_summary(const ReportData& d);
void write_fields(const ReportData& d);
void write_legend(const ReportData& d);
void write_failed(const ReportData& d);
void write_sweep(const ReportData& d);
void write_precision(const ReportData& d);
void write_budget(const ReportData& d);
void write_plot_data(const ReportData& d);
// The plot script (plot_report.py), started on the data/ files written so far and drawing while
// pxh writes the tables (a folder of files apart from the figures'). It creates its files in a
// staging folder of the report's (OwnedFolder::staging); finish() waits for it, then takes its
// files into the report folder (OwnedFolder::adopt), or throws its failure (InputError: it
// refused its input, exit 2) and removes what it drew. A Plotter destroyed unfinished (a table's
// write failed) waits for the script and removes its files before pxh goes on.
class Plotter {
  public:
    Plotter(const OwnedFolder& folder, double figure_width, const std::string& formats);
    Plotter(const Plotter&) = delete;
    Plotter& operator=(const Plotter&) = delete;
    ~Plotter();
    void finish();

  private:
    int wait_status();
    OwnedFolder folder_;
    std::filesystem::path staging_;
    std::string script_;
    pid_t pid_ = 0;
};

}  // namespace pxh

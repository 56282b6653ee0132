// The columns of results.csv: one registry, in file order. Every writer (results.csv, the
// console summary) and reader (pxh report, pxh check) takes the columns from here; none keeps
// its own list. A column is a key (says what ran: kept on a failed row) or measured (a number
// the run produced: empty on a failed row, since a failure is never a number).
//
// Adding a column: one line in the table of harness/metrics/columns.cpp (name, type, role,
// meaning), at the place it takes in results.csv; the code that measures it then calls
// row.set("name", value) (harness/metrics/row.h). A metric outside that table (a test's) is
// registered at run time with ColumnRegistration.
#pragma once
#include <algorithm>
#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace pxh {

struct CameraKey;  // harness/scene/view.h

enum class ColumnType { text, integer, number };  // numbers are doubles; NaN is an empty cell
enum class ColumnRole { key, measured };
// A key that says where in the experiment's grid a row lies (what ran, on what, from where):
// named axes appear in a row's name ("theta=30 distance=4"); quiet ones identify the row but are
// implied by its name (samples, camera, ground_truth). pxh run --only, pxh check's filters and
// ratio baselines, pxh compare's row identity and names, the report's tables and the view's
// file names all take the axes from here (row_axes()).
enum class ColumnAxis { none, named, quiet };

// Which way a measured column is better: smaller (an error, a cost), larger (PSNR, SSIM), or
// neither (a count that describes the view, a unit).
enum class Better { none, smaller, larger };

struct ColumnSpec {
    std::string name;
    ColumnType type = ColumnType::number;
    ColumnRole role = ColumnRole::measured;
    std::string meaning;  // one line, for docs and `pxh columns`-like listings
    ColumnAxis axis = ColumnAxis::none;
    // The axis' short label in row names ("theta" for theta_deg); empty: its name.
    std::string label = {};
    // What the report needs of a measured column (pxh report reads nothing else): its family
    // (texel, pixel, depth, cut, coverage, sliding, image, fetches, timing, agreement, or a new
    // one a component brings: the report gives every family present in a run its table and
    // figure), its unit, which way is better, and whether it is one of the family's headline
    // columns (tabled per angle band and drawn against the run's axes; the others are in
    // results.csv and the family's data file). Empty family: bookkeeping (paths, units, lists).
    std::string family = {};
    std::string unit = {};
    Better better = Better::none;
    bool headline = false;
    // Keys only: the families whose values the key can change (empty: every family). A key
    // that cannot change a family (the depth mode cannot move a method's uv) is left out of
    // that family's tables, which show its first value's rows and say so, instead of
    // repeating equal numbers once per value.
    std::vector<std::string> affects = {};

    bool numeric() const { return type != ColumnType::text; }
    const std::string& shown_as() const { return label.empty() ? name : label; }
    // Declaration helpers: ColumnSpec{...}.in("texel", "texels").lead().
    ColumnSpec& in(std::string fam, std::string u, Better b = Better::smaller) {
        family = std::move(fam);
        unit = std::move(u);
        better = b;
        return *this;
    }
    ColumnSpec& lead() {
        headline = true;
        return *this;
    }
    ColumnSpec& affecting(std::vector<std::string> families) {
        affects = std::move(families);
        return *this;
    }
    bool can_change(const std::string& fam) const {
        return affects.empty() || std::find(affects.begin(), affects.end(), fam) != affects.end();
    }
};

// A family's title and one line on what it measures (known families; a new family's title is
// its name).
std::string family_title(const std::string& family);

// Every registered column, in results.csv order.
std::vector<const ColumnSpec*> result_column_specs();

// The column's spec, nullptr when no column has that name.
const ColumnSpec* find_column(std::string_view name);

// A stable index of a registered column (what a row stores its cells by); a name that is not
// registered is a programming error (std::logic_error naming it).
size_t column_id(std::string_view name);
const ColumnSpec& column_spec(size_t id);

// The axis keys that name a row's series (its setting and group: method params lod depth cut
// backend precision texture_format), its field (heightfield scale bias), and the sweep axes
// (theta_deg phi_deg) the report's bands and figures run over. Every other axis key is a
// context key (base, radius, samples, camera, ground_truth, the cameras' keys, a component's
// own): the outputs keep rows that differ in one apart, never averaging across it.
bool series_key(std::string_view column);
bool field_key(std::string_view column);
bool sweep_key(std::string_view column);
bool context_key(const ColumnSpec& c);  // an axis that is none of the three

// The context keys whose value varies between the rows (`cell(row, column)`), in column order.
std::vector<std::string> varying_context_keys(
    size_t rows, const std::function<std::string(size_t, const std::string&)>& cell);

// Every axis column (ColumnSpec::axis != none), in results.csv order.
std::vector<const ColumnSpec*> row_axes();

// The range keys of a numeric axis, KEY_min and KEY_max: "theta_min" for theta_deg, "phi_min"
// for phi_deg, "distance_min" for distance (pxh run --only and pxh check's [[limit]] alike).
std::string range_key(const ColumnSpec& axis, bool max);

// " theta=30 phi=0 distance=4 fov_deg=45": a row's named axes other than what its series and
// field name (method, params, lod, backend, precision, texture_format, heightfield, scale,
// bias), each that has a value, as " label=value". `cell` gives a column's cell.
std::string axes_name(const std::function<std::string(const std::string&)>& cell);

// Every camera's own keys (CameraEntry::keys), each a numeric key column, in column order:
// what pxh check filters by, pxh compare keys rows by and the view's file names carry.
const std::vector<CameraKey>& camera_key_columns();

// Registers one more column for as long as it lives, placed after every built-in measured
// column and before status and error (tests; a metric linked into another binary).
class ColumnRegistration {
  public:
    explicit ColumnRegistration(ColumnSpec spec);
    ~ColumnRegistration();
    ColumnRegistration(const ColumnRegistration&) = delete;
    ColumnRegistration& operator=(const ColumnRegistration&) = delete;

  private:
    std::string name_;
};

}  // namespace pxh

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

struct ColumnSpec {
    std::string name;
    ColumnType type = ColumnType::number;
    ColumnRole role = ColumnRole::measured;
    std::string meaning;  // one line, for docs and `pxh columns`-like listings
    ColumnAxis axis = ColumnAxis::none;
    // The axis' short label in row names ("theta" for theta_deg); empty: its name.
    std::string label = {};
    bool numeric() const { return type != ColumnType::text; }
    const std::string& shown_as() const { return label.empty() ? name : label; }
};

// Every registered column, in results.csv order.
std::vector<const ColumnSpec*> result_column_specs();

// The column's spec, nullptr when no column has that name.
const ColumnSpec* find_column(std::string_view name);

// A stable index of a registered column (what a row stores its cells by); a name that is not
// registered is a programming error (std::logic_error naming it).
size_t column_id(std::string_view name);
const ColumnSpec& column_spec(size_t id);

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

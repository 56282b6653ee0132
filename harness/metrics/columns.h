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
#include <string>
#include <string_view>
#include <vector>

namespace pxh {

struct CameraKey;  // harness/scene/view.h

enum class ColumnType { text, integer, number };  // numbers are doubles; NaN is an empty cell
enum class ColumnRole { key, measured };

struct ColumnSpec {
    std::string name;
    ColumnType type = ColumnType::number;
    ColumnRole role = ColumnRole::measured;
    std::string meaning;  // one line, for docs and `pxh columns`-like listings
};

// Every registered column, in results.csv order.
std::vector<const ColumnSpec*> result_column_specs();

// The column's spec, nullptr when no column has that name.
const ColumnSpec* find_column(std::string_view name);

// A stable index of a registered column (what a row stores its cells by); a name that is not
// registered is a programming error (std::logic_error naming it).
size_t column_id(std::string_view name);
const ColumnSpec& column_spec(size_t id);

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

// One row of results: one (method, params, height field, s, b, view, backend, precision or
// texture format). Its cells are named by the column registry (harness/metrics/columns.h):
// the keys (what ran) and the measured values (NaN / "" = empty), plus status and error.
#pragma once
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "harness/metrics/columns.h"

namespace pxh {

class ResultRow {
  public:
    ResultRow();  // status "ok", every other cell empty

    // A number (number or integer column) or a text (text column); a name that is not
    // registered, or of the other type, is a programming error (std::logic_error).
    void set(std::string_view column, double value);
    void set_text(std::string_view column, std::string value);
    double num(std::string_view column) const;               // NaN when empty
    const std::string& text(std::string_view column) const;  // "" when empty
    // The cell as results.csv writes it (numbers with round-trip precision, integers as
    // integers, "" when empty), whatever its type.
    std::string cell(size_t column_id) const;
    std::string cell(std::string_view column) const { return cell(column_id(column)); }

    bool ok() const { return text("status") == "ok"; }
    void fail(const std::string& message);  // status failed, error = message

  private:
    struct Cell {
        double num = NAN;
        std::string text;
    };
    std::vector<Cell> cells_;  // by column id
    const Cell* find(size_t id) const { return id < cells_.size() ? &cells_[id] : nullptr; }
    Cell& at(size_t id);
};

// A number as results.csv writes it: %.10g, inf / -inf, "" for NaN.
std::string format_cell_number(double v);

}  // namespace pxh

#include "harness/metrics/row.h"

#include <cstdio>
#include <stdexcept>

namespace pxh {
namespace {

// The column's id, checked to hold text (text = true) or numbers.
size_t typed(std::string_view column, bool text) {
    const size_t id = column_id(column);
    const ColumnSpec& c = column_spec(id);
    if ((c.type == ColumnType::text) != text)
        throw std::logic_error("results column '" + c.name + "' holds " +
                               (text ? "numbers" : "text") + ", not " +
                               (text ? "text" : "a number"));
    return id;
}

}  // namespace

std::string format_cell_number(double v) {
    if (std::isnan(v)) return "";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
}

ResultRow::ResultRow() { set_text("status", "ok"); }

ResultRow::Cell& ResultRow::at(size_t id) {
    if (id >= cells_.size()) cells_.resize(id + 1);
    return cells_[id];
}

void ResultRow::set(std::string_view column, double value) { at(typed(column, false)).num = value; }

void ResultRow::set_text(std::string_view column, std::string value) {
    at(typed(column, true)).text = std::move(value);
}

double ResultRow::num(std::string_view column) const {
    const Cell* c = find(typed(column, false));
    return c ? c->num : NAN;
}

const std::string& ResultRow::text(std::string_view column) const {
    static const std::string empty;
    const Cell* c = find(typed(column, true));
    return c ? c->text : empty;
}

std::string ResultRow::cell(size_t id) const {
    const ColumnSpec& spec = column_spec(id);
    const Cell* c = find(id);
    if (!c) return "";
    switch (spec.type) {
        case ColumnType::text:
            return c->text;
        case ColumnType::integer:
            return std::isfinite(c->num) ? std::to_string((long long)c->num)
                                         : format_cell_number(c->num);
        case ColumnType::number:
            break;
    }
    return format_cell_number(c->num);
}

void ResultRow::fail(const std::string& message) {
    set_text("status", "failed");
    set_text("error", message);
}

}  // namespace pxh

// A table described once and written as Markdown and LaTeX; number formats of the report.
#pragma once
#include <cmath>
#include <string>
#include <vector>

namespace pxh {

// Mean of the finite values.
struct Mean {
    double sum = 0;
    int n = 0;
    void add(double v) {
        if (std::isfinite(v)) {
            sum += v;
            ++n;
        }
    }
    double get() const { return n ? sum / n : NAN; }
};

// For tables: fixed decimals, "-" when missing.
std::string fmt(double v, int prec = 3);
// For the report's CSVs: a missing value is an empty cell, as in results.csv.
std::string csv_num(double v);
// A table cell in Markdown: one line, '|' escaped.
std::string md_cell(const std::string& s);
// Text (as written in the Markdown tables) for LaTeX text mode: TeX's special characters
// escaped, θ, <=, <, >, | and † as math.
std::string tex_text(const std::string& s);

struct TextTable {
    std::vector<std::string> header;
    std::string align;          // 'l' or 'r' per column
    std::string latex_columns;  // the tabular's column spec when not `align` (e.g. a p{} column)
    std::vector<std::vector<std::string>> rows;
    std::vector<std::string> notes;  // paragraphs under the table

    std::string markdown() const;
    std::string latex(const std::string& source) const;
};

}  // namespace pxh

// A results folder written by a test, cell by cell, and pxh report run on it in process without
// plots, and a Markdown table row read back: what the report-table suites build their cases from.
#pragma once
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "harness/report/report.h"
#include "harness/results/results.h"

namespace pxh::test {

// One row of a hand-written results.csv: column -> cell (a column it lacks is empty).
using Cells = std::map<std::string, std::string>;

// DIR/NAME/results.csv with these columns and rows (cells quoted as pxh writes them).
inline std::filesystem::path write_results_folder(const std::filesystem::path& dir,
                                                  const std::vector<std::string>& columns,
                                                  const std::vector<Cells>& rows,
                                                  const std::string& name = "res") {
    const std::filesystem::path res = dir / name;
    std::filesystem::create_directories(res);
    std::string text;
    for (size_t c = 0; c < columns.size(); ++c) text += (c ? "," : "") + columns[c];
    text += "\n";
    for (const auto& r : rows) {
        for (size_t c = 0; c < columns.size(); ++c) {
            auto it = r.find(columns[c]);
            text += (c ? "," : "") + csv_quote(it == r.end() ? "" : it->second);
        }
        text += "\n";
    }
    std::ofstream(res / "results.csv", std::ios::binary) << text;
    return res;
}

// pxh report RES without plots (its listing of the files swallowed); RES/report.
inline std::filesystem::path report_tables_of(const std::filesystem::path& res) {
    ReportOptions o;
    o.plots = false;
    testing::internal::CaptureStdout();
    run_report(res.string(), o);
    testing::internal::GetCapturedStdout();
    return res / "report";
}

// The cells after the first of the Markdown table row whose first cell is `first`; empty if
// there is none.
inline std::vector<std::string> markdown_row(const std::string& md, const std::string& first) {
    std::istringstream in(md);
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("| " + first + " |", 0) != 0) continue;
        std::vector<std::string> cells;
        size_t at = first.size() + 5;
        for (size_t bar; (bar = line.find(" |", at)) != std::string::npos; at = bar + 3)
            cells.push_back(line.substr(at, bar - at));
        return cells;
    }
    return {};
}

}  // namespace pxh::test

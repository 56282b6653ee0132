// The metric families of a run (harness/metrics/columns.h, ColumnSpec::family): each family
// present gets report/families/FAMILY.md and .csv (its headline columns per series and angle
// band) and data/families/FAMILY_vs_X.csv (per line, panel and x: θ and every numeric key of
// the run with three or more values), listed in data/families/index.csv for the plotter.
#pragma once
#include <string>
#include <vector>

namespace pxh {

struct ReportData;

// The families with a value in some ok row, in column order.
std::vector<std::string> family_names(const ReportData& d);
void write_families(const ReportData& d);

}  // namespace pxh

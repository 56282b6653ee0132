// results.csv: rows (harness/metrics/row.h) written in the registry's column order
// (harness/metrics/columns.cpp), and read back into typed rows once (pxh report, pxh check).
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "harness/metrics/row.h"

namespace pxh {

// A CSV field, quoted when it holds a comma, a quote or a newline (RFC 4180).
std::string csv_quote(const std::string& s);

// The header, and the rows in the registry's order (numbers with round-trip precision). A
// failed row (status != ok) has every measured column empty: a failure is never a number.
std::vector<std::string> result_columns();
std::string results_csv(const std::vector<ResultRow>& rows);

// results.csv read back: every registered column of the header parsed by its declared type
// (numbers as double, an empty cell NaN); columns of the registry absent from the file are
// empty, columns the registry does not know are kept only in `header`. A file written before
// the backends named their own timing (ns_per_sample*, ms_per_frame*) is read as time*, with
// time_unit ns/sample or ms/frame on the rows that have a value there. A cell of a numeric
// column that is not wholly a number is an InputError "PATH:LINE: column 'NAME': 'TEXT' is
// not a number"; a malformed CSV one naming PATH(:LINE).
struct ResultsFile {
    std::string path;
    std::vector<std::string> header;  // as in the file
    std::vector<ResultRow> rows;
    std::vector<size_t> lines;                  // the file line each row starts on (header: line 1)
    bool has(const std::string& column) const;  // in the header (time*: or its old name)
    std::string where(size_t row) const;        // "PATH:LINE"
};
ResultsFile read_results(const std::string& path);

// The same one row at a time (pxh compare streams results.csv through CsvReader): the registered
// column of each header name (nullptr for one the registry does not know), and one record as a
// typed row; a numeric cell that is not a number is the InputError above, at `where`.
std::vector<const ColumnSpec*> column_specs_of(const std::vector<std::string>& header);
ResultRow parse_result_row(const std::vector<const ColumnSpec*>& specs,
                           const std::vector<std::string>& fields, const std::string& where);

// How rows are named in tables and messages:
std::string setting_of(const ResultRow& r);  // method, parameters and a lod other than base:
                                             // "pom layers=8", "pom layers=8 lod=level"
std::string group_of(const ResultRow& r);    // backend/precision or format: "glsl/r32f"
std::string series_of(const ResultRow& r);   // "pom layers=8 [glsl/r32f]"
std::string field_of(const ResultRow& r);    // "fbm s=0.05 b=1"
// "pom layers=8 [glsl/r32f] on fbm s=0.05 b=1 theta=30 phi=0 distance=4 fov_deg=45": the
// series, the field and the row's other named axes (harness/metrics/columns.h, row_axes()).
// `cell` gives a column's cell, so a name can be made from a row or from the keys alone.
std::string row_name(const std::function<std::string(const std::string&)>& cell);
std::string row_name(const ResultRow& r);

}  // namespace pxh

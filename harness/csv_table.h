// Reading results.csv back: a table of named string columns (RFC 4180 quoting).
#pragma once
#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace pxh {

struct CsvTable {
    std::vector<std::string> columns;
    std::vector<std::vector<std::string>> rows;
    int index(const std::string& column) const;  // -1 when absent
    const std::string& get(size_t row, const std::string& column) const;
    double number(size_t row, const std::string& column) const;  // NaN when empty/absent
};

// Throws InputError(path, ...) on a missing or malformed file.
CsvTable read_csv(const std::string& path);

}  // namespace pxh

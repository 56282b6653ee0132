// Reading results.csv back: a table of named string columns (RFC 4180 quoting).
#pragma once
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace pxh {

struct CsvTable {
    std::string path;  // the file it was read from (for messages)
    std::vector<std::string> columns;
    std::vector<std::vector<std::string>> rows;
    std::vector<size_t> lines;  // the file line each row starts on (the header is line 1)
    int index(const std::string& column) const;  // -1 when absent
    const std::string& get(size_t row, const std::string& column) const;
    // The cell as a number: NaN when empty or the column is absent; "inf", "-inf" and "nan"
    // as pxh writes them. A cell that is not wholly a number ("0.5garbage", "0x0") is an
    // InputError naming PATH:LINE and the column.
    double number(size_t row, const std::string& column) const;
    std::string where(size_t row) const;  // "PATH:LINE" of a row
};

// The whole text as a number (decimal or scientific notation, inf, -inf, nan; no spaces, no
// hexadecimal); nullopt otherwise, and for an empty text.
std::optional<double> parse_number(const std::string& text);

// The contents of a regular file. Anything else (missing, a folder, a FIFO, a device) is an
// InputError naming the path, raised before opening it (a FIFO would block the read).
std::string read_regular_file(const std::string& path);

// Throws InputError(path, ...) on a missing, non-regular or malformed file.
CsvTable read_csv(const std::string& path);

}  // namespace pxh

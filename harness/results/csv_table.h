// Reading results.csv back: a table of named string columns (RFC 4180 quoting).
#pragma once
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "harness/core/params.h"  // parse_number

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

// The contents of a regular file. Anything else (missing, a folder, a FIFO, a device) is an
// InputError naming the path, raised before opening it (a FIFO would block the read).
std::string read_regular_file(const std::string& path);

// Throws InputError(path, ...) on a missing, non-regular or malformed file.
CsvTable read_csv(const std::string& path);

// The same file one record at a time (read_csv is built on it): memory independent of the
// number of rows (pxh compare streams its inputs). The constructor reads the header (an empty
// file, a missing or non-regular one is an InputError naming the path); next() the following
// records, each with exactly the header's number of fields (InputError "PATH:LINE: has N
// fields, the header M" otherwise, or "PATH: unterminated quoted field").
class CsvReader {
  public:
    explicit CsvReader(const std::string& path);
    ~CsvReader();
    CsvReader(const CsvReader&) = delete;
    CsvReader& operator=(const CsvReader&) = delete;
    const std::vector<std::string>& columns() const { return columns_; }
    bool next(std::vector<std::string>& fields);  // false at the end of the file
    size_t line() const { return start_; }        // the line the last record started on
    std::string where() const { return path_ + ":" + std::to_string(start_); }
    const std::string& path() const { return path_; }

  private:
    bool record(std::vector<std::string>& fields);  // any record, header included
    int get();
    std::string path_;
    std::vector<std::string> columns_;
    std::FILE* file_ = nullptr;
    size_t line_ = 1, start_ = 1;
};

}  // namespace pxh

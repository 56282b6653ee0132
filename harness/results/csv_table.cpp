#include "harness/results/csv_table.h"

#include <charconv>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "harness/core/error.h"

namespace pxh {

int CsvTable::index(const std::string& column) const {
    for (size_t i = 0; i < columns.size(); ++i)
        if (columns[i] == column) return int(i);
    return -1;
}

const std::string& CsvTable::get(size_t row, const std::string& column) const {
    static const std::string empty;
    const int i = index(column);
    return i < 0 || size_t(i) >= rows[row].size() ? empty : rows[row][size_t(i)];
}

std::string CsvTable::where(size_t row) const {
    return path + ":" + std::to_string(row < lines.size() ? lines[row] : row + 2);
}

double CsvTable::number(size_t row, const std::string& column) const {
    const std::string& s = get(row, column);
    if (s.empty()) return NAN;
    if (const auto v = parse_number(s)) return *v;
    throw InputError(where(row), "column '" + column + "': '" + s + "' is not a number");
}

std::optional<double> parse_number(const std::string& text) {
    double v = 0;
    const char* end = text.data() + text.size();
    // from_chars: no leading spaces or '+', no hexadecimal in the general format.
    const auto [ptr, ec] = std::from_chars(text.data(), end, v, std::chars_format::general);
    if (text.empty() || ec != std::errc() || ptr != end) return std::nullopt;
    return v;
}

std::string read_regular_file(const std::string& path) {
    std::error_code ec;
    const auto st = std::filesystem::status(path, ec);
    if (!std::filesystem::exists(st)) throw InputError(path, "cannot open: no such file");
    if (!std::filesystem::is_regular_file(st))
        throw InputError(path, "is not a regular file (a folder, FIFO or device is refused)");
    std::ifstream f(path, std::ios::binary);
    if (!f) throw InputError(path, "cannot open");
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

CsvTable read_csv(const std::string& path) {
    const std::string text = read_regular_file(path);
    std::vector<std::vector<std::string>> records;
    std::vector<size_t> starts;  // the line each record starts on
    std::vector<std::string> rec;
    std::string field;
    bool quoted = false, any = false;
    size_t line = 1, start = 1;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '\n') ++line;
        if (quoted) {
            if (c == '"') {
                if (i + 1 < text.size() && text[i + 1] == '"') {
                    field += '"';
                    ++i;
                } else quoted = false;
            } else {
                field += c;
            }
            continue;
        }
        if (c == '"') {
            quoted = true;
            any = true;
        } else if (c == ',') {
            rec.push_back(field);
            field.clear();
            any = true;
        } else if (c == '\n') {
            rec.push_back(field);
            records.push_back(rec);
            starts.push_back(start);
            start = line;
            rec.clear();
            field.clear();
            any = false;
        } else if (c != '\r') {
            field += c;
            any = true;
        }
    }
    if (quoted) throw InputError(path, "unterminated quoted field");
    if (any) {
        rec.push_back(field);
        records.push_back(rec);
        starts.push_back(start);
    }
    if (records.empty()) throw InputError(path, "empty file");
    CsvTable t;
    t.path = path;
    t.columns = records[0];
    for (size_t r = 1; r < records.size(); ++r) {
        if (records[r].size() != t.columns.size())
            throw InputError(path + ":" + std::to_string(starts[r]),
                             "has " + std::to_string(records[r].size()) + " fields, the header " +
                                 std::to_string(t.columns.size()));
        t.rows.push_back(std::move(records[r]));
        t.lines.push_back(starts[r]);
    }
    return t;
}

}  // namespace pxh

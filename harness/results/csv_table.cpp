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

CsvReader::CsvReader(const std::string& path) : path_(path) {
    std::error_code ec;
    const auto st = std::filesystem::status(path, ec);
    if (!std::filesystem::exists(st)) throw InputError(path, "cannot open: no such file");
    if (!std::filesystem::is_regular_file(st))
        throw InputError(path, "is not a regular file (a folder, FIFO or device is refused)");
    file_ = std::fopen(path.c_str(), "rb");
    if (!file_) throw InputError(path, "cannot open");
    if (!record(columns_)) throw InputError(path, "empty file");
}

CsvReader::~CsvReader() {
    if (file_) std::fclose(file_);
}

int CsvReader::get() { return getc_unlocked(file_); }  // one reader per FILE

// One record: fields separated by commas, ended by a newline or the end of the file, quoted
// fields as RFC 4180 ("" a quote), CR outside quotes dropped. False when nothing is left.
bool CsvReader::record(std::vector<std::string>& fields) {
    fields.clear();
    std::string field;
    bool quoted = false, any = false;
    start_ = line_;
    for (int ch = get(); ch != EOF; ch = get()) {
        const char c = char(ch);
        if (c == '\n') ++line_;
        if (quoted) {
            if (c == '"') {
                const int after = get();
                if (after == '"') {
                    field += '"';
                } else {
                    quoted = false;
                    if (after != EOF) std::ungetc(after, file_);
                }
            } else {
                field += c;
            }
            continue;
        }
        if (c == '"') {
            quoted = true;
            any = true;
        } else if (c == ',') {
            fields.push_back(std::move(field));
            field.clear();
            any = true;
        } else if (c == '\n') {
            fields.push_back(std::move(field));
            return true;
        } else if (c != '\r') {
            field += c;
            any = true;
        }
    }
    if (std::ferror(file_)) throw InputError(path_, "read error");
    if (quoted) throw InputError(path_, "unterminated quoted field");
    if (!any) return false;
    fields.push_back(std::move(field));
    return true;
}

bool CsvReader::next(std::vector<std::string>& fields) {
    if (!record(fields)) return false;
    if (fields.size() != columns_.size())
        throw InputError(where(), "has " + std::to_string(fields.size()) + " fields, the header " +
                                      std::to_string(columns_.size()));
    return true;
}

CsvTable read_csv(const std::string& path) {
    CsvReader in(path);
    CsvTable t;
    t.path = path;
    t.columns = in.columns();
    std::vector<std::string> rec;
    while (in.next(rec)) {
        t.rows.push_back(rec);
        t.lines.push_back(in.line());
    }
    return t;
}

}  // namespace pxh

#include "harness/csv_table.h"

#include <fstream>
#include <sstream>

#include "harness/error.h"

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

double CsvTable::number(size_t row, const std::string& column) const {
    const std::string& s = get(row, column);
    if (s.empty()) return NAN;
    try {
        return std::stod(s);
    } catch (...) {
        return NAN;
    }
}

CsvTable read_csv(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw InputError(path, "cannot open (no results.csv here?)");
    std::stringstream ss;
    ss << f.rdbuf();
    const std::string text = ss.str();
    std::vector<std::vector<std::string>> records;
    std::vector<std::string> rec;
    std::string field;
    bool quoted = false, any = false;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (quoted) {
            if (c == '"') {
                if (i + 1 < text.size() && text[i + 1] == '"') { field += '"'; ++i; }
                else quoted = false;
            } else {
                field += c;
            }
            continue;
        }
        if (c == '"') { quoted = true; any = true; }
        else if (c == ',') { rec.push_back(field); field.clear(); any = true; }
        else if (c == '\n') {
            rec.push_back(field);
            records.push_back(rec);
            rec.clear();
            field.clear();
            any = false;
        } else if (c != '\r') { field += c; any = true; }
    }
    if (quoted) throw InputError(path, "unterminated quoted field");
    if (any) { rec.push_back(field); records.push_back(rec); }
    if (records.empty()) throw InputError(path, "empty file");
    CsvTable t;
    t.columns = records[0];
    for (size_t r = 1; r < records.size(); ++r) {
        if (records[r].size() != t.columns.size())
            throw InputError(path + ":" + std::to_string(r + 1),
                             "has " + std::to_string(records[r].size()) + " fields, the header " +
                                 std::to_string(t.columns.size()));
        t.rows.push_back(std::move(records[r]));
    }
    return t;
}

}  // namespace pxh

#include "harness/core/limits.h"

#include <cctype>
#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>

#include "harness/core/error.h"

namespace pxh {

size_t parse_bytes(const std::string& text, const std::string& where) {
    size_t used = 0;
    double v = 0;
    try {
        v = std::stod(text, &used);
    } catch (...) {
        used = 0;
    }
    std::string unit = text.substr(used);
    for (auto& c : unit) c = char(std::toupper((unsigned char)c));
    if (!unit.empty() && unit.back() == 'B') unit.pop_back();
    if (unit.size() == 2 && unit[1] == 'I') unit.pop_back();  // GiB, MiB
    const std::map<std::string, double> mult = {
        {"", 1.0}, {"K", 1024.0}, {"M", 1048576.0}, {"G", 1073741824.0}, {"T", 1099511627776.0}};
    if (used == 0 || !mult.count(unit) || !(v > 0) || !std::isfinite(v * mult.at(unit)) ||
        v * mult.at(unit) > 1e18)
        throw InputError(where, "'" + text + "' is not a size (e.g. 512M, 8G)");
    return size_t(v * mult.at(unit));
}

std::string format_bytes(size_t bytes) {
    std::ostringstream os;
    os << std::fixed;
    if (bytes < (size_t(1) << 30))
        os << std::setprecision(1) << double(bytes) / double(1 << 20) << " MiB";
    else os << std::setprecision(1) << double(bytes) / double(size_t(1) << 30) << " GiB";
    return os.str();
}

}  // namespace pxh

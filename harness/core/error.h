// Errors: InputError is bad user input (exit status 2), always naming the file at fault.
#pragma once
#include <stdexcept>
#include <string>

namespace pxh {

// The message on one line: control characters (a newline quoted from the input, ...) are
// written as escapes (\n, \r, \t, \xNN), so an error is always exactly one line.
inline std::string one_line(const std::string& s) {
    static const char* hex = "0123456789abcdef";
    std::string out;
    for (unsigned char c : s) {
        if (c == '\n') out += "\\n";
        else if (c == '\r') out += "\\r";
        else if (c == '\t') out += "\\t";
        else if (c < 0x20 || c == 0x7f) out += std::string("\\x") + hex[c >> 4] + hex[c & 15];
        else out += char(c);
    }
    return out;
}

class InputError : public std::runtime_error {
  public:
    InputError(const std::string& where, const std::string& what)
        : std::runtime_error(one_line(where.empty() ? what : where + ": " + what)) {}
};

}  // namespace pxh

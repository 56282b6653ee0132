// Errors: InputError is bad user input (exit status 2), always naming the file at fault.
#pragma once
#include <stdexcept>
#include <string>

namespace pxh {

class InputError : public std::runtime_error {
  public:
    InputError(const std::string& where, const std::string& what)
        : std::runtime_error(where.empty() ? what : where + ": " + what) {}
};

}  // namespace pxh

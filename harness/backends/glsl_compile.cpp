// The GLSL backend's shader compilation: a shader compiled, and the driver's log (Mesa's
// "S:L(C): " locations) mapped to the files the program was compiled from.
#include <glad/gl.h>

#include <algorithm>
#include <cctype>
#include <sstream>

#include "harness/backends/glsl_backend.h"
#include "harness/backends/glsl_parts.h"

namespace pxh::glsl_detail {

std::string raw_log(unsigned object, bool program) {
    GLint len = 0;
    (program ? glGetProgramiv : glGetShaderiv)(object, GL_INFO_LOG_LENGTH, &len);
    std::string log(size_t(std::max(len, 1)), '\0');
    (program ? glGetProgramInfoLog : glGetShaderInfoLog)(object, len, nullptr, log.data());
    return log.c_str();
}

std::vector<std::string> located(const std::string& log, const std::map<int, std::string>& files,
                                 const BodyLines& body) {
    std::vector<std::string> out;
    std::istringstream in(log);
    std::string line;
    while (std::getline(in, line)) {
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
        if (line.empty()) continue;
        size_t i = 0;
        auto number = [&](long& v) {
            const size_t start = i;
            v = 0;
            while (i < line.size() && std::isdigit(static_cast<unsigned char>(line[i])) &&
                   i < 9 + start)
                v = v * 10 + (line[i++] - '0');
            return i > start;
        };
        long src = 0, ln = 0, col = 0;
        bool ok = number(src) && i < line.size() && line[i++] == ':' && number(ln);
        if (ok && i < line.size() && line[i] == '(') {
            ++i;
            ok = number(col) && i < line.size() && line[i++] == ')';
        }
        ok = ok && i < line.size() && line[i++] == ':';
        if (ln > kBodyLine) {  // the method's file, whatever string number Mesa gives
            // k > 0: a plug-in's k-th other file (an include, pxh's engine adapter), numbered
            // from kBodyLine (k + 1) + 1 (harness/backends/engine_shader.h).
            const long k = ln / kBodyLine - 1;
            src = 2 + k;
            ln = k == 0 ? body.file_line(ln - kBodyLine) : ln - (k + 1) * kBodyLine;
        } else if (src == 0) {
            src = 1;
        }
        const auto f = files.find(int(src));
        if (!ok || f == files.end()) {
            out.push_back(line);
            continue;
        }
        while (i < line.size() && line[i] == ' ') ++i;
        out.push_back(f->second + ":" + std::to_string(ln) +
                      (col > 0 ? ":" + std::to_string(col) : "") + ": " + line.substr(i));
    }
    if (out.empty()) out.push_back("(the driver gave no log)");
    return out;
}

std::string joined(const std::vector<std::string>& lines) {
    std::string s;
    for (const auto& l : lines) s += (s.empty() ? "" : "; ") + l;
    return s;
}

unsigned compile(unsigned type, const std::string& src, const std::string& what,
                 const std::map<int, std::string>& files, const BodyLines& body) {
    const GLuint sh = glCreateShader(type);
    const char* p = src.c_str();
    glShaderSource(sh, 1, &p, nullptr);
    glCompileShader(sh);
    GLint ok = 0;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        std::vector<std::string> lines = located(raw_log(sh, false), files, body);
        glDeleteShader(sh);
        // Errors only, when the log has any (Mesa's warnings would bury them).
        std::vector<std::string> errors;
        for (const auto& l : lines)
            if (l.find("error") != std::string::npos) errors.push_back(l);
        if (!errors.empty()) lines = errors;
        throw GlslProgramError(what + ": shader compile failed: " + joined(lines), lines);
    }
    return sh;
}

}  // namespace pxh::glsl_detail

#include "harness/backends/shaders.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace pxh {

ShaderSource shader_file_source(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw std::runtime_error(path + ": cannot read the shader file");
    std::stringstream ss;
    ss << f.rdbuf();
    return {ss.str(), path};
}

std::string with_declarations(const std::string& text, const std::string& declarations,
                              const std::string& path, long& line) {
    const std::string marker = kDeclarationsLine;
    line = 1;
    for (size_t start = 0; start < text.size(); ++line) {
        size_t end = text.find('\n', start);
        end = end == std::string::npos ? text.size() : end + 1;
        if (text.compare(start, marker.size(), marker) == 0)
            return text.substr(0, start) + declarations + text.substr(end);
        start = end;
    }
    throw std::runtime_error(path + ": no '" + marker +
                             "' line for the method's generated declarations");
}

ShaderSource shader_source(const std::string& path, const std::string& override_dir,
                           const char* builtin_text) {
    namespace fs = std::filesystem;
    if (!override_dir.empty()) {
        for (const fs::path& p :
             {fs::path(override_dir) / path, fs::path(override_dir) / fs::path(path).filename()}) {
            std::error_code ec;
            if (fs::is_regular_file(p, ec)) {
                std::ifstream f(p, std::ios::binary);
                std::stringstream ss;
                ss << f.rdbuf();
                if (!f && !f.eof()) throw std::runtime_error(p.string() + ": cannot read");
                return {ss.str(), fs::absolute(p).lexically_normal().string()};
            }
        }
    }
    if (builtin_text) return {builtin_text, "builtin"};
    for (const auto& s : embedded_shaders())
        if (path == s.path) return {s.source, "builtin"};
    throw std::runtime_error(path + ": no such shader (no GLSL implementation)");
}

}  // namespace pxh

#include "harness/backends/plugin_source.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include "harness/core/error.h"
#include "harness/core/safe_files.h"

namespace pxh {
namespace {

namespace fs = std::filesystem;

struct Token {
    std::string text;
    int line = 1, col = 1;
};

bool ident_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool ident_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// GLSL tokens without comments: identifiers, numbers, and punctuation (one character each,
// except "##"), each with its 1-based line and byte column.
std::vector<Token> tokens(const std::string& s) {
    std::vector<Token> out;
    int line = 1, col = 1;
    size_t i = 0;
    auto advance = [&](size_t n) {
        for (size_t k = 0; k < n && i < s.size(); ++k, ++i) {
            if (s[i] == '\n') {
                ++line;
                col = 1;
            } else {
                ++col;
            }
        }
    };
    while (i < s.size()) {
        const char c = s[i];
        if (c == '/' && i + 1 < s.size() && s[i + 1] == '/') {
            while (i < s.size() && s[i] != '\n') advance(1);
        } else if (c == '/' && i + 1 < s.size() && s[i + 1] == '*') {
            advance(2);
            while (i < s.size() && !(s[i] == '*' && i + 1 < s.size() && s[i + 1] == '/'))
                advance(1);
            advance(2);
        } else if (std::isspace(static_cast<unsigned char>(c))) {
            advance(1);
        } else if (ident_start(c) || std::isdigit(static_cast<unsigned char>(c))) {
            Token t{"", line, col};
            size_t j = i;
            while (j < s.size() && (ident_char(s[j]) || (!ident_start(c) && s[j] == '.'))) ++j;
            t.text = s.substr(i, j - i);
            advance(j - i);
            out.push_back(std::move(t));
        } else if (c == '#' && i + 1 < s.size() && s[i + 1] == '#') {
            out.push_back({"##", line, col});
            advance(2);
        } else {
            out.push_back({std::string(1, c), line, col});
            advance(1);
        }
    }
    return out;
}

// What a shader may not name, and why.
const std::map<std::string, std::string>& forbidden_names() {
    static const std::map<std::string, std::string> m = {
        {"u_height",
         "is pxh's height texture: read heights with pxh_height(uv) or pxh_z(uv), which count "
         "the fetch (a shader that samples it around them is refused)"},
        {"u_view_map",
         "is pxh's per-sample view map (the height texture is bound to it when a view has no "
         "map): read the view direction as pxh_V"},
        {"pxh_fetches",
         "is pxh's fetch counter: a shader may not read or write it (pxh_height, pxh_z and "
         "pxh_texture count every fetch)"},
        {"pxh_out_uv", "is pxh's output: return the uv from pxh_method"},
        {"pxh_out_shadow", "is pxh's output: pxh computes the shadow factors itself"},
    };
    return m;
}

}  // namespace

std::string shader_text_problem(const std::string& s) {
    // The first NUL byte or invalid UTF-8 sequence (harness/core/safe_files.h decides which
    // sequences are valid), as "LINE:COL" with COL counted in characters, as editors do.
    const size_t nul = s.find('\0');
    const size_t bad_utf8 = invalid_utf8_at(s);
    const size_t at = std::min(nul, bad_utf8);
    if (at == std::string::npos) return "";
    size_t line = 1, col = 1;
    for (size_t k = 0; k < at; ++k) {
        if (s[k] == '\n') ++line, col = 1;
        else if ((static_cast<unsigned char>(s[k]) & 0xC0) != 0x80) ++col;
    }
    const std::string where = std::to_string(line) + ":" + std::to_string(col) + ": ";
    if (at == nul) return where + "a NUL byte: a shader must be text";
    char hex[8];
    std::snprintf(hex, sizeof hex, "0x%02X", unsigned(static_cast<unsigned char>(s[at])));
    return where + "byte " + hex + " is not UTF-8 (the file must be UTF-8 text)";
}

PluginSource read_plugin_source(const std::string& experiment_path, const std::string& rel,
                                const std::string& where) {
    const std::string what = "shader '" + rel + "'";
    const std::string rule =
        "a plug-in shader is a file inside the experiment's folder, named relative to it";
    if (rel.empty()) throw InputError(where, "shader = \"\" names no file");
    const fs::path rp(rel);
    if (rp.is_absolute()) throw InputError(where, what + ": an absolute path; " + rule);
    fs::path folder = fs::path(experiment_path).parent_path();
    if (folder.empty()) folder = ".";
    std::error_code ec;
    const fs::path base = fs::canonical(folder, ec);
    if (ec) throw InputError(where, what + ": cannot resolve the experiment's folder");
    const fs::path target = folder / rp;
    const fs::path display = target.lexically_normal();
    if (!fs::exists(fs::symlink_status(target, ec)))
        throw InputError(where, what + ": no such file (" + display.string() +
                                    "; paths are relative to the experiment file)");
    const fs::path canon = fs::canonical(target, ec);
    if (ec)
        throw InputError(where, what + ": cannot be resolved (" + display.string() +
                                    ": a symbolic link to nothing?)");
    const fs::path inside = canon.lexically_relative(base);
    if (inside.empty() || *inside.begin() == "..")
        throw InputError(where, what +
                                    ": lies outside the experiment's folder once links are "
                                    "resolved (" +
                                    canon.string() + "); " + rule);
    const fs::file_status st = fs::status(canon, ec);
    if (fs::is_directory(st)) throw InputError(where, what + ": is a directory, not a file");
    if (!fs::is_regular_file(st))
        throw InputError(where, what + ": not a regular file (a FIFO, socket or device?)");
    // Opened without following a link swapped in since, and without blocking on a FIFO.
    const int fd = ::open(canon.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) throw InputError(where, what + ": cannot open " + canon.string());
    struct stat sb {};
    if (fstat(fd, &sb) != 0 || !S_ISREG(sb.st_mode)) {
        ::close(fd);
        throw InputError(where, what + ": not a regular file");
    }
    if (size_t(sb.st_size) > kMaxPluginShaderBytes) {
        ::close(fd);
        throw InputError(where, what + ": " + std::to_string(sb.st_size) +
                                    " bytes; a plug-in shader is at most " +
                                    std::to_string(kMaxPluginShaderBytes) + " bytes (1 MiB)");
    }
    PluginSource out;
    std::string buf(kMaxPluginShaderBytes + 1, '\0');
    size_t got = 0;
    while (got < buf.size()) {
        const ssize_t r = ::read(fd, buf.data() + got, buf.size() - got);
        if (r < 0) {
            ::close(fd);
            throw InputError(where, what + ": cannot read " + canon.string());
        }
        if (r == 0) break;
        got += size_t(r);
    }
    ::close(fd);
    if (got > kMaxPluginShaderBytes)
        throw InputError(where, what + ": grew past " + std::to_string(kMaxPluginShaderBytes) +
                                    " bytes while being read");
    buf.resize(got);
    if (const std::string why = shader_text_problem(buf); !why.empty()) {
        const size_t colon = why.find(": ");  // "LINE:COL: why"
        throw InputError(display.string() + ":" + why.substr(0, colon), why.substr(colon + 2));
    }
    out.text = std::move(buf);
    out.resolved = canon.string();
    out.display = display.string();
    return out;
}

std::string uniform_declaration(const std::string& text, const std::string& name) {
    const std::vector<Token> t = tokens(text);
    for (size_t i = 0; i + 2 < t.size(); ++i)
        if (t[i].text == "uniform")
            for (size_t j = i + 1; j < t.size() && j <= i + 3; ++j)
                if (t[j].text == name)
                    return std::to_string(t[j].line) + ":" + std::to_string(t[j].col);
    return "";
}

std::string identifier_position(const std::string& text, const std::string& name) {
    for (const Token& k : tokens(text))
        if (k.text == name) return std::to_string(k.line) + ":" + std::to_string(k.col);
    return "";
}

std::vector<std::string> common_uniform_names(const std::string& common) {
    std::vector<std::string> out;
    const std::vector<Token> t = tokens(common);
    for (size_t i = 0; i + 2 < t.size(); ++i)
        if (t[i].text == "uniform" && ident_start(t[i + 2].text[0])) out.push_back(t[i + 2].text);
    return out;
}

std::vector<std::string> plugin_source_problems(const std::string& display, const std::string& text,
                                                const std::string& common) {
    std::vector<std::string> out;
    const std::vector<std::string> reserved_list = common_uniform_names(common);
    const std::set<std::string> reserved(reserved_list.begin(), reserved_list.end());
    const std::vector<Token> t = tokens(text);
    auto at = [&](const Token& k) {
        return display + ":" + std::to_string(k.line) + ":" + std::to_string(k.col) + ": ";
    };
    std::set<std::string> said;  // one line per name (its first use)
    for (size_t i = 0; i < t.size(); ++i) {
        const Token& k = t[i];
        if (k.text == "##") {
            if (said.insert("##").second)
                out.push_back(at(k) +
                              "token pasting (##) is refused in plug-in shaders (it could spell "
                              "one of pxh's reserved names)");
            continue;
        }
        if (const auto f = forbidden_names().find(k.text); f != forbidden_names().end()) {
            if (said.insert(k.text).second) out.push_back(at(k) + "'" + k.text + "' " + f->second);
            continue;
        }
        if (k.text != "uniform") continue;
        size_t j = i + 1;
        while (j < t.size() &&
               (t[j].text == "lowp" || t[j].text == "mediump" || t[j].text == "highp"))
            ++j;
        if (j + 1 >= t.size()) continue;
        const Token& name = t[j + 1];
        if (!reserved.count(name.text) || !said.insert(name.text).second) continue;
        if (name.text.rfind("p_", 0) == 0)
            out.push_back(at(name) + "'" + name.text +
                          "' is a reserved name: methods/common.glsl declares it (a uniform of "
                          "its layer search, pxh_layer_search); do not declare it, give its "
                          "value in the entry's uniforms (" +
                          name.text +
                          " = ...), or call pxh_layer_search_n(P, n), which needs none");
        else
            out.push_back(at(name) + "'" + name.text +
                          "' is a reserved name: methods/common.glsl declares it and pxh sets "
                          "it; use it without declaring it");
    }
    return out;
}

}  // namespace pxh

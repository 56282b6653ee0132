// A converter's GLSL of a whole fragment shader (SPIRV-Cross's, naga's) made a plug-in's text:
// converted_shader.h, converted_plugin_glsl.
#include <map>
#include <vector>

#include "harness/backends/converted_shader.h"
#include "harness/core/error.h"

namespace pxh {
namespace {

using Toks = std::vector<ShaderToken>;

bool ident(const std::string& s) {
    return !s.empty() && (std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_');
}

// The index of the token that closes the bracket opened at `open`.
size_t closing(const Toks& t, size_t open) {
    const std::string o = t[open].text, c = o == "(" ? ")" : o == "{" ? "}" : "]";
    int depth = 0;
    for (size_t i = open; i < t.size(); ++i) {
        if (t[i].text == o) ++depth;
        if (t[i].text == c && --depth == 0) return i;
    }
    return t.size() - 1;
}

// A top-level item of the text: a declaration ending at ';' or a function with its body.
struct Item {
    size_t first = 0, last = 0;  // tokens
    bool function = false;
    std::string name;  // the function's name
};

std::vector<Item> items(const Toks& t) {
    std::vector<Item> out;
    size_t i = 0;
    while (i < t.size()) {
        Item it;
        it.first = i;
        size_t j = i;
        while (j < t.size()) {
            if (t[j].text == "(" || t[j].text == "[") {
                const size_t c = closing(t, j);
                if (t[j].text == "(" && c + 1 < t.size() && t[c + 1].text == "{" && j > i) {
                    it.function = true;
                    it.name = t[j - 1].text;
                    j = closing(t, c + 1);
                    break;
                }
                j = c + 1;
                continue;
            }
            if (t[j].text == "{") {
                j = closing(t, j) + 1;
                continue;
            }
            if (t[j].text == ";") break;
            ++j;
        }
        it.last = std::min(j, t.size() - 1);
        out.push_back(it);
        i = it.last + 1;
    }
    return out;
}

bool has(const Toks& t, const Item& it, const std::string& s) {
    for (size_t i = it.first; i <= it.last; ++i)
        if (t[i].text == s) return true;
    return false;
}

// `TYPE NAME ;` members between the braces at `open`: (type, name).
std::vector<std::pair<std::string, std::string>> members(const Toks& t, size_t open) {
    std::vector<std::pair<std::string, std::string>> out;
    const size_t close = closing(t, open);
    for (size_t i = open + 1; i + 2 <= close; ++i)
        if (ident(t[i].text) && ident(t[i + 1].text) && t[i + 2].text == ";")
            out.emplace_back(t[i].text, t[i + 1].text);
    return out;
}

// The directives SPIRV-Cross writes before the code: dropped (its loop attributes become empty
// macros); any extension is refused.
std::string without_directives(const std::string& glsl, const std::string& display) {
    std::string out;
    size_t start = 0;
    bool in_attributes = false;
    while (start < glsl.size()) {
        size_t end = glsl.find('\n', start);
        if (end == std::string::npos) end = glsl.size();
        const std::string line = glsl.substr(start, end - start);
        start = end + 1;
        if (line.rfind("#if defined(GL_EXT_control_flow_attributes)", 0) == 0) {
            in_attributes = true;
            continue;
        }
        if (in_attributes) {
            in_attributes = line.rfind("#endif", 0) != 0;
            continue;
        }
        if (line.rfind("#version", 0) == 0) continue;
        if (line.rfind("#extension", 0) == 0 || line.rfind("#error", 0) == 0)
            throw InputError(display, "the converted GLSL needs what pxh's GLSL 4.50 lacks (`" +
                                          line +
                                          "`; 16-bit types?): write the shader with 32-bit types");
        out += line + "\n";
    }
    return out;
}

// The blank lines left by what was removed, squeezed to one.
std::string squeezed(const std::string& body) {
    std::string out;
    int blank = 0;
    size_t s = 0;
    while (s < body.size()) {
        size_t e = body.find('\n', s);
        if (e == std::string::npos) e = body.size();
        const std::string line = body.substr(s, e - s);
        blank = line.find_first_not_of(" \t") == std::string::npos ? blank + 1 : 0;
        if (blank <= 1) out += line + "\n";
        s = e + 1;
    }
    return out;
}

}  // namespace

size_t next_argument(const std::vector<ShaderToken>& t, size_t i) {
    int depth = 0;
    for (; i < t.size(); ++i) {
        const std::string& x = t[i].text;
        if (x == "(" || x == "[") ++depth;
        if ((x == ")" || x == "]") && --depth < 0) return std::string::npos;
        if (x == "," && depth == 0) return i;
    }
    return std::string::npos;
}

bool literal_level_zero(const std::vector<ShaderToken>& t, size_t c) {
    const size_t uv_end = next_argument(t, c + 1);
    if (uv_end == std::string::npos || uv_end + 2 >= t.size() || t[uv_end + 2].text != ")")
        return false;
    const std::string& x = t[uv_end + 1].text;
    return x.find_first_not_of("0.f") == std::string::npos && x.find('0') != std::string::npos;
}

std::string converted_plugin_glsl(const std::string& glsl_in, const std::string& display,
                                  const std::set<std::string>& stand_ins,
                                  const std::set<std::string>& bools) {
    const std::string glsl = without_directives(glsl_in, display);
    const Toks t = shader_tokens(glsl);
    std::map<std::string, std::vector<std::pair<std::string, std::string>>> structs;
    std::map<std::string, std::string> access;    // "inst.member[.field]" -> its replacement
    std::map<std::string, std::string> declared;  // plain uniform -> its type
    std::vector<bool> drop(t.size(), false);
    // A block member as a plain uniform: a uint (SPIR-V's bool, WGSL's u32) is declared bool
    // when `bools` names it, else int (pxh sets float, int and bool uniforms), and read as uint.
    auto declare = [&](const std::string& prefix, const std::string& type, const std::string& n) {
        const bool u = type == "uint";
        access[prefix + n] = u ? "uint(" + n + ")" : n;
        declared[n] = !u ? type : bools.count(n) ? "bool" : "int";
    };
    for (const Item& it : items(t)) {
        auto drop_item = [&] {
            for (size_t i = it.first; i <= it.last; ++i) drop[i] = true;
        };
        const std::string& first = t[it.first].text;
        if (it.function) {
            if (it.name == "main" || it.name == "_main" || stand_ins.count(it.name)) drop_item();
            continue;
        }
        if (it.first + 1 <= it.last && stand_ins.count(t[it.first + 1].text)) {
            drop_item();  // a stand-in variable (WGSL's pxh_V, u_scale, ...)
            continue;
        }
        if (first == "struct" && it.first + 2 < t.size() && t[it.first + 2].text == "{") {
            structs[t[it.first + 1].text] = members(t, it.first + 2);
            continue;
        }
        if (has(t, it, "in") || has(t, it, "out")) {
            drop_item();
            continue;
        }
        if (!has(t, it, "uniform") || !has(t, it, "{")) continue;
        size_t open = it.first;
        while (t[open].text != "{") ++open;
        const size_t close = closing(t, open);
        const std::string inst = close + 1 < it.last ? t[close + 1].text + "." : "";
        for (const auto& [type, name] : members(t, open)) {
            if (const auto s = structs.find(type); s != structs.end()) {
                for (const auto& [ftype, field] : s->second)
                    declare(inst + name + ".", ftype, field);
                continue;
            }
            declare(inst, type, name);
        }
        drop_item();
    }
    // The text without the dropped items, each access to a block's member made the plain name.
    std::string body;
    size_t copied = 0;
    for (size_t i = 0; i < t.size(); ++i) {
        if (drop[i]) {
            body += glsl.substr(copied, t[i].begin - copied);
            copied = t[i].end;
            continue;
        }
        if (!ident(t[i].text) || (i > 0 && t[i - 1].text == ".")) continue;
        std::string path = t[i].text, best;
        size_t best_end = i, k = i;
        while (true) {
            if (access.count(path)) {
                best = path;
                best_end = k;
            }
            if (k + 2 < t.size() && t[k + 1].text == "." && ident(t[k + 2].text)) {
                path += "." + t[k + 2].text;
                k += 2;
            } else {
                break;
            }
        }
        if (best.empty()) continue;
        body += glsl.substr(copied, t[i].begin - copied) + access[best];
        copied = t[best_end].end;
        i = best_end;
    }
    body += glsl.substr(copied);
    std::string out =
        "#define SPIRV_CROSS_FLATTEN\n#define SPIRV_CROSS_BRANCH\n#define SPIRV_CROSS_UNROLL\n"
        "#define SPIRV_CROSS_LOOP\n";
    for (const auto& [name, type] : declared)
        out += "uniform " + type + " " + name + ";\n";  // read or not (as a GLSL text declares)
    out +=
        "vec3 pxh_hlsl_V() { return pxh_V; }\nfloat pxh_hlsl_scale() { return u_scale; }\n"
        "float pxh_hlsl_bias() { return u_bias; }\nivec2 pxh_hlsl_size() { return u_size; }\n";
    return out + squeezed(body);
}

}  // namespace pxh

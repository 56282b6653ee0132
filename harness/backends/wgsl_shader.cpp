// WGSL plug-ins: naga (npm naga-wasm, pinned in tools/naga/package.json, run by node through
// tools/naga/wgsl_to_glsl.mjs) translates the file and pxh's methods/common.wgsl after it to
// GLSL 4.50; the stand-ins are removed as for HLSL (converted_shader.h). naga_oil's directives
// (Bevy's #define_import_path, #import, #ifdef) are read first, modules joined in.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <regex>

#include "harness/backends/converted_shader.h"
#include "harness/backends/plugin_source.h"
#include "harness/backends/shaders.h"
#include "harness/backends/tool_process.h"
#include "harness/core/error.h"

namespace pxh {
namespace {

using Toks = std::vector<ShaderToken>;

constexpr const char* kPrelude = "methods/common.wgsl";

std::string at(const std::string& display, const ShaderToken& t) {
    return display + ":" + std::to_string(t.line) + ":" + std::to_string(t.col);
}

// WGSL's sampling built-ins on the height texture: textureSample(t, s, uv),
// textureSampleBias(t, s, uv, bias), textureSampleLevel(t, s, uv, level),
// textureSampleGrad(t, s, uv, ddx, ddy).
const std::map<std::string, std::pair<const char*, bool>>& sampling_calls() {
    static const std::map<std::string, std::pair<const char*, bool>> m = {
        {"textureSample", {"pxh_engine_height(", false}},
        {"textureSampleBias", {"pxh_engine_height_bias(", false}},
        {"textureSampleLevel", {"pxh_engine_height_lod(", true}},
        {"textureSampleGrad", {"pxh_engine_height_grad(", false}}};
    return m;
}

// The text with every sampling call on the height texture made pxh's counted call (same lines),
// anything else done with the texture refused; `level`: the first explicit level.
std::string rewrite(const std::string& text, const std::string& display, const std::string& tex,
                    std::string& level) {
    const Toks t = shader_tokens(text);
    for (size_t i = 0; i + 2 < t.size(); ++i)
        if ((sampling_calls().count(t[i].text) || t[i].text == "textureLoad" ||
             t[i].text == "textureGather") &&
            t[i + 1].text == "(" && t[i + 2].text != tex)
            throw InputError(at(display, t[i]),
                             "texture '" + t[i + 2].text +
                                 "' is sampled here, and pxh binds no texture but the height "
                                 "map: if it is the engine's height texture, name it in the "
                                 "entry (height_sampler = \"" +
                                 t[i + 2].text + "\")");
    if (tex.empty()) return text;
    std::string out;
    size_t copied = 0;
    for (size_t i = 0; i < t.size(); ++i) {
        const auto c = sampling_calls().find(t[i].text);
        if (c != sampling_calls().end() && i + 3 < t.size() && t[i + 1].text == "(" &&
            t[i + 2].text == tex && t[i + 3].text == ",") {
            const size_t comma = next_argument(t, i + 4);
            if (comma == std::string::npos) continue;
            if (c->second.second && level.empty() && !literal_level_zero(t, comma))
                level = at(display, t[i]) + ": " + t[i].text;
            out += text.substr(copied, t[i].begin - copied) + c->second.first;
            copied = t[comma].end;
            i = comma;
            continue;
        }
        const bool declaration = i > 0 && t[i - 1].text == "var";
        if (t[i].text == tex && !declaration)
            throw InputError(at(display, t[i]),
                             "the height texture '" + tex +
                                 "' is used here other than as the first argument of a "
                                 "sampling call pxh counts (textureSample, textureSampleBias, "
                                 "textureSampleLevel, textureSampleGrad)");
    }
    return out + text.substr(copied);
}

// The prelude's functions and private variables: removed from naga's GLSL.
std::set<std::string> stand_ins(const std::string& prelude) {
    std::set<std::string> out;
    const Toks t = shader_tokens(prelude);
    for (size_t i = 0; i + 1 < t.size(); ++i) {
        if (t[i].text == "fn" && t[i + 1].text != "main") out.insert(t[i + 1].text);
        if (t[i].text == "private" && i + 2 < t.size() && t[i + 1].text == ">")
            out.insert(t[i + 2].text);
    }
    return out;
}

// A file of the module naga reads, and where its lines are in the joined text.
struct WgslPart {
    std::string display;
    int first = 1, lines = 0;
};

// The plug-in's file and what it imports, joined (WGSL declarations come in any order), with
// naga_oil's directives (Bevy's preprocessor) read: the subset pxh knows.
struct WgslModules {
    const std::string& experiment_path;
    const EngineAdapter& a;
    std::string text;
    std::vector<WgslPart> parts;
    std::set<std::string> imported;
    std::string explicit_level;
};

bool defined(const EngineAdapter& a, const std::string& name) {
    for (const auto& [k, v] : a.defines)
        if (k == name) return v != "0";
    return false;
}

std::string trimmed(const std::string& s) {
    const size_t b = s.find_first_not_of(" \t\r");
    if (b == std::string::npos) return "";
    return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

// The module a `#import` line names: `#import a::b`, `#import a::b x, y`, `#import a::b::{x, y}`.
std::string import_module(const std::string& rest, const std::string& where) {
    std::string m = rest.substr(0, rest.find_first_of(" \t"));
    if (const size_t brace = m.find("::{"); brace != std::string::npos) m.resize(brace);
    if (m.empty() || rest.find(" as ") != std::string::npos)
        throw InputError(where, "#import " + rest +
                                    ": pxh reads `#import MODULE [items]` (its items unqualified); "
                                    "an alias (as) or a qualified use is not supported");
    return m;
}

void add_part(WgslModules& m, const std::string& text, const std::string& display, int depth);

// A directive line (`#...`): its effect on the #ifdef stack, or an import (module, where).
void directive(WgslModules& m, const std::string& line, const std::string& where,
               std::vector<std::pair<bool, bool>>& stack,
               std::vector<std::pair<std::string, std::string>>& imports) {
    const bool active = stack.empty() || stack.back().first;
    std::string word = line.substr(1, line.find_first_of(" \t", 1) - 1);
    const std::string rest =
        word.size() + 1 < line.size() ? trimmed(line.substr(word.size() + 1)) : "";
    if (word == "ifdef" || word == "ifndef") {
        const bool c = defined(m.a, rest) == (word == "ifdef");
        stack.push_back({active && c, c});
    } else if (word == "else") {
        if (stack.empty()) throw InputError(where, "#else without #ifdef");
        const bool outer = stack.size() < 2 || stack[stack.size() - 2].first;
        stack.back() = {outer && !stack.back().second, true};
    } else if (word == "endif") {
        if (stack.empty()) throw InputError(where, "#endif without #ifdef");
        stack.pop_back();
    } else if (word == "define_import_path") {
    } else if (word == "import") {
        if (active) imports.emplace_back(import_module(rest, where), where);
    } else if (active) {
        throw InputError(where, "#" + word +
                                    ": pxh reads naga_oil's #define_import_path, #import, #ifdef, "
                                    "#ifndef, #else and #endif (the entry's defines decide "
                                    "#ifdef; false is undefined)");
    }
}

// The file's text with its directive lines and the lines #ifdef leaves out blanked (its lines
// keep their numbers), its height texture's calls counted, then the modules it imports (each
// once, through the entry's includes table: module name -> file).
void add_part(WgslModules& m, const std::string& text, const std::string& display, int depth) {
    std::string kept;
    std::vector<std::pair<bool, bool>> stack;  // (active, a branch was taken)
    std::vector<std::pair<std::string, std::string>> imports;
    size_t start = 0;
    int line = 0;
    while (start < text.size()) {
        size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        const std::string l = text.substr(start, end - start);
        start = end + 1;
        ++line;
        const std::string t = trimmed(l);
        if (!t.empty() && t[0] == '#') {
            directive(m, t, display + ":" + std::to_string(line), stack, imports);
            kept += "\n";
            continue;
        }
        kept += (stack.empty() || stack.back().first ? l : std::string()) + "\n";
    }
    if (!stack.empty()) throw InputError(display, "#ifdef without #endif");
    m.parts.push_back({display, int(std::count(m.text.begin(), m.text.end(), '\n')) + 1, line});
    m.text += rewrite(kept, display, m.a.height_sampler, m.explicit_level);
    for (const auto& [name, where] : imports) {
        if (!m.imported.insert(name).second) continue;
        const auto it = m.a.includes.find(name);
        if (it == m.a.includes.end())
            throw InputError(where, "#import " + name +
                                        ": no such module in the entry's includes (map it to a "
                                        "file: includes = { \"" +
                                        name + "\" = \"FILE\" })");
        if (depth >= 16) throw InputError(where, "#import nested deeper than 16");
        const PluginSource src = read_plugin_source(m.experiment_path, it->second, where);
        add_part(m, src.text, src.display, depth + 1);
    }
}

std::string naga_script() {
    if (const char* s = std::getenv("PXH_NAGA_SCRIPT")) return s;
    return std::string(PXH_SOURCE_DIR) + "/tools/naga/wgsl_to_glsl.mjs";
}

// naga's report as FILE:LINE:COL: error: MESSAGE, at the file the line is in (past the files:
// pxh's prelude).
[[noreturn]] void naga_error(const std::string& report, const std::vector<WgslPart>& parts) {
    static const std::regex span("wgsl:([0-9]+):([0-9]+)");
    std::string message = report.substr(0, report.find('\n'));
    if (message.rfind("error: ", 0) == 0 || message.rfind("Error: ", 0) == 0)
        message = message.substr(7);
    std::smatch m;
    if (!std::regex_search(report, m, span))
        throw InputError(parts[0].display, "error: " + message);
    const int line = std::stoi(m[1]);
    std::string where;
    for (const WgslPart& p : parts)
        if (line >= p.first && line < p.first + p.lines)
            where = p.display + ":" + std::to_string(line - p.first + 1) + ":" + std::string(m[2]);
    if (where.empty()) {
        const WgslPart& last = parts.back();
        where = "pxh's methods/common.wgsl:" + std::to_string(line - last.first - last.lines + 1);
    }
    throw InputError(where, "error: " + message + " (naga)");
}

}  // namespace

ConvertedShader wgsl_to_glsl(const std::string& experiment_path, const std::string&,
                             const std::string& text, const std::string& display,
                             const EngineAdapter& a) {
    ConvertedShader out;
    out.display = display + " (as GLSL)";
    WgslModules m{experiment_path, a, "", {}, {}, ""};
    add_part(m, text, display, 0);
    out.explicit_level = m.explicit_level;
    const std::string prelude = shader_source(kPrelude, "").text;
    const std::string script = naga_script();
    if (!std::filesystem::exists(std::filesystem::path(script).parent_path() / "node_modules" /
                                 "naga-wasm"))
        throw InputError(display, "a WGSL plug-in needs naga (npm naga-wasm 30.1.0, pinned in " +
                                      script +
                                      "'s folder): ./run.sh installs it (npm ci in tools/naga)");
    TempFolder dir;
    dir.write("plugin.wgsl", m.text + prelude);
    const ToolResult r = run_tool(
        {"node", script, dir.path() + "/plugin.wgsl", dir.path() + "/plugin.glsl"}, dir.path());
    if (!r.started)
        throw InputError(display,
                         "a WGSL plug-in needs node (Debian's nodejs; ./run.sh installs it)");
    if (r.exit_code != 0) naga_error(r.output, m.parts);
    out.glsl = "// GLSL of " + display + " (naga WGSL -> GLSL), pxh\n" +
               converted_plugin_glsl(dir.read("plugin.glsl"), out.display, stand_ins(prelude), {});
    if (!a.height_sampler.empty())
        out.glsl +=
            "vec4 pxh_engine_height_bias(vec2 uv, float bias) { return "
            "pxh_engine_height(uv, bias); }\n";
    return out;
}

}  // namespace pxh

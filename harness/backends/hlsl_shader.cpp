#include <cctype>
#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <vector>

#include "harness/backends/converted_shader.h"
#include "harness/backends/plugin_source.h"
#include "harness/backends/shaders.h"
#include "harness/backends/tool_process.h"
#include "harness/core/error.h"

namespace pxh {
namespace {

using Toks = std::vector<ShaderToken>;
namespace fs = std::filesystem;

constexpr const char* kPrelude = "methods/common.hlsl";
constexpr const char* kEntryFile = "pxh entry (generated)";

std::string at(const std::string& display, const ShaderToken& t) {
    return display + ":" + std::to_string(t.line) + ":" + std::to_string(t.col);
}

// A file name as `#line N "NAME"` can hold it.
std::string line_name(const std::string& display) {
    std::string s = display;
    for (char& c : s)
        if (c == '"' || c == '\\') c = '_';
    return s;
}

// What the engine's height texture's sampling calls read: the row's lod (Sample, SampleBias),
// an explicit level, explicit derivatives.
struct SamplingCall {
    const char* replacement;
    bool level;
};
const std::map<std::string, SamplingCall>& texture_methods() {
    static const std::map<std::string, SamplingCall> m = {
        {"Sample", {"pxh_engine_height(", false}},
        {"SampleBias", {"pxh_engine_height(", false}},
        {"SampleLevel", {"pxh_engine_height_lod(", true}},
        {"SampleGrad", {"pxh_engine_height_grad(", false}}};
    return m;
}
// Unity's Core render pipeline macros (SAMPLE_TEXTURE2D_LOD(tex, sampler, uv, lod), ...).
const std::map<std::string, SamplingCall>& texture_macros() {
    static const std::map<std::string, SamplingCall> m = {
        {"SAMPLE_TEXTURE2D", {"pxh_engine_height(", false}},
        {"SAMPLE_TEXTURE2D_BIAS", {"pxh_engine_height(", false}},
        {"SAMPLE_TEXTURE2D_LOD", {"pxh_engine_height_lod(", true}},
        {"SAMPLE_TEXTURE2D_GRAD", {"pxh_engine_height_grad(", false}}};
    return m;
}

// What pxh refuses in an HLSL file before glslang reads it, each at its FILE:LINE:COL.
void refuse(const Toks& t, const std::string& display) {
    static const std::set<std::string> dx9 = {"sampler",     "sampler1D", "sampler2D", "sampler3D",
                                              "samplerCUBE", "tex2D",     "tex2Dlod",  "tex2Dgrad",
                                              "tex2Dbias",   "tex2Dproj"};
    static const std::regex sixteen("(float|int|uint)16_t[1-4]?(x[1-4])?");
    for (size_t i = 0; i < t.size(); ++i) {
        const std::string& x = t[i].text;
        if (dx9.count(x))
            throw InputError(at(display, t[i]),
                             "'" + x +
                                 "' is a DX9-style sampler: declare Texture2D NAME and "
                                 "SamplerState, and sample with NAME.Sample / SampleLevel / "
                                 "SampleGrad (pxh converts DX10+ HLSL)");
        if (std::regex_match(x, sixteen))
            throw InputError(at(display, t[i]),
                             "'" + x +
                                 "' is an explicit 16-bit type, which pxh's GLSL 4.50 target "
                                 "lacks: write float / int (half and min16float are computed as "
                                 "32-bit float)");
    }
}

// The lines of preprocessor directives (with their continuation lines): macro bodies such as
// Unity's SAMPLE_TEXTURE2D_LOD definition are not calls.
std::set<int> directive_lines(const std::string& text) {
    std::set<int> out;
    int line = 1;
    bool directive = false;
    size_t start = 0;
    while (start <= text.size()) {
        size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        const size_t first = text.find_first_not_of(" \t", start);
        if (!directive) directive = first < end && text[first] == '#';
        if (directive) out.insert(line);
        const size_t last = text.find_last_not_of(" \t\r", end == 0 ? 0 : end - 1);
        directive = directive && last != std::string::npos && last >= start && text[last] == '\\';
        start = end + 1;
        ++line;
    }
    return out;
}

// A texture other than the height texture sampled in code: pxh binds the height map alone.
void refuse_other_textures(const Toks& t, const std::string& text, const std::string& display,
                           const std::string& tex) {
    static const std::set<std::string> methods = {"Sample",     "SampleBias", "SampleLevel",
                                                  "SampleGrad", "SampleCmp",  "SampleCmpLevelZero",
                                                  "Load",       "Gather"};
    const std::set<int> directives = directive_lines(text);
    for (size_t i = 0; i + 3 < t.size(); ++i) {
        if (directives.count(t[i].line)) continue;
        const bool method = t[i + 1].text == "." && methods.count(t[i + 2].text) &&
                            t[i + 3].text == "(" && t[i].text != tex;
        const bool macro =
            texture_macros().count(t[i].text) && t[i + 1].text == "(" && t[i + 2].text != tex;
        if (!method && !macro) continue;
        const std::string name = method ? t[i].text : t[i + 2].text;
        throw InputError(at(display, t[i]),
                         "texture '" + name +
                             "' is sampled here, and pxh binds no texture but the height map: "
                             "if it is the engine's height texture, name it in the entry "
                             "(height_sampler = \"" +
                             name + "\")");
    }
}

// The text with every sampling call on the height texture made pxh's (counted) call, at the
// same lines; `level` set to the first explicit level's FILE:LINE:COL.
std::string rewrite_height_calls(const std::string& text, const std::string& display,
                                 const std::string& tex, std::string& level) {
    const Toks t = shader_tokens(text);
    refuse_other_textures(t, text, display, tex);
    if (tex.empty()) return text;
    std::string out;
    size_t copied = 0;
    auto replace = [&](size_t from, size_t to, const std::string& with) {
        out += text.substr(copied, t[from].begin - copied) + with;
        copied = t[to].end;
    };
    auto note_level = [&](const SamplingCall& c, size_t i, const std::string& name, size_t comma) {
        if (c.level && level.empty() && !literal_level_zero(t, comma))
            level = at(display, t[i]) + ": " + name;
    };
    for (size_t i = 0; i < t.size(); ++i) {
        const std::string& x = t[i].text;
        if (const auto m = texture_macros().find(x); m != texture_macros().end() &&
                                                     i + 3 < t.size() && t[i + 1].text == "(" &&
                                                     t[i + 2].text == tex && t[i + 3].text == ",") {
            const size_t c = next_argument(t, i + 4);
            if (c == std::string::npos) continue;
            note_level(m->second, i, x, c);
            replace(i, c, m->second.replacement);
            i = c;
            continue;
        }
        if (x != tex) continue;
        const bool declaration =
            i > 0 && (t[i - 1].text == "Texture2D" || t[i - 1].text == ">" ||
                      (t[i - 1].text == "(" && i > 1 && t[i - 2].text == "TEXTURE2D"));
        if (declaration) continue;
        const bool method = i + 3 < t.size() && t[i + 1].text == "." && t[i + 3].text == "(";
        const auto m = method ? texture_methods().find(t[i + 2].text) : texture_methods().end();
        if (m == texture_methods().end())
            throw InputError(at(display, t[i]),
                             "the height texture '" + tex +
                                 "' is used here other than by a sampling call pxh counts "
                                 "(NAME.Sample, SampleBias, SampleLevel, SampleGrad, or "
                                 "SAMPLE_TEXTURE2D[_BIAS|_LOD|_GRAD](NAME, ...))");
        const size_t c = next_argument(t, i + 4);
        if (c == std::string::npos) continue;
        note_level(m->second, i, tex + "." + t[i + 2].text, c);
        replace(i, c, m->second.replacement);
        i = c;
    }
    return out + text.substr(copied);
}

// One HLSL file and what it includes, expanded: each file checked (refuse) and its height
// texture's calls rewritten, `#line N "FILE"` before each part so that glslang's messages name
// the file and line the user wrote. Files as for GLSL engine shaders: "file" relative to the
// including file, <name> and "name" through the entry's includes table, inside the experiment's
// folder, at most 16 deep.
struct HlslExpansion {
    const std::string& experiment_path;
    const EngineAdapter& a;
    std::string explicit_level;
    std::vector<std::string> stack;  // canonical paths being expanded
};

void expand_hlsl(HlslExpansion& e, const std::string& rel, const std::string& text,
                 const std::string& display, std::string& out) {
    refuse(shader_tokens(text), display);
    const std::string body =
        rewrite_height_calls(text, display, e.a.height_sampler, e.explicit_level);
    out += "#line 1 \"" + line_name(display) + "\"\n";
    size_t start = 0;
    long line = 1;
    while (start <= body.size()) {
        size_t end = body.find('\n', start);
        if (end == std::string::npos) end = body.size();
        const std::string l = body.substr(start, end - start);
        std::string name, problem;
        bool angle = false;
        if (!engine_include_line(l, name, angle, problem)) {
            out += l + "\n";
        } else {
            const std::string where = display + ":" + std::to_string(line);
            if (!problem.empty()) throw InputError(where, problem);
            std::string inc;
            if (const auto it = e.a.includes.find(name); it != e.a.includes.end()) inc = it->second;
            else if (angle)
                throw InputError(where, "#include <" + name +
                                            ">: no such name in the entry's includes (map it to "
                                            "a file: includes = { \"" +
                                            name + "\" = \"FILE\" })");
            else inc = (fs::path(rel).parent_path() / name).lexically_normal().string();
            if (e.stack.size() >= 16) throw InputError(where, "#include nested deeper than 16");
            const PluginSource src = read_plugin_source(e.experiment_path, inc, where);
            for (const std::string& r : e.stack)
                if (r == src.resolved)
                    throw InputError(where, "#include \"" + name + "\" includes itself");
            e.stack.push_back(src.resolved);
            expand_hlsl(e, inc, src.text, src.display, out);
            e.stack.pop_back();
            out += "#line " + std::to_string(line + 1) + " \"" + line_name(display) + "\"\n";
        }
        start = end + 1;
        ++line;
    }
}

// Names declared `bool` (a uniform's bool becomes a uint in SPIR-V).
std::set<std::string> bool_names(const Toks& t) {
    std::set<std::string> out;
    for (size_t i = 0; i + 2 < t.size(); ++i)
        if (t[i].text == "bool" && (t[i + 2].text == ";" || t[i + 2].text == ":"))
            out.insert(t[i + 1].text);
    return out;
}

// glslang's first error as FILE:LINE[:COL]: message.
[[noreturn]] void glslang_error(const std::string& output) {
    static const std::regex error("ERROR: (.*):([0-9]+): (.*)");
    static const std::regex column("(.*)\\(([0-9]+)\\): error at column ([0-9]+).*");
    std::smatch m, c;
    int count = 0;
    std::string first_file, first_line, message, col;
    size_t start = 0;
    while (start < output.size()) {
        size_t end = output.find('\n', start);
        if (end == std::string::npos) end = output.size();
        const std::string line = output.substr(start, end - start);
        start = end + 1;
        if (std::regex_match(line, m, error)) {
            if (count++ == 0) {
                first_file = m[1];
                first_line = m[2];
                message = m[3];
                while (!message.empty() && message.back() == ' ') message.pop_back();
            }
        } else if (std::regex_match(line, c, column) && c[1] == first_file && c[2] == first_line &&
                   col.empty()) {
            col = c[3];
        }
    }
    if (count == 0) throw InputError("", "glslangValidator failed: " + output.substr(0, 400));
    throw InputError(
        first_file + ":" + first_line + (col.empty() ? "" : ":" + col),
        "error: " + message +
            (count > 1 ? " (glslang: " + std::to_string(count) + " errors, the first shown)" : ""));
}

std::set<std::string> prelude_functions(const std::string& prelude) {
    std::set<std::string> out;
    const Toks t = shader_tokens(prelude);
    for (size_t i = 1; i + 1 < t.size(); ++i)
        if (t[i + 1].text == "(" && t[i].text.rfind("pxh_", 0) == 0 &&
            (t[i - 1].text == "float" || t[i - 1].text == "float4" || t[i - 1].text == "int2" ||
             t[i - 1].text == "float3" || t[i - 1].text == "void"))
            out.insert(t[i].text);
    return out;
}

}  // namespace

bool converted_language(const std::string& path) {
    auto ends = [&](const char* e) {
        const std::string x = e;
        return path.size() > x.size() && path.compare(path.size() - x.size(), x.size(), x) == 0;
    };
    return ends(".hlsl") || ends(".wgsl");
}

ConvertedShader hlsl_to_glsl(const std::string& experiment_path, const std::string& rel,
                             const std::string& text, const std::string& display_in,
                             const EngineAdapter& a) {
    const std::string display = line_name(display_in);
    ConvertedShader out;
    out.display = display + " (as GLSL)";
    HlslExpansion e{experiment_path, a, "", {}};
    std::string body;
    expand_hlsl(e, rel, text, display_in, body);
    out.explicit_level = e.explicit_level;
    const Toks t = shader_tokens(body);
    const std::string prelude = shader_source(kPrelude, "").text;
    const std::string program = "#line 1 \"pxh's methods/common.hlsl\"\n" + prelude +
                                "#line 1 \"pxh's defines (generated)\"\n" +
                                engine_define_lines(a, engine_names(body)) + body + "\n#line 1 \"" +
                                kEntryFile +
                                "\"\nfloat4 main(float4 pxh_frag : SV_Position) : SV_Target {\n"
                                "    return float4(pxh_method(pxh_frag.xy), 0.0, 1.0);\n}\n";
    TempFolder dir;
    dir.write("plugin.hlsl", program);
    const ToolResult g =
        run_tool({"glslangValidator", "-D", "-V", "-Od", "-S", "frag", "-e", "main", "-o",
                  dir.path() + "/plugin.spv", dir.path() + "/plugin.hlsl"},
                 dir.path());
    if (!g.started)
        throw InputError(display_in,
                         "an HLSL plug-in needs glslangValidator (Debian's glslang-tools; "
                         "./run.sh installs it)");
    if (g.exit_code != 0) glslang_error(g.output);
    const ToolResult c = run_tool({"spirv-cross", "--version", "450", "--output",
                                   dir.path() + "/plugin.glsl", dir.path() + "/plugin.spv"},
                                  dir.path());
    if (!c.started)
        throw InputError(display_in,
                         "an HLSL plug-in needs spirv-cross (Debian's spirv-cross; ./run.sh "
                         "installs it)");
    if (c.exit_code != 0)
        throw InputError(display_in, "spirv-cross failed: " + c.output.substr(0, 400));
    out.glsl = "// GLSL of " + display + " (glslang HLSL -> SPIR-V -> SPIRV-Cross), pxh\n" +
               converted_plugin_glsl(dir.read("plugin.glsl"), out.display,
                                     prelude_functions(prelude), bool_names(t));
    return out;
}

ConvertedShader converted_to_glsl(const std::string& experiment_path, const std::string& rel,
                                  const std::string& text, const std::string& display,
                                  const EngineAdapter& a) {
    if (rel.size() > 5 && rel.compare(rel.size() - 5, 5, ".wgsl") == 0)
        return wgsl_to_glsl(experiment_path, rel, text, display, a);
    return hlsl_to_glsl(experiment_path, rel, text, display, a);
}

}  // namespace pxh

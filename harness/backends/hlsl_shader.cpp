#include "harness/backends/hlsl_shader.h"

#include <map>
#include <regex>
#include <vector>

#include "harness/backends/shaders.h"
#include "harness/backends/tool_process.h"
#include "harness/core/error.h"

namespace pxh {
namespace {

using Toks = std::vector<ShaderToken>;

constexpr const char* kPrelude = "methods/common.hlsl";
constexpr const char* kEntryFile = "pxh entry (generated)";

std::string at(const std::string& display, const ShaderToken& t) {
    return display + ":" + std::to_string(t.line) + ":" + std::to_string(t.col);
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

// The index of the first ',' at the bracket depth of token `i` (inside the call), or npos.
size_t next_comma(const Toks& t, size_t i) {
    int depth = 0;
    for (; i < t.size(); ++i) {
        const std::string& x = t[i].text;
        if (x == "(" || x == "[") ++depth;
        if (x == ")" || x == "]") {
            if (--depth < 0) return std::string::npos;
        }
        if (x == "," && depth == 0) return i;
    }
    return std::string::npos;
}

// What pxh refuses in an HLSL plug-in before glslang reads it, each at its FILE:LINE:COL.
void refuse(const Toks& t, const std::string& display) {
    static const std::map<std::string, std::string> dx9 = {
        {"sampler", ""},     {"sampler1D", ""}, {"sampler2D", ""}, {"sampler3D", ""},
        {"samplerCUBE", ""}, {"tex2D", ""},     {"tex2Dlod", ""},  {"tex2Dgrad", ""},
        {"tex2Dbias", ""},   {"tex2Dproj", ""}};
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
        if (x == "#" && i + 1 < t.size() && t[i + 1].text == "include")
            throw InputError(at(display, t[i]),
                             "#include in an HLSL plug-in is not supported yet: write the "
                             "included text into the file");
    }
}

// The text with every sampling call on the height texture made pxh's (counted) call, at the
// same lines; `level` set to the first explicit level's FILE:LINE:COL.
std::string rewrite_height_calls(const std::string& text, const std::string& display,
                                 const std::string& tex, std::string& level) {
    if (tex.empty()) return text;
    const Toks t = shader_tokens(text);
    std::string out;
    size_t copied = 0;
    auto replace = [&](size_t from, size_t to, const std::string& with) {
        out += text.substr(copied, t[from].begin - copied) + with;
        copied = t[to].end;
    };
    auto note_level = [&](const SamplingCall& c, size_t i, const std::string& name) {
        if (c.level && level.empty()) level = at(display, t[i]) + ": " + name;
    };
    for (size_t i = 0; i < t.size(); ++i) {
        const std::string& x = t[i].text;
        if (const auto m = texture_macros().find(x); m != texture_macros().end() &&
                                                     i + 3 < t.size() && t[i + 1].text == "(" &&
                                                     t[i + 2].text == tex && t[i + 3].text == ",") {
            const size_t c = next_comma(t, i + 4);
            if (c == std::string::npos) continue;
            note_level(m->second, i, x);
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
        const size_t c = next_comma(t, i + 4);
        if (c == std::string::npos) continue;
        note_level(m->second, i, tex + "." + t[i + 2].text);
        replace(i, c, m->second.replacement);
        i = c;
    }
    return out + text.substr(copied);
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
[[noreturn]] void glslang_error(const std::string& output, const std::string& display) {
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
    if (count == 0) throw InputError(display, "glslangValidator failed: " + output.substr(0, 400));
    if (first_file != display && first_file != kEntryFile) first_file = "pxh's methods/common.hlsl";
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

std::string line_name(const std::string& display) {
    std::string s = display;
    for (char& c : s)
        if (c == '"' || c == '\\') c = '_';
    return s;
}

}  // namespace

bool converted_language(const std::string& path) {
    auto ends = [&](const char* e) {
        const std::string x = e;
        return path.size() > x.size() && path.compare(path.size() - x.size(), x.size(), x) == 0;
    };
    return ends(".hlsl") || ends(".wgsl");
}

ConvertedShader hlsl_to_glsl(const std::string& text, const std::string& display_in,
                             const EngineAdapter& a) {
    const std::string display = line_name(display_in);
    const Toks t = shader_tokens(text);
    refuse(t, display);
    ConvertedShader out;
    out.display = display + " (as GLSL)";
    const std::string body =
        rewrite_height_calls(text, display, a.height_sampler, out.explicit_level);
    const std::string prelude = shader_source(kPrelude, "").text;
    const std::string program = prelude + engine_define_lines(a, engine_code_names(text)) +
                                "#line 1 \"" + display + "\"\n" + body + "\n#line 1 \"" +
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
    if (g.exit_code != 0) glslang_error(g.output, display);
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
               spirv_cross_plugin_glsl(dir.read("plugin.glsl"), out.display,
                                       prelude_functions(prelude), bool_names(t));
    return out;
}

ConvertedShader converted_to_glsl(const std::string& path, const std::string& text,
                                  const std::string& display, const EngineAdapter& a) {
    if (path.size() > 5 && path.compare(path.size() - 5, 5, ".wgsl") == 0)
        return wgsl_to_glsl(text, display, a);
    return hlsl_to_glsl(text, display, a);
}

}  // namespace pxh

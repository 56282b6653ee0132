// WGSL plug-ins: naga (npm naga-wasm, pinned in tools/naga/package.json, run by node through
// tools/naga/wgsl_to_glsl.mjs) translates the file and pxh's methods/common.wgsl after it to
// GLSL 4.50; the stand-ins are removed as for HLSL (converted_shader.h).
#include <cstdlib>
#include <filesystem>
#include <map>
#include <regex>

#include "harness/backends/converted_shader.h"
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
    for (size_t i = 0; i < t.size(); ++i)
        if (t[i].text == "#" && (i == 0 || t[i - 1].line != t[i].line))
            throw InputError(at(display, t[i]),
                             "a WGSL plug-in is plain WGSL: preprocessor lines (naga_oil's "
                             "#import, #define_import_path, #ifdef, as Bevy uses) are not read; "
                             "write the imported items into the file");
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

std::string naga_script() {
    if (const char* s = std::getenv("PXH_NAGA_SCRIPT")) return s;
    return std::string(PXH_SOURCE_DIR) + "/tools/naga/wgsl_to_glsl.mjs";
}

// naga's report as FILE:LINE:COL: error: MESSAGE (a line past the plug-in's: pxh's prelude).
[[noreturn]] void naga_error(const std::string& report, const std::string& display, int lines) {
    static const std::regex span("wgsl:([0-9]+):([0-9]+)");
    std::string message = report.substr(0, report.find('\n'));
    if (message.rfind("error: ", 0) == 0 || message.rfind("Error: ", 0) == 0)
        message = message.substr(7);
    std::smatch m;
    if (!std::regex_search(report, m, span)) throw InputError(display, "error: " + message);
    const int line = std::stoi(m[1]);
    const std::string where = line <= lines
                                  ? display + ":" + std::to_string(line) + ":" + std::string(m[2])
                                  : "pxh's methods/common.wgsl:" + std::to_string(line - lines);
    throw InputError(where, "error: " + message + " (naga)");
}

}  // namespace

ConvertedShader wgsl_to_glsl(const std::string&, const std::string&, const std::string& text,
                             const std::string& display, const EngineAdapter& a) {
    if (!a.defines.empty() || !a.includes.empty())
        throw InputError(display,
                         "defines and includes apply to GLSL and HLSL plug-ins: WGSL has no "
                         "preprocessor (write the WGSL file out for each mode)");
    ConvertedShader out;
    out.display = display + " (as GLSL)";
    const std::string body = rewrite(text, display, a.height_sampler, out.explicit_level);
    int lines = 1;
    for (char c : body) lines += c == '\n';
    if (!body.empty() && body.back() == '\n') --lines;
    const std::string prelude = shader_source(kPrelude, "").text;
    const std::string script = naga_script();
    if (!std::filesystem::exists(std::filesystem::path(script).parent_path() / "node_modules" /
                                 "naga-wasm"))
        throw InputError(display, "a WGSL plug-in needs naga (npm naga-wasm 30.1.0, pinned in " +
                                      script +
                                      "'s folder): ./run.sh installs it (npm ci in tools/naga)");
    TempFolder dir;
    dir.write("plugin.wgsl", body + (body.empty() || body.back() == '\n' ? "" : "\n") + prelude);
    const ToolResult r = run_tool(
        {"node", script, dir.path() + "/plugin.wgsl", dir.path() + "/plugin.glsl"}, dir.path());
    if (!r.started)
        throw InputError(display,
                         "a WGSL plug-in needs node (Debian's nodejs; ./run.sh installs it)");
    if (r.exit_code != 0) naga_error(r.output, display, lines);
    out.glsl = "// GLSL of " + display + " (naga WGSL -> GLSL), pxh\n" +
               converted_plugin_glsl(dir.read("plugin.glsl"), out.display, stand_ins(prelude), {});
    if (!a.height_sampler.empty())
        out.glsl +=
            "vec4 pxh_engine_height_bias(vec2 uv, float bias) { return "
            "pxh_engine_height(uv, bias); }\n";
    return out;
}

}  // namespace pxh

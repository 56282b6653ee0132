// An engine's shader text as the engine ships it, made into a plug-in's program text
// (docs/guide/plugin-shaders.md, "Engine shaders as written"): its `#include`s expanded, the
// entry's defines written before it, every sampling call on the engine's height sampler made a
// counted fetch of pxh's height (at the level the call asks for, else the row's lod), and its
// uniforms bound to the scene's scale and bias. Nothing else of the engine's text changes, and
// its lines keep their numbers: the driver's messages are located in the engine's own files.
//
// Each file is line-mapped into the program by `#line (kBodyLine (k + 1) + L) (k + 2)`: file
// k (0 the shader named by the entry, then each included file in the order first met, then
// pxh's generated adapter) at its line L (harness/backends/glsl_parts.h, located()).
#pragma once
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace pxh {

// What an entry says about the engine's text, for one setting of its defines.
struct EngineAdapter {
    std::string height_sampler;  // the engine's sampler2D of the height map ("": none)
    int channel = -1;            // 0..3: the channel that holds the height; -1: all four
    bool depth = false;          // the map holds depth 1 - h (three.js's bumpMap)
    // Uniforms bound to scene quantities: name -> GLSL expression over u_scale, u_bias.
    std::map<std::string, std::string> quantities;
    // The defines, in the entry's order: name -> its value as written in `#define NAME VALUE`.
    std::vector<std::pair<std::string, std::string>> defines;
    // Names that some define's value takes (over every setting, sorted): each that the text
    // names only on #if / #elif lines is defined as a distinct number, so that
    // `#if MODE == OCCLUSION` compares names as the engines do.
    std::vector<std::string> define_names;
    // `#include <name>` and `#include "name"`: name -> the file, relative to the experiment.
    std::map<std::string, std::string> includes;
    // True when the entry uses none of the above and the text has no #include: the text is
    // compiled as it is.
    bool plain() const;
};

// The program text of a plug-in and what locating its messages needs.
struct EngineShader {
    std::string text;                // what is compiled after common.glsl (and recorded)
    std::vector<std::string> files;  // the files read, as the user reaches them ([0] the entry's)
    std::vector<std::string> texts;  // each file's text as read
    // Where the shader reads an explicit texture level ("FILE:LINE:COL: CALL"), "" if nowhere.
    std::string explicit_level;
    // The uniforms its files declare: name -> GLSL type.
    std::map<std::string, std::string> uniform_types;
};

// The adapted text of `main_text` (the file `main_rel` as the entry names it, `main_display` as
// the user reaches it, read for the experiment at `experiment_path`; `where` the entry's
// "FILE:LINE"). Throws InputError at the engine file's
// FILE:LINE:COL for an include that cannot be read, a height sampler used other than by a
// sampling call pxh counts, a bound uniform the text does not declare, and the like.
EngineShader adapt_engine_shader(const std::string& experiment_path, const std::string& main_rel,
                                 const std::string& main_text, const std::string& main_display,
                                 const EngineAdapter& a, const std::string& where);

// A token of GLSL (or HLSL, WGSL) text with its byte range and 1-based line and column:
// identifiers, numbers, and each other character on its own (comments skipped).
struct ShaderToken {
    std::string text;
    size_t begin = 0, end = 0;
    int line = 1, col = 1;
};
std::vector<ShaderToken> shader_tokens(const std::string& s);

// The identifiers of a text's code (its lines other than #if / #elif).
struct EngineNames {
    std::set<std::string> code;
};
EngineNames engine_names(const std::string& text);

// The `#define` lines of the adapter's defines, and of each string value that the text's code
// does not name (a distinct number, so `#if MODE == OCCLUSION` compares names), as written
// before the engine's text; the value of a define that the code expands stays undefined (a
// swizzle such as CHANNEL = "g" in `texture(..).CHANNEL`).
std::string engine_define_lines(const EngineAdapter& a, const EngineNames& names);

// Whether `line` is an `#include` line: its name, its form (<name> or "name"), and the problem
// when it is malformed (an engine's include parameters, no closing bracket, ...).
bool engine_include_line(const std::string& line, std::string& name, bool& angle,
                         std::string& problem);

// The GLSL of a bound quantity ("scale", "bias", "0.1 * scale", "scale / 0.1 + bias", ...):
// numbers, scale, bias, + - * / and parentheses; "" and `problem` set when it is not one.
std::string quantity_glsl(const std::string& q, std::string& problem);

}  // namespace pxh

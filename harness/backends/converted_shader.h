// HLSL and WGSL plug-ins (docs/guide/plugin-shaders.md, "HLSL and WGSL"): the plug-in's file,
// in the language the engine ships, converted to the GLSL a GLSL plug-in would be. HLSL goes
// through glslang's HLSL front end to SPIR-V (glslangValidator, optimizer off, so functions
// stay functions) and SPIRV-Cross back to GLSL 4.50; pxh's interface is an HLSL prelude,
// methods/common.hlsl, whose stand-in functions are removed from the GLSL so that the calls
// reach methods/common.glsl's (the same fetch counting as a GLSL plug-in). The GLSL is then
// adapted like an engine's GLSL (bind, the height sampler's functions): engine_shader.h. WGSL
// goes through naga (npm naga-wasm, pinned in tools/naga) straight to GLSL, with
// methods/common.wgsl after the file. Files: hlsl_shader.cpp, wgsl_shader.cpp, converted_glsl.cpp.
#pragma once
#include <set>
#include <string>
#include <vector>

#include "harness/backends/engine_shader.h"

namespace pxh {

// The GLSL of a converted plug-in and what the adaptation needs to know of its source.
struct ConvertedShader {
    std::string glsl;            // defines pxh_method; its uniforms as `uniform TYPE NAME;`
    std::string display;         // how messages about the GLSL name it ("FILE (as GLSL)")
    std::string explicit_level;  // "FILE:LINE:COL: CALL" of the first explicit level, or ""
};

// True for a file that pxh converts (.hlsl, .wgsl).
bool converted_language(const std::string& path);

// The GLSL of the HLSL `text` (the file `display`) for one setting of the adapter's defines:
// its height sampler's sampling calls made pxh's, its defines written before it. Throws
// InputError at the HLSL file's FILE:LINE[:COL] for what glslang refuses (its first error),
// DX9 samplers and explicit 16-bit types, includes it cannot read, and missing tools.
// `rel` is the file as the entry names it (includes are read relative to it, inside the
// folder of `experiment_path`).
ConvertedShader hlsl_to_glsl(const std::string& experiment_path, const std::string& rel,
                             const std::string& text, const std::string& display,
                             const EngineAdapter& a);

// The same for WGSL (through naga; harness/backends/wgsl_shader.cpp).
ConvertedShader wgsl_to_glsl(const std::string& experiment_path, const std::string& rel,
                             const std::string& text, const std::string& display,
                             const EngineAdapter& a);

// Any converted plug-in by its file's extension.
ConvertedShader converted_to_glsl(const std::string& experiment_path, const std::string& rel,
                                  const std::string& text, const std::string& display,
                                  const EngineAdapter& a);

// The index of the first ',' at the bracket depth of token `i` of `t` (a call's next argument),
// or npos when the call closes first.
size_t next_argument(const std::vector<ShaderToken>& t, size_t i);
// Whether the sampling call whose sampler argument ends at the comma `c` passes the literal level
// 0 as its last argument (level 0 exists in every lod mode: no explicit level to refuse).
bool literal_level_zero(const std::vector<ShaderToken>& t, size_t c);

// A converter's GLSL of a whole fragment shader (SPIRV-Cross's, naga's) made a plug-in's: the
// preamble, the entry point (main, _main), the in/out variables and the functions and variables
// named in `stand_ins` removed, uniform blocks (and structs in them) written as plain uniforms (a
// uint member, which is how SPIR-V holds a bool, as a bool when `bools` names it, else as an int).
// Throws InputError at `display` when the text needs an extension.
std::string converted_plugin_glsl(const std::string& glsl, const std::string& display,
                                  const std::set<std::string>& stand_ins,
                                  const std::set<std::string>& bools);

}  // namespace pxh

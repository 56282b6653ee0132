// Plug-in shader files ([[methods]] shader = FILE): read once, when the experiment is parsed,
// under rules that keep an experiment from reading anything but its own shader (a CI gate runs
// experiments from pull requests), and checked for what pxh's counts rely on.
//
// The file: a path relative to the experiment's folder that lies inside that folder after every
// symbolic link is resolved; a regular file of at most kMaxPluginShaderBytes; UTF-8 text without
// NUL bytes. Anything else is an InputError naming the experiment's line (or, for the text, the
// shader's own line), and nothing of the file is kept.
//
// The source: pxh counts fetches through pxh_height / pxh_z / pxh_texture (methods/common.glsl),
// so a shader may not name the height texture (u_height), the view map bound beside it
// (u_view_map), the counter (pxh_fetches) or pxh's outputs (pxh_out_uv, pxh_out_shadow), nor
// paste tokens (`##`, which could spell those names); and it may not declare a uniform that
// common.glsl declares (u_*, the layer search's p_layers*): those are reserved names.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "harness/core/limits.h"  // kMaxPluginShaderBytes

namespace pxh {

struct PluginSource {
    std::string text;      // the file's content, as compiled and recorded in run.json
    std::string resolved;  // the file's canonical path
    std::string display;   // its path as the user reaches it: experiment folder / FILE
};

// Reads `rel` (as written in the experiment at `where`, "FILE:LINE") relative to the folder of
// `experiment_path`. Throws InputError.
PluginSource read_plugin_source(const std::string& experiment_path, const std::string& rel,
                                const std::string& where);

// The first invalid UTF-8 sequence (or NUL byte) of `text` as "LINE:COL: why", "" when none.
std::string shader_text_problem(const std::string& text);

// One line per problem of the source's use of pxh's interface, each "DISPLAY:LINE:COL: ...";
// empty when none. `common` is the text of the common.glsl it is compiled with.
std::vector<std::string> plugin_source_problems(const std::string& display, const std::string& text,
                                                const std::string& common);

// "LINE:COL" of the uniform declaration of `name` in `text` (`uniform TYPE name`), "" if none.
std::string uniform_declaration(const std::string& text, const std::string& name);
// "LINE:COL" of the first token `name` in `text` (comments skipped; C-like tokens, so HLSL and
// WGSL too), "" when there is none.
std::string identifier_position(const std::string& text, const std::string& name);

// The names common.glsl declares at global scope as uniforms (u_*, p_layers*).
std::vector<std::string> common_uniform_names(const std::string& common);

}  // namespace pxh

// The GLSL backend's hooks in its registry entry (BackendEntry: preflight, warnings, record):
// what it checks before a run, what it warns of once made, and what its block of run.json
// records of the GL behind it. The runner calls them through the entry, never by name.
#pragma once
#include <map>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "harness/backends/backend.h"

namespace pxh {

// Every plug-in setting's shader compiled and linked in each program its rows use, its uniforms
// checked, in a GL process of its own: one line per problem (the driver's messages as
// FILE:LINE:COL: ... of the user's file), empty when all are ready (at once, without GL, when
// there is no plug-in). std::runtime_error when no GL context can be made.
std::vector<std::string> glsl_preflight(const Preflight& p, const BackendSettings& settings);

// `--gl egl` that gave a software renderer: no GPU's EGL device was usable, so the GLSL
// timings are the CPU's.
std::vector<std::string> glsl_warnings(const Backend& b, const BackendSettings& settings);

// The block's "gl" (context, GL_VENDOR, GL_RENDERER, GL_VERSION, GL_QUERY_COUNTER_BITS,
// driver), "shader_dir" (absolute; "" for the embedded shaders) and "LP_NUM_THREADS" (llvmpipe's
// rasteriser threads, "" when unset).
void glsl_record(const Backend& b, const BackendSettings& settings, nlohmann::json& block);

// The timed frames per GLSL row: gl_frames, or none when the experiment times nothing
// (timing_repeats = 0: one untimed frame draws the answers, no time column is filled).
int glsl_repeats(const BackendSettings& s);

// Whether a GL renderer is software (llvmpipe, softpipe, SwiftShader, an EGL software device),
// from a GLSL backend's facts (gl_renderer, gl_driver.platform).
bool software_renderer(const std::map<std::string, std::string>& backend_facts);

}  // namespace pxh

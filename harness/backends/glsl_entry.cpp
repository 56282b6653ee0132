#include "harness/backends/glsl_entry.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "harness/backends/gl_worker.h"
#include "harness/backends/glsl_backend.h"

namespace pxh {

std::vector<std::string> glsl_preflight(const Preflight& p, const BackendSettings& settings) {
    if (p.plugins.empty()) return {};
    GlslChildBackend gl(settings);
    std::vector<std::string> problems;
    for (const PluginSettings& s : p.plugins) {
        // Each program its rows compile: the point map of a camera whose rays are not
        // parallel, and each level mode (each declares other names).
        std::vector<uint8_t> kinds;
        for (LodMode lod : s.lods) kinds.push_back(glsl_program_kind(!p.parallel_camera, lod));
        for (auto& line : gl.check(GlslMethod::of(*s.first->method),
                                   method_uniforms(*s.first->method, s.first->params), kinds))
            problems.push_back(std::move(line));
    }
    return problems;
}

namespace {

std::string fact(const std::map<std::string, std::string>& f, const std::string& key) {
    const auto it = f.find(key);
    return it == f.end() ? "" : it->second;
}

}  // namespace

bool software_renderer(const std::map<std::string, std::string>& f) {
    auto has = [](const std::string& s, const char* what) {
        std::string low;
        for (char c : s) low += char(std::tolower(static_cast<unsigned char>(c)));
        return low.find(what) != std::string::npos;
    };
    const std::string renderer = fact(f, "gl_renderer"), platform = fact(f, "gl_driver.platform");
    return has(renderer, "llvmpipe") || has(renderer, "softpipe") || has(renderer, "swiftshader") ||
           has(renderer, "software") || has(platform, "software");
}

std::vector<std::string> glsl_warnings(const Backend& b, const BackendSettings& settings) {
    const auto f = b.facts();
    if (settings.gl != "egl" || !software_renderer(f)) return {};
    return {"--gl egl gave a software renderer (GL_RENDERER '" + fact(f, "gl_renderer") +
            "', EGL platform '" + fact(f, "gl_driver.platform") +
            "'): no GPU's EGL device was usable, so the GLSL timings are the CPU's"};
}

void glsl_record(const Backend& b, const BackendSettings& settings, nlohmann::json& block) {
    const auto f = b.facts();
    nlohmann::json driver = nlohmann::json::object();
    for (const auto& [k, v] : f)
        if (k.rfind("gl_driver.", 0) == 0) driver[k.substr(10)] = v;
    const std::string bits = fact(f, "gl_timer_bits");
    block["gl"] = {{"context", fact(f, "gl_context")},
                   {"GL_VENDOR", fact(f, "gl_vendor")},
                   {"GL_RENDERER", fact(f, "gl_renderer")},
                   {"GL_VERSION", fact(f, "gl_version")},
                   {"GL_QUERY_COUNTER_BITS", bits.empty() ? 0 : std::stoi(bits)},
                   {"driver", driver}};
    block["shader_dir"] =
        settings.shader_dir.empty() ? "" : std::filesystem::absolute(settings.shader_dir).string();
    const char* lp = std::getenv("LP_NUM_THREADS");
    block["LP_NUM_THREADS"] = lp ? lp : "";
}

}  // namespace pxh

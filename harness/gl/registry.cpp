// The GL contexts pxh knows. Adding one: a file harness/gl/NAME_context.cpp that defines
// std::unique_ptr<GlContext> make_NAME_context(), and one line in PXH_GL_CONTEXTS below.
#include <algorithm>
#include <atomic>

#include "harness/core/error.h"
#include "harness/gl/context.h"

// X(NAME, SUMMARY): one line per context.
#define PXH_GL_CONTEXTS(X)                                                                         \
    X(osmesa, "Mesa's off-screen library: software rendering (llvmpipe), no display, the default") \
    X(egl, "headless EGL (a GPU device, else Mesa's surfaceless platform): the vendor's driver")

namespace pxh {

#define PXH_DECLARE(NAME, SUMMARY) std::unique_ptr<GlContext> make_##NAME##_context();
PXH_GL_CONTEXTS(PXH_DECLARE)
#undef PXH_DECLARE

const std::vector<GlContextType>& gl_context_types() {
#define PXH_ENTRY(NAME, SUMMARY) GlContextType{#NAME, SUMMARY, &make_##NAME##_context},
    static const std::vector<GlContextType> types = [] {
        std::vector<GlContextType> t{PXH_GL_CONTEXTS(PXH_ENTRY)};
        std::sort(t.begin(), t.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
        return t;
    }();
#undef PXH_ENTRY
    return types;
}

const GlContextType* find_gl_context(const std::string& name) {
    for (const auto& t : gl_context_types())
        if (t.name == name) return &t;
    return nullptr;
}

std::string gl_context_names() {
    std::string s;
    for (const auto& t : gl_context_types()) s += (s.empty() ? "" : ", ") + t.name;
    return s;
}

namespace {
std::atomic<bool> g_context_made{false};
}

bool gl_context_made_in_process() { return g_context_made.load(); }

std::unique_ptr<GlContext> make_gl_context(const std::string& name) {
    const GlContextType* t = find_gl_context(name);
    if (!t)
        throw InputError("--gl",
                         "unknown GL context '" + name + "' (known: " + gl_context_names() + ")");
    g_context_made = true;
    return t->make();
}

}  // namespace pxh

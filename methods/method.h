// The method interface. A method is one folder methods/NAME/ with NAME.cpp (CPU reference,
// generic over float/double) that ends in PXH_REGISTER_METHOD(Type); nothing else to edit.
//
// A method type M provides:
//   static MethodInfo describe();                       name, citation, parameters
//   struct Config; static Config configure(const ParamValues&, const std::string& where);
//   static int max_fetches(const Config&, const Scene<double>&);   declared bound per sample
//   template <typename T> static Vec2<T> eval(const Config&, const Scene<T>&,
//                                             HeightSampler<T>&, Vec2<T> P);
//   optionally static GlUniforms gl_uniforms(const Config&);  the GLSL twin's uniforms that
//                                                       are not one parameter's value (a
//                                                       parameter that reaches the shader as
//                                                       it is names its uniform in its
//                                                       ParamSpec: ParamSpec::to_uniform)
//   optionally static void complete_params(ParamValues&); writes in the values an unset
//                                                       optional parameter stands for
// and methods/NAME/NAME.frag.glsl defines vec2 pxh_method(vec2 P) (see methods/common.glsl).
//
// The shader interface (checked by the GLSL backend after linking, an error naming the method,
// the uniform and the shader file otherwise): the method's uniforms (method_uniforms(): the
// parameters' and gl_uniforms()) are exactly the program's active uniforms besides the
// harness's u_* ones, each with the declared GLSL type (real: float, integer: int, bool: bool,
// choice: int, the index of the name).
#pragma once
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "harness/scene/heightfield.h"
#include "harness/scene/scene.h"
#include "harness/core/params.h"
#include "harness/core/vec.h"

namespace pxh {

// A uniform the method's shader reads, with its GLSL type and value.
enum class GlslType { Float, Int, Bool };
struct GlUniform {
    std::string name;
    GlslType type = GlslType::Float;
    double value = 0;
    static GlUniform real(std::string n, double v) { return {std::move(n), GlslType::Float, v}; }
    static GlUniform integer(std::string n, int v) { return {std::move(n), GlslType::Int, double(v)}; }
    static GlUniform boolean(std::string n, bool v) { return {std::move(n), GlslType::Bool, v ? 1.0 : 0.0}; }
};
using GlUniforms = std::vector<GlUniform>;
const char* glsl_type_name(GlslType t);  // "float", "int", "bool"

template <typename T>
using BatchFn = void (*)(const ParamValues&, const Scene<T>&, const HeightField&, const Vec2<T>* P,
                         size_t n, Vec2<T>* uv, int* fetches);

struct MethodInfo {
    std::string name;      // registry key = folder name = what users type
    std::string citation;  // the source, one line
    std::string summary;   // what it returns, one line
    std::vector<ParamSpec> params;
    bool exact_on_flat = false;  // returns the true point on any flat field
    int order = 100;             // listing order
    void (*check)(const ParamValues&, const std::string& where) = nullptr;
    int (*max_fetches)(const ParamValues&, const Scene<double>&) = nullptr;
    // The uniforms the method computes (M::gl_uniforms); nullptr: none. The backend sets
    // method_uniforms(), which adds the parameters that name a uniform.
    GlUniforms (*gl_uniforms)(const ParamValues&) = nullptr;
    BatchFn<float> run_float = nullptr;
    BatchFn<double> run_double = nullptr;
    // Fills in the values that unset optional parameters stand for (checked values in), so
    // that `params` lists what ran; nullptr: nothing to fill.
    void (*complete_params)(ParamValues&) = nullptr;
};

template <class M, typename T>
void run_method_batch(const ParamValues& p, const Scene<T>& sc, const HeightField& hf,
                      const Vec2<T>* P, size_t n, Vec2<T>* uv, int* fetches) {
    const typename M::Config cfg = M::configure(p, "");
    for (size_t i = 0; i < n; ++i) {
        HeightSampler<T> sampler(hf, sc.scale, sc.bias);
        uv[i] = M::template eval<T>(cfg, sc, sampler, P[i]);
        fetches[i] = sampler.fetches;
    }
}

template <class M>
MethodInfo make_method_info() {
    MethodInfo info = M::describe();
    info.check = [](const ParamValues& p, const std::string& where) { M::configure(p, where); };
    info.max_fetches = [](const ParamValues& p, const Scene<double>& sc) {
        return M::max_fetches(M::configure(p, ""), sc);
    };
    if constexpr (requires(const typename M::Config& c) { M::gl_uniforms(c); })
        info.gl_uniforms = [](const ParamValues& p) { return M::gl_uniforms(M::configure(p, "")); };
    info.run_float = &run_method_batch<M, float>;
    info.run_double = &run_method_batch<M, double>;
    if constexpr (requires(ParamValues& p) { M::complete_params(p); })
        info.complete_params = [](ParamValues& p) { M::complete_params(p); };
    return info;
}

// Every uniform the method's shader gets, in declaration order: each parameter that names a
// uniform (its value, typed by the parameter's type), then the method's computed ones.
GlUniforms method_uniforms(const MethodInfo& m, const ParamValues& p);

// Checks the declarations (throws std::logic_error naming the method: a parameter's uniform
// without the "p_" prefix, on a parameter that can be a name or unset, or given twice) and
// adds the method to the registry.
bool register_method(MethodInfo info);
// All registered methods, in listing order.
const std::vector<MethodInfo>& all_methods();
const MethodInfo* find_method(const std::string& name);

// One method setting of an experiment: the method and its resolved parameters.
struct MethodSpec {
    const MethodInfo* method = nullptr;
    ParamValues params;
};

#define PXH_REGISTER_METHOD(M) \
    [[maybe_unused]] static const bool pxh_registered_##M = ::pxh::register_method(::pxh::make_method_info<M>())

}  // namespace pxh

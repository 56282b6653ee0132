// The method interface. A method is one folder methods/NAME/ with NAME.cpp (CPU reference,
// generic over float/double) that ends in PXH_REGISTER_METHOD(Type); nothing else to edit.
//
// A method type M provides:
//   static MethodInfo describe();                       name, citation, parameters
//   struct Config; static Config configure(const ParamValues&, const std::string& where);
//   static int max_fetches(const Config&, const Scene<double>&);   declared bound per sample
//   template <typename T> static Vec2<T> eval(const Config&, const Scene<T>&,
//                                             HeightSampler<T>&, Vec2<T> P);
//     (a search returns MethodHit<T> instead: its uv and the height z_m of its answer, the
//     value it computed itself, in its own precision; docs/conventions.md section 8)
//     or, for a method with resources (MethodInfo::resources, methods/resource.h),
//   template <typename T> static Vec2<T> eval(const Config&, const Scene<T>&,
//                                             HeightSampler<T>&, ResourceSamplers<T>&, Vec2<T> P);
//   optionally static GlUniforms gl_uniforms(const Config&);  the GLSL twin's uniforms that
//                                                       are not one parameter's value (a
//                                                       parameter that reaches the shader as
//                                                       it is names its uniform in its
//                                                       ParamSpec: ParamSpec::to_uniform)
//   optionally static void complete_params(ParamValues&); writes in the values an unset
//                                                       optional parameter stands for
//   optionally static HitHeight hit_height(const Config&); where its hit's height z_m is
//                                                       (methods/depth.h; default: ray when
//                                                       eval returns MethodHit, else surface)
//   optionally static Vec2d hit_direction(const Config&, Vec3d V, double s); a ray method's
//                                                       search line (default V.xy / V.z)
// and methods/NAME/NAME.frag.glsl defines vec2 pxh_method(vec2 P) (see methods/common.glsl).
//
// The shader interface (checked by the GLSL backend after linking, an error naming the method,
// the uniform and the shader file otherwise): the method's uniforms (method_uniforms(): the
// parameters' and gl_uniforms()) and one `uniform sampler2D NAME;` per resource are exactly the
// program's active uniforms besides the harness's u_* ones, each with the declared GLSL type
// (real: float, integer: int, bool: bool, choice: int, the index of the name). The shader reads
// a resource with pxh_texture(NAME, uv, level) (counted like pxh_height).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "harness/core/params.h"
#include "harness/core/vec.h"
#include "harness/scene/heightfield.h"
#include "harness/scene/scene.h"
#include "harness/scene/texture_levels.h"
#include "methods/depth.h"
#include "methods/resource.h"

namespace pxh {

// A uniform the method's shader reads, with its GLSL type and value.
enum class GlslType { Float, Int, Bool };
struct GlUniform {
    std::string name;
    GlslType type = GlslType::Float;
    double value = 0;
    static GlUniform real(std::string n, double v) { return {std::move(n), GlslType::Float, v}; }
    static GlUniform integer(std::string n, int v) {
        return {std::move(n), GlslType::Int, double(v)};
    }
    static GlUniform boolean(std::string n, bool v) {
        return {std::move(n), GlslType::Bool, v ? 1.0 : 0.0};
    }
};
using GlUniforms = std::vector<GlUniform>;
const char* glsl_type_name(GlslType t);  // "float", "int", "bool"

// What a method's C++ twin reads: the height field and the method's built resources (nullptr
// or empty for a method without resources); lambda[i]: sample i's level of detail (indexed
// like the batch's P; nullptr: 0), and with `levels` every height fetch of sample i is at that
// level of detail (the `level` mode).
struct MethodInputs {
    const HeightField* hf = nullptr;
    const MethodResources* resources = nullptr;
    const TextureLevels* levels = nullptr;
    const double* lambda = nullptr;
};

// Runs the method on n points. V: nullptr (every sample looks along sc.V, a parallel view) or
// n directions, sample i's toward its eye (the method sees it as sc.V). fetches[i]: all texture
// fetches of sample i (height and resources). texture_fetches: nullptr, or n x (1 + R) counts, per
// sample the height's then each resource's in declaration order. z: nullptr, or n heights z_m
// (MethodHit::z, the surface's at uv for a single-step method, not counted as a fetch);
// engine_z: nullptr, or n heights (MethodHit::engine_z, the surface's at uv where not given).
template <typename T>
using BatchFn = void (*)(const ParamValues&, const Scene<T>&, const MethodInputs&, const Vec2<T>* P,
                         const Vec3<T>* V, size_t n, Vec2<T>* uv, int* fetches,
                         int* texture_fetches, T* z, T* engine_z);

struct MethodInfo {
    std::string name;      // registry key = folder name = what users type
    std::string citation;  // the source, one line
    std::string summary;   // what it returns, one line
    std::vector<ParamSpec> params;
    bool exact_on_flat = false;  // returns the true point on any flat field
    int order = 100;             // listing order
    // May discard a sample (a NaN uv from the C++ twin, `discard` in the shader): the
    // silhouette-aware methods (docs/conventions.md section 12). The registry's tests then
    // allow non-finite answers and compare the twins' discards instead of their uv there.
    bool may_discard = false;
    // A may_discard method's own discard test, in a phrase (the row's note names it).
    std::string discard_test{};
    void (*check)(const ParamValues&, const std::string& where) = nullptr;
    int (*max_fetches)(const ParamValues&, const Scene<double>&) = nullptr;
    // The largest max_fetches over the scene seen along each of `Vs` (a perspective view's
    // rays), its parameters read once; nullptr exactly when max_fetches is.
    int (*max_fetches_over)(const ParamValues&, const Scene<double>&,
                            const std::vector<Vec3d>& Vs) = nullptr;
    // The uniforms the method computes (M::gl_uniforms); nullptr: none. The backend sets
    // method_uniforms(), which adds the parameters that name a uniform.
    GlUniforms (*gl_uniforms)(const ParamValues&) = nullptr;
    BatchFn<float> run_float = nullptr;
    BatchFn<double> run_double = nullptr;
    // Fills in the values that unset optional parameters stand for (checked values in), so
    // that `params` lists what ran; nullptr: nothing to fill.
    void (*complete_params)(ParamValues&) = nullptr;
    // Precomputed textures (methods/resource.h), in the order the C++ twin indexes them.
    std::vector<ResourceSpec> resources{};
    // The GLSL twin: empty: methods/NAME/NAME.frag.glsl, embedded in pxh. A method registered
    // elsewhere (a test's) names its file (relative to the source tree) and gives its text.
    std::string shader_path{};
    const char* shader_text = nullptr;
    // Generated GLSL the backend writes in place of the shader's `// @pxh-declarations` line
    // (harness/backends/shaders.h; the marcher's knob uniforms); empty: none.
    std::string shader_declarations{};
    // An engine preset whose engine fixes the reference plane: the bias b it draws its surface
    // with (NaN: any b), and why (one phrase, for the error an experiment with another b gets).
    double required_bias = NAN;
    std::string bias_reason{};
    // A plug-in shader named by an experiment ([[methods]] shader = FILE): the file (absolute;
    // read when compiled) and the fetch bound its entry declares (max_fetches). No CPU twin.
    std::string plugin_shader{};
    int declared_max_fetches = -1;
    // ... its text as read (and checked) when the experiment was parsed: what is compiled and
    // recorded, never the file read again; and its path as the user reaches it (messages).
    std::string plugin_source{};
    std::string plugin_display{};
    // The other files its text was made from, as the user reaches them (its #includes, then
    // pxh's engine adapter: harness/backends/engine_shader.h); file k is #line source 2 + k.
    std::vector<std::string> plugin_files{};
    // An HLSL or WGSL plug-in's own file and text (plugin_source is the GLSL made of it): where
    // a message about one of its names points.
    std::string plugin_original{};
    std::string plugin_original_display{};
    // Where it places its hit's height (methods/depth.h; the `hit` depth mode), for a setting
    // of its parameters; nullptr: surface (a plug-in shader: shader).
    HitHeight (*hit_height)(const ParamValues&) = nullptr;
    // A `ray` method's search line uv = P + d z (methods/depth.h) for a view direction V at
    // scale s; nullptr: the eye ray's, d = V.xy / V.z.
    Vec2d (*hit_direction)(const ParamValues&, Vec3d V, double scale) = nullptr;
    // The `engine` depth mode: depth(X_w) of the point its engine writes the depth of
    // (methods/depth.h); nullptr: the engine writes none (engine = base).
    double (*engine_depth)(const ParamValues&, const EngineDepthInput&) = nullptr;
    // An engine preset: the engine release it follows (methods/march/preset.h); "" otherwise.
    std::string engine_version{};
    HitHeight hit_height_of(const ParamValues& p) const {
        if (!plugin_shader.empty()) return HitHeight::shader;
        return hit_height ? hit_height(p) : HitHeight::surface;
    }
    // The shader's path relative to the source tree (shader_path or the default).
    std::string shader_file() const {
        return shader_path.empty() ? "methods/" + name + "/" + name + ".frag.glsl" : shader_path;
    }
};

// Sample i's height sampler: level 0, or the levels at its lambda.
template <typename T>
HeightSampler<T> height_sampler(const MethodInputs& in, const Scene<T>& sc, size_t i) {
    if (in.lambda) return HeightSampler<T>(*in.hf, sc.scale, sc.bias, in.levels, T(in.lambda[i]));
    return HeightSampler<T>(*in.hf, sc.scale, sc.bias);
}

// What eval returned, as uv and heights: z_m and engine_z (not counted as fetches).
template <typename T, typename R>
void store_answer(const R& r, HeightSampler<T>& hs, size_t i, Vec2<T>* uv, T* z, T* engine_z) {
    Vec2<T> u;
    T zm = std::numeric_limits<T>::quiet_NaN(), ze = zm;
    if constexpr (std::is_same_v<R, MethodHit<T>>) {
        u = r.uv;
        zm = r.z;
        ze = r.engine_z;
    } else {
        u = r;
    }
    uv[i] = u;
    if (!z && !engine_z) return;
    const bool finite = std::isfinite(u.x) && std::isfinite(u.y);
    T surface = std::numeric_limits<T>::quiet_NaN();
    if (finite && ((z && std::isnan(zm)) || (engine_z && std::isnan(ze)))) {
        const int before = hs.fetches;
        surface = hs.z(u);
        hs.fetches = before;
    }
    if (z) z[i] = !finite ? std::numeric_limits<T>::quiet_NaN() : std::isnan(zm) ? surface : zm;
    if (engine_z)
        engine_z[i] = !finite ? std::numeric_limits<T>::quiet_NaN() : std::isnan(ze) ? surface : ze;
}

template <class M, typename T>
void run_method_batch(const ParamValues& p, const Scene<T>& scene, const MethodInputs& in,
                      const Vec2<T>* P, const Vec3<T>* V, size_t n, Vec2<T>* uv, int* fetches,
                      int* texture_fetches, T* z, T* engine_z) {
    const typename M::Config cfg = M::configure(p, "");
    Scene<T> sc = scene;  // per sample: its own V when the view's rays are not parallel
    if constexpr (requires(HeightSampler<T> & hs, ResourceSamplers<T> & rs) {
                      M::template eval<T>(cfg, sc, hs, rs, Vec2<T>());
                  }) {
        ResourceSamplers<T> rs;
        if (in.resources)
            for (const BuiltResource& r : in.resources->items)
                rs.tex.emplace_back(*r.spec, *r.image);
        if (rs.tex.size() != M::describe().resources.size())
            throw std::logic_error("method resources missing: " + M::describe().name);
        const size_t stride = 1 + rs.tex.size();
        for (size_t i = 0; i < n; ++i) {
            HeightSampler<T> sampler = height_sampler(in, sc, i);
            if (V) sc.V = V[i];
            for (auto& t : rs.tex) t.fetches = 0;
            const auto r = M::template eval<T>(cfg, sc, sampler, rs, P[i]);
            fetches[i] = sampler.fetches + rs.fetches();
            if (texture_fetches) {
                texture_fetches[i * stride] = sampler.fetches;
                for (size_t k = 0; k < rs.tex.size(); ++k)
                    texture_fetches[i * stride + 1 + k] = rs.tex[k].fetches;
            }
            store_answer<T>(r, sampler, i, uv, z, engine_z);
        }
    } else {
        for (size_t i = 0; i < n; ++i) {
            HeightSampler<T> sampler = height_sampler(in, sc, i);
            if (V) sc.V = V[i];
            const auto r = M::template eval<T>(cfg, sc, sampler, P[i]);
            fetches[i] = sampler.fetches;
            if (texture_fetches) texture_fetches[i] = sampler.fetches;
            store_answer<T>(r, sampler, i, uv, z, engine_z);
        }
    }
}

// Whether M's eval returns MethodHit (a search handing back its z_m).
template <class M>
constexpr bool returns_hit() {
    using C = typename M::Config;
    if constexpr (requires(const C& c, const Scene<double>& sc, HeightSampler<double>& hs,
                           ResourceSamplers<double>& rs) {
                      M::template eval<double>(c, sc, hs, rs, Vec2d());
                  }) {
        using R = decltype(M::template eval<double>(
            std::declval<const C&>(), std::declval<const Scene<double>&>(),
            std::declval<HeightSampler<double>&>(), std::declval<ResourceSamplers<double>&>(),
            Vec2d()));
        return std::is_same_v<R, MethodHit<double>>;
    } else {
        using R = decltype(M::template eval<double>(
            std::declval<const C&>(), std::declval<const Scene<double>&>(),
            std::declval<HeightSampler<double>&>(), Vec2d()));
        return std::is_same_v<R, MethodHit<double>>;
    }
}

template <class M>
MethodInfo make_method_info() {
    MethodInfo info = M::describe();
    info.check = [](const ParamValues& p, const std::string& where) { M::configure(p, where); };
    info.max_fetches = [](const ParamValues& p, const Scene<double>& sc) {
        return M::max_fetches(M::configure(p, ""), sc);
    };
    info.max_fetches_over = [](const ParamValues& p, const Scene<double>& sc,
                               const std::vector<Vec3d>& Vs) {
        const typename M::Config c = M::configure(p, "");
        Scene<double> s = sc;
        int bound = 0;
        for (const Vec3d& V : Vs) {
            s.V = V;
            bound = std::max(bound, M::max_fetches(c, s));
        }
        return bound;
    };
    if constexpr (requires(const typename M::Config& c) { M::gl_uniforms(c); })
        info.gl_uniforms = [](const ParamValues& p) { return M::gl_uniforms(M::configure(p, "")); };
    info.run_float = &run_method_batch<M, float>;
    info.run_double = &run_method_batch<M, double>;
    if constexpr (requires(ParamValues & p) { M::complete_params(p); })
        info.complete_params = [](ParamValues& p) { M::complete_params(p); };
    if constexpr (requires(const typename M::Config& c) { M::hit_height(c); })
        info.hit_height = [](const ParamValues& p) { return M::hit_height(M::configure(p, "")); };
    else if constexpr (returns_hit<M>())
        info.hit_height = [](const ParamValues&) { return HitHeight::ray; };
    if constexpr (requires(const typename M::Config& c) { M::engine_depth(c, EngineDepthInput{}); })
        info.engine_depth = [](const ParamValues& p, const EngineDepthInput& in) {
            return M::engine_depth(M::configure(p, ""), in);
        };
    if constexpr (requires(const typename M::Config& c) { M::hit_direction(c, Vec3d(), 1.0); })
        info.hit_direction = [](const ParamValues& p, Vec3d V, double s) {
            return M::hit_direction(M::configure(p, ""), V, s);
        };
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

// Where a method setting's height fetches sample the texture levels (docs/conventions.md
// section 10; the [[methods]] key `lod`): base (level 0, the default), level (every fetch of a
// sample at its pixel's lambda, both twins), and on the GLSL backend only grad (textureGrad
// with the pixel's footprint) and implicit (texture() with the hardware's derivatives).
enum class LodMode { base, level, grad, implicit };
const char* lod_name(LodMode mode);
std::vector<std::string> lod_names();  // base, level, grad, implicit
// Whether only the GLSL backend can sample this way (grad, implicit).
inline bool lod_glsl_only(LodMode mode) {
    return mode == LodMode::grad || mode == LodMode::implicit;
}

// One method setting of an experiment: the method and its resolved parameters.
struct MethodSpec {
    const MethodInfo* method = nullptr;
    ParamValues params;
    // The height-field entries (by name) it runs on; empty: every one (the experiment's
    // [[methods]] key `heightfields`: e.g. an engine preset at its engine's scale and bias).
    std::vector<std::string> heightfields{};
    // A plug-in's `reference`: the built-in method (and parameters) whose CPU twin its GLSL
    // rows are compared with (the agreement columns); nullptr: none.
    const MethodInfo* reference = nullptr;
    ParamValues reference_params{};
    LodMode lod = LodMode::base;        // the entry's `lod`
    DepthMode depth = DepthMode::base;  // the entry's `depth` (methods/depth.h)
    // [views] cut: the height c of the opaque plane its rows test against (NaN: none).
    double cut = NAN;
    bool runs_on(const std::string& field) const {
        if (heightfields.empty()) return true;
        for (const auto& f : heightfields)
            if (f == field) return true;
        return false;
    }
};

#define PXH_REGISTER_METHOD(M)                              \
    [[maybe_unused]] static const bool pxh_registered_##M = \
        ::pxh::register_method(::pxh::make_method_info<M>())

}  // namespace pxh

// Helpers shared by the tests: random fields, a brute-force ray march, method evaluation, the
// registered methods by name and as the values of a registry-wide suite, and an inline experiment
// run or its parse error.
#pragma once
#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/core/error.h"
#include "harness/experiment/experiment.h"
#include "harness/metrics/columns.h"
#include "harness/run/runner.h"
#include "harness/scene/heightfield.h"
#include "harness/truth/ground_truth.h"
#include "heightfields/heightfields.h"
#include "methods/method.h"

namespace pxh::test {

// The message of the InputError `f()` throws, or "" when it throws none.
template <class F>
std::string input_error(F f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

// The rows of running the experiment TOML text (parsed as the file "e.toml") with default options.
inline std::vector<ResultRow> run(const std::string& toml) {
    return run_experiment(parse_experiment(toml, "e.toml"), {});
}

// The message of the InputError parsing the experiment TOML text (as the file "e.toml") throws,
// or "(no error)" when it parses.
inline std::string parse_error(const std::string& toml) {
    try {
        (void)parse_experiment(toml, "e.toml");
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no error)";
}

inline HeightField random_field(int w, int h, uint32_t seed, float lo = 0.0f, float hi = 1.0f) {
    HeightField hf(w, h, "random");
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> d(lo, hi);
    for (auto& t : hf.texels) t = d(rng);
    return hf;
}

// The names of results.csv's columns, in file order.
inline std::vector<std::string> result_column_names() {
    std::vector<std::string> out;
    for (const ColumnSpec* c : result_column_specs()) out.push_back(c->name);
    return out;
}

// A procedural field at its generator's default parameters, W x H (H = W when not given).
inline HeightField generated_field(const std::string& generator, int w, int h = 0) {
    const GeneratorInfo* g = find_generator(generator);
    if (!g) throw std::logic_error("no generator " + generator);
    return generate_heightfield(*g, w, h > 0 ? h : w,
                                resolve_params(g->params, {}, "test", generator));
}

// An experiment's [[heightfields]] entry for a generator at its default parameters, size x size
// (scale and bias left at their defaults: the caller sets them).
inline HeightfieldSpec generator_spec(const std::string& generator, int size) {
    HeightfieldSpec hs;
    hs.name = hs.generator = generator;
    hs.width = hs.height = size;
    hs.gen_params = resolve_params(find_generator(generator)->params, {}, "t", generator);
    return hs;
}

inline HeightField flat_field(int w, int h, float level) {
    HeightField hf(w, h, "flat");
    for (auto& t : hf.texels) t = level;
    return hf;
}

// Brute force: march from the slab top along -V in steps of `step` (world units), first
// point at or below the surface, refined by bisection. Independent of ExactTracer: it uses
// HeightSampler (the method-side bilinear code) for heights.
inline Vec2d brute_force_hit(const HeightField& hf, double s, double b, Vec2d P, Vec3d V,
                             double step) {
    HeightSampler<double> hs(hf, s, b);
    const double zt = s * (1 - b);
    const Vec2d E{P.x + V.x / V.z * zt, P.y + V.y / V.z * zt};
    auto f = [&](double tau) {
        return (zt - tau * V.z) - hs.z({E.x - tau * V.x, E.y - tau * V.y});
    };
    const double tau_max = s / V.z;
    double prev = 0;
    if (f(0) <= 0) return E;
    for (double tau = step;; tau += step) {
        const double t = std::min(tau, tau_max);
        if (f(t) <= 0) {
            double lo = prev, hi = t;
            for (int i = 0; i < 100; ++i) {
                const double mid = 0.5 * (lo + hi);
                (f(mid) > 0 ? lo : hi) = mid;
            }
            return {E.x - hi * V.x, E.y - hi * V.y};
        }
        if (t >= tau_max) return {E.x - tau_max * V.x, E.y - tau_max * V.y};
        prev = t;
    }
}

inline Scene<double> make_scene(const HeightField& hf, double s, double b, double theta,
                                double phi = 0) {
    return {s, b, view_vector(theta, phi), hf.width, hf.height};
}

// Runs a registered method on given points in precision T; returns uv (as double), fetches and
// the height z_m it handed back (MethodHit::z, or the surface's at uv for a single-step method).
template <typename T>
std::vector<Vec2d> run_method(const MethodInfo& m, const ParamValues& p, const Scene<double>& sc,
                              const HeightField& hf, const std::vector<Vec2d>& P,
                              std::vector<int>* fetches = nullptr,
                              std::vector<int>* per_texture = nullptr,
                              std::vector<double>* z_m = nullptr) {
    std::vector<Vec2<T>> pts(P.size()), uv(P.size());
    std::vector<T> zs(z_m ? P.size() : 0);
    T* z = z_m ? zs.data() : nullptr;
    std::vector<int> f(P.size());
    ResourceCache cache(hf);  // the method's resources, if it declares any
    const MethodResources res = cache.get(m.name, m.resources, sc.scale, sc.bias, &p);
    const MethodInputs in{&hf, &res};
    std::vector<int> split(per_texture ? P.size() * (1 + m.resources.size()) : 0);
    for (size_t i = 0; i < P.size(); ++i) pts[i] = Vec2<T>(P[i]);
    const Scene<T> st = scene_cast<T>(sc);
    if constexpr (std::is_same_v<T, float>)
        m.run_float(p, st, in, pts.data(), nullptr, pts.size(), uv.data(), f.data(),
                    per_texture ? split.data() : nullptr, z, nullptr);
    else
        m.run_double(p, st, in, pts.data(), nullptr, pts.size(), uv.data(), f.data(),
                     per_texture ? split.data() : nullptr, z, nullptr);
    if (fetches) *fetches = f;
    if (per_texture) *per_texture = split;
    if (z_m) z_m->assign(zs.begin(), zs.end());
    std::vector<Vec2d> out(P.size());
    for (size_t i = 0; i < P.size(); ++i) out[i] = Vec2d(uv[i]);
    return out;
}

inline ParamValues params_for(const MethodInfo& m, const GivenParams& given = {}) {
    return resolve_params(m.params, given, "test", m.name);
}

// The registered method NAME (a test failure naming it, not a crash, when there is none).
inline const MethodInfo& method(const std::string& name) {
    const MethodInfo* m = find_method(name);
    if (!m) throw std::runtime_error("no registered method '" + name + "'");
    return *m;
}

// The names of the registered methods (those KEEP accepts; all without it), in registry order:
//   INSTANTIATE_TEST_SUITE_P(Registry, Suite, ValuesIn(method_names()), MethodName())
// covers every method, a new one included, without editing the suite.
inline std::vector<std::string> method_names(
    const std::function<bool(const MethodInfo&)>& keep = nullptr) {
    std::vector<std::string> n;
    for (const auto& m : all_methods())
        if (!keep || keep(m)) n.push_back(m.name);
    return n;
}

// gtest's name generator for a suite over method names: each test is named after its method.
struct MethodName {
    std::string operator()(const ::testing::TestParamInfo<std::string>& info) const {
        return info.param;
    }
};

inline std::vector<Vec2d> random_points(int n, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> d(0.0, 1.0);
    std::vector<Vec2d> p(n);
    for (auto& q : p) q = {d(rng), d(rng)};
    return p;
}

}  // namespace pxh::test

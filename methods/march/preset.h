// An engine preset of the parametric marcher as a data row: the knobs the engine fixes, the
// engine's own parameters (each setting one knob), the citation, and what the engine fixes of
// the scene. One file per engine (methods/march/presets/ENGINE.cpp), one registration line per
// row: PXH_REGISTER_PRESET(kRow). How to write one: methods/march/PRESETS.md.
#pragma once
#include <cmath>
#include <string>
#include <vector>

#include "methods/march/march.h"

namespace pxh {

// An engine parameter (the engine's name, default and range) and the knob it sets: with its
// value as it is (a number; a bool as 0 / 1), or, when `values` is given (a choice parameter),
// with values[i] for the i-th choice.
struct PresetParam {
    ParamSpec spec;
    MarchKnob knob;
    std::vector<double> values{};
};

struct MarchPresetRow {
    std::string name;      // what users type
    std::string citation;  // repository, file, commit
    std::string summary;   // what it computes, one line
    // The knobs the engine fixes, as designated initialisers in the table's order
    // (methods/march/knobs.h); the others keep the table's defaults.
    MarchConfig knobs{};
    std::vector<PresetParam> params{};  // set after `knobs`, in order
    bool exact_on_flat = false;  // true exactly when it returns the true point on flat fields
    int order = 300;             // listing order: 300 + a small number
    // The bias b the engine draws its surface with (NaN: any b), and why (one phrase).
    double required_bias = NAN;
    std::string bias_reason{};
    // Knobs that follow from others once the parameters are set (O3DE relief: iterations = n - 1).
    void (*derive)(MarchConfig&) = nullptr;
    // Input checks on the knobs, InputError(where, ...) (the `march` method's).
    void (*check)(const MarchConfig&, const std::string& where) = nullptr;
    // The engine release (or, where none was checked, the source commit) the preset follows:
    // what `pxh list methods` shows as "follows".
    std::string engine_version{};
};

// The knobs a row gives for the parameters' values p.
MarchConfig preset_config(const MarchPresetRow& row, const ParamValues& p,
                          const std::string& where);
// The method the row describes (its GLSL twin: methods/march/march.frag.glsl with the knobs'
// generated declarations).
MethodInfo preset_info(const MarchPresetRow& row);

// A row as a method type (methods/method.h).
template <const MarchPresetRow& Row>
struct MarchPreset {
    using Config = MarchConfig;
    static MethodInfo describe() { return preset_info(Row); }
    static Config configure(const ParamValues& p, const std::string& where) {
        return preset_config(Row, p, where);
    }
    static int max_fetches(const Config& c, const Scene<double>& sc) {
        return march_max_fetches(c, sc);
    }
    static GlUniforms gl_uniforms(const Config& c) { return march_uniforms(c); }
    // The offset search is one fetch (its hit: the surface at uv); the layered search returns
    // a point of its own line uv = P + d z (d: march_direction; the eye ray's only with
    // step = tan, no max_slope, no mirror_v).
    static HitHeight hit_height(const Config& c) {
        return c.search == MarchConfig::Offset ? HitHeight::surface : HitHeight::ray;
    }
    static double engine_depth(const Config& c, const EngineDepthInput& in) {
        return march_engine_depth(c, in);
    }
    static Vec2d hit_direction(const Config& c, Vec3d V, double scale) {
        Scene<double> sc;
        sc.V = V;
        sc.scale = scale;
        return march_direction(c, sc);
    }
    template <typename T>
    static MethodHit<T> eval(const Config& c, const Scene<T>& sc, HeightSampler<T>& hs, Vec2<T> P) {
        return march(c, sc, hs, P);
    }
};

#define PXH_REGISTER_PRESET(row)                              \
    [[maybe_unused]] static const bool pxh_registered_##row = \
        ::pxh::register_method(::pxh::make_method_info<::pxh::MarchPreset<row>>())

}  // namespace pxh

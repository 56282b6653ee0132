// Experiment files (TOML): what to run. Parsing checks every key; a bad file is an InputError
// naming the file and line.
#pragma once
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "harness/heightfield.h"
#include "harness/params.h"
#include "methods/method.h"

namespace pxh {

struct HeightfieldSpec {
    std::string name;       // as reported in results
    std::string generator;  // either a generator ...
    std::string file;       // ... or an image file (resolved path)
    std::string scan;       // ... or an imported scan (heightfields/scanned/NAME)
    int width = 256, height = 256;
    int channel = 0;
    ParamValues gen_params;
    double scale = 0.05, bias = 1.0;
    std::string where;  // file:line of the entry, for errors
};

struct MethodSpec {
    const MethodInfo* method = nullptr;
    ParamValues params;
};

// Optional directional light for the self-shadowing metrics.
struct LightSpec {
    double theta_deg = 45, phi_deg = 180;
    double layers_min = 8, layers_max = 32;  // the shadow march's layer counts
};

struct Experiment {
    std::string name;
    std::string path;  // the file it came from
    std::string text;  // its content, recorded in provenance
    int samples = 256;
    std::vector<std::string> backends{"cpu"};
    std::vector<std::string> precisions{"float"};
    std::vector<std::string> texture_formats{"r32f"};  // GLSL height texture: r32f | r16 | r8
    int timing_repeats = 5;
    std::string ground_truth = "exact";
    double sweep_dt_deg = 0;  // > 0: sliding/shimmering from a companion view dt away
    bool maps = false;        // write per-row error maps
    bool exclude_filled = false;  // leave samples whose truth lands on filled holes out  // the reference the errors are measured against
    std::vector<double> theta_deg, phi_deg{0.0};
    std::optional<LightSpec> light;
    std::vector<HeightfieldSpec> heightfields;  // arrays of scale/bias already expanded
    std::vector<MethodSpec> methods;            // arrays of parameter values already expanded
};

Experiment load_experiment(const std::string& path);
Experiment parse_experiment(const std::string& text, const std::string& path);

// Materialises a height field (generates or loads); throws InputError.
HeightField make_heightfield(const HeightfieldSpec& spec);

}  // namespace pxh

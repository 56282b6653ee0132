// The CPU backend: each method's C++ reference, in float or double, over every sample.
#pragma once
#include "harness/backends/backend.h"

namespace pxh {

// Runs the method on every sample in the given precision ("float"/"double"), in parallel
// (outputs do not depend on threads), then times `repeats` single-thread passes after one
// warm-up pass: its timing, in ns per sample (cpu_timing). V: nullptr (every sample looks along
// scene.V) or one direction per sample. lambda (one per sample): each sample's level of detail
// (what a method reads as HeightSampler::lod()), and with `levels` every height fetch of sample k
// is at lambda[k] on those levels (lod = level).
MethodOutput run_cpu(const MethodSpec& m, const std::string& precision, const Scene<double>& scene,
                     const HeightField& hf, const std::vector<Vec2d>& P, int repeats,
                     const MethodResources* resources = nullptr,
                     const std::vector<Vec3d>* V = nullptr, const TextureLevels* levels = nullptr,
                     const std::vector<double>* lambda = nullptr);

// The CPU backend's timing: ns/sample, no counters.
const TimingSpec& cpu_timing();

// The tutorial's hard and soft self-shadowing at each output uv, in the given precision.
void add_shadows(MethodOutput& out, const LightSpec& light, const std::string& precision,
                 const Scene<double>& scene, const HeightField& hf);

// "" when the CPU backend runs setting m, else why not (its registry entry's skips).
std::string cpu_skips(const MethodSpec& m);

class CpuBackend : public Backend {
  public:
    explicit CpuBackend(BackendSettings settings) : settings_(std::move(settings)) {}
    std::string name() const override { return "cpu"; }
    std::vector<Variant> variants() const override;
    // Methods with a C++ twin, in the level modes both twins share (base, level).
    bool runs(const MethodSpec& m) const override { return cpu_skips(m).empty(); }
    MethodOutput run(const MethodSpec& m, const ViewInput& view, const Variant& v) override;

  private:
    BackendSettings settings_;
};

}  // namespace pxh

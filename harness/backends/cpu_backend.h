// The CPU backend: each method's C++ reference, in float or double, over every sample.
#pragma once
#include "harness/backends/backend.h"

namespace pxh {

// Runs the method on every sample in the given precision ("float"/"double"), in parallel
// (outputs do not depend on threads), then times `repeats` single-thread passes after one
// warm-up pass; ns_per_sample is their median. V: nullptr (every sample looks along scene.V)
// or one direction per sample.
MethodOutput run_cpu(const MethodSpec& m, const std::string& precision, const Scene<double>& scene,
                     const HeightField& hf, const std::vector<Vec2d>& P, int repeats,
                     const MethodResources* resources = nullptr,
                     const std::vector<Vec3d>* V = nullptr);

// The tutorial's hard and soft self-shadowing at each output uv, in the given precision.
void add_shadows(MethodOutput& out, const LightSpec& light, const std::string& precision,
                 const Scene<double>& scene, const HeightField& hf);

class CpuBackend : public Backend {
  public:
    explicit CpuBackend(BackendSettings settings) : settings_(std::move(settings)) {}
    std::string name() const override { return "cpu"; }
    std::vector<Variant> variants() const override;
    bool runs(const MethodInfo& m) const override { return m.run_float && m.run_double; }
    MethodOutput run(const MethodSpec& m, const ViewInput& view, const Variant& v) override;

  private:
    BackendSettings settings_;
};

}  // namespace pxh

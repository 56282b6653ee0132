// Random views of random fields on a curved base, for the pyramid tracer's tests
// (curved_pyramid_test.cpp against the walk, curved_pyramid_lanes_test.cpp against trace_one):
// fields of 3 to 62 texels a side (three in ten with plateaus, whose tops rays meet exactly),
// the cylinder or the sphere, R from 0.1 to 1e6, s from 0.005 to 0.5, b in [0, 1], theta to 89
// degrees, any phi, orthographic or perspective cameras (eyes 0.6 to 4.6 tiles away), 16 x 16
// rays. One call draws one view from `rng`, always the same numbers in the same order.
#pragma once
#include <cmath>
#include <memory>
#include <random>
#include <string>

#include "harness/scene/base_surface.h"
#include "harness/scene/curved_view.h"
#include "harness/scene/perspective_camera.h"
#include "tests/test_util.h"

namespace pxh::test {

struct RandomCurvedView {
    HeightField hf;
    std::string name;  // "cylinder" or "sphere"
    double s, b, R, theta;
    std::unique_ptr<BaseSurface> base;
    CurvedView cv;
};

// The next view, or nullptr where the drawn perspective eye sits in the relief (skipped).
inline std::unique_ptr<RandomCurvedView> random_curved_view(std::mt19937& rng) {
    std::uniform_real_distribution<double> U(0, 1);
    const int W = 3 + int(U(rng) * 60), H = 3 + int(U(rng) * 60);
    HeightField hf = random_field(W, H, uint32_t(rng()));
    if (U(rng) < 0.3)
        for (float& t : hf.texels) t = t > 0.7f ? t : 0.2f;
    const char* name = U(rng) < 0.5 ? "cylinder" : "sphere";
    const double s = std::exp(std::log(0.005) + U(rng) * std::log(0.5 / 0.005));
    const double b = U(rng) < 0.5 ? 1.0 : U(rng);
    double R = std::exp(std::log(0.1) + U(rng) * std::log(1e6 / 0.1));
    if (R <= s * b * 1.05) R = s * b * 1.05 + 0.01;
    auto base = make_base(name, R);
    const double theta = U(rng) * 89, phi = U(rng) * 360;
    std::unique_ptr<Camera> cam;
    if (U(rng) < 0.5) {
        cam = std::make_unique<OrthographicCamera>(theta, phi, 16);
    } else {
        PerspectiveParams p;
        p.theta_deg = theta;
        p.phi_deg = phi;
        p.distance = 0.6 + U(rng) * 4;
        p.fov_deg = 20 + U(rng) * 60;
        p.samples = 16;
        if (p.distance * std::cos(theta * M_PI / 180) <= s * (1 - b) + 0.05) return nullptr;
        cam = std::make_unique<PerspectiveCamera>(p);
    }
    CurvedView cv = curved_view(*cam, *base, s * (1 - b));
    return std::unique_ptr<RandomCurvedView>(
        new RandomCurvedView{std::move(hf), name, s, b, R, theta, std::move(base), std::move(cv)});
}

}  // namespace pxh::test

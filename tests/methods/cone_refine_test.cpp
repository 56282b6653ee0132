// `cone`'s refinement (methods/cone/cone.md), after Ban, Valasek, Balint, Vad, "Robust Cone Step
// Mapping", EGSR 2024, github.com/Bundas102/robust-cone-map commit 2dbc39b, Refinement.slang
// (refineIntersection_linearApprox, refineIntersection_binarySearch) on the depths before and
// after the loop's last step (FindIntersection.slang: last_t, t). Checked against: the closed
// form on a plane (the chord is the surface), a literal transcription of the two functions on
// the bracket the loop produced, and the bisection's error bound.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "methods/method.h"
#include "methods/resource.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

using Vec2f = Vec2<float>;

const MethodInfo& cone() { return *find_method("cone"); }

// h = (x + 2 y) / 256 at texel coordinates (x, y) = (u W - 1/2, v H - 1/2): every height is a
// dyadic float, so the bilinear surface is this plane exactly wherever it does not wrap
// (u, v in [1/2W, 1 - 1/2W]).
HeightField plane_field(int n) {
    HeightField hf(n, n, "plane");
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            hf.texels[size_t(j) * size_t(n) + size_t(i)] = float(i + 2 * j) / 256;
    return hf;
}

// The depth where the ray uv0 + m t, height 1 - t, meets that plane.
double plane_hit(const HeightField& hf, Vec2d uv0, Vec2d m) {
    const double W = hf.width, H = hf.height;
    const double h0 = ((uv0.x * W - 0.5) + 2 * (uv0.y * H - 0.5)) / 256;
    const double dh = (m.x * W + 2 * m.y * H) / 256;  // dh/dt along the ray
    return (1 - h0) / (1 + dh);
}

// cone.cpp's loop, transcribed (the same operations in T): the depths before and after the
// last step, and the number of steps.
template <typename T>
struct Bracket {
    T t0 = 0, t1 = 0;
    int taken = 0;
};

template <typename T>
T to_border(Vec2<T> p, Vec2<T> m, int W, int H, bool& any) {
    T d = T(0);
    any = false;
    if (m.x != T(0)) {
        const T i0 = std::floor(p.x * T(W) - T(0.5));
        d = ((i0 + (m.x > T(0) ? T(1.5) : T(0.5))) / T(W) - p.x) / m.x;
        any = true;
    }
    if (m.y != T(0)) {
        const T j0 = std::floor(p.y * T(H) - T(0.5));
        const T dy = ((j0 + (m.y > T(0) ? T(1.5) : T(0.5))) / T(H) - p.y) / m.y;
        d = any ? std::min(d, dy) : dy;
        any = true;
    }
    return d;
}

template <typename T>
Bracket<T> cone_loop(const Scene<T>& sc, TextureSampler<T>& map, Vec2<T> P, int steps, int channel,
                     int min_step) {
    const Vec2<T> D = sc.V.xy() * (T(1) / sc.V.z);
    const Vec2<T> uv0 = P + D * sc.z_top(), m = D * (-sc.scale);
    const T dist = std::sqrt(m.x * m.x + m.y * m.y);
    const T dsz = T(1) / std::sqrt(T(1) + dist * dist);
    Bracket<T> b;
    std::array<T, 4> tex = map.fetch(uv0, 0);
    while (b.taken < steps && T(1) - b.t1 - tex[0] > T(0x1p-20)) {
        b.t0 = b.t1;
        const T c = tex[size_t(channel)];
        const T cone = c * (T(1) - b.t1 - tex[0]) / (dist + c);
        T w = T(0);
        bool any = false;
        if (min_step == 0) w = dsz / T(sc.width);
        if (min_step == 1) {
            const T d = to_border(uv0 + m * b.t1, m, sc.width, sc.height, any);
            if (any) w = d + T(1e-5) * dsz;
        }
        b.t1 = b.t1 + std::max(w, cone);
        tex = map.fetch(uv0 + m * b.t1, 0);
        ++b.taken;
    }
    return b;
}

// Refinement.slang, literally, in float. HLSL: lerp(a, b, s) = a + s (b - a); clamp is
// min(max(x, lo), hi) with D3D's min/max returning the other operand for a NaN (std::fmin,
// std::fmax); getH is the map's r channel (Parallax.ps.slang: the red channel of the texture
// whose (r, g) the cone loop reads).
struct Slang {
    TextureSampler<float>& map;
    unsigned refine_steps;
    float getH(Vec2f uv) { return map.fetch(uv, 0)[0]; }
    static Vec2f lerp(Vec2f a, Vec2f b, float s) { return a + (b - a) * s; }
    Vec2f refineIntersection_linearApprox(float last_t, float it, Vec2f u0, Vec2f u1) {
        float t0 = last_t;
        float t1 = it;
        float h0 = getH(lerp(u0, u1, t0));
        float h1 = getH(lerp(u0, u1, t1));
        float dt = t1 - t0;
        float t = (dt + t0 * h1 - t1 * h0) / (dt + h1 - h0);
        t = std::fmin(std::fmax(t, t0), t1);
        return lerp(u0, u1, t);
    }
    Vec2f refineIntersection_binarySearch(float last_t, float it, Vec2f u0, Vec2f u1) {
        float t0 = last_t;
        float t1 = it;
        float th = 0.5f * (t0 + t1);
        for (unsigned i = 0; i < refine_steps; ++i) {
            float fh = getH(lerp(u0, u1, th));
            if (fh > 1 - th) t1 = th;
            else t0 = th;
            th = 0.5f * (t0 + t1);
        }
        return lerp(u0, u1, th);
    }
};

double texel_dist(Vec2d a, Vec2d b, const HeightField& hf) {
    return std::hypot((a.x - b.x) * hf.width, (a.y - b.y) * hf.height);
}

// The plane field's cone map at s = 0.05, b = 1, and 64 random points in its middle
// (0.3..0.7 in u and v; `seed` picks them).
struct PlaneCone {
    explicit PlaneCone(uint32_t seed)
        : res(build_resource(cone().resources[0], hf, s, b)),
          map(*res.spec, *res.image),
          P(test::random_points(64, seed)) {
        for (Vec2d& p : P) p = {0.3 + 0.4 * p.x, 0.3 + 0.4 * p.y};
    }
    HeightField hf = plane_field(64);
    double s = 0.05, b = 1;
    BuiltResource res;
    TextureSampler<double> map;
    std::vector<Vec2d> P;
};

struct Setting {
    const char* map;
    int channel;
    const char* min_step;
    int min_step_index;
    int steps;
};

// (a) On a plane the chord through any two surface points along the ray is the surface: the
// linear refinement returns the exact hit clamped to the bracket [t0, t1] the loop produced,
// whatever the map, minimum step and step count (steps = 1 or 2: brackets that end above the
// surface). Without the refinement the same rays are up to a cell off.
TEST(ConeRefine, LinearRefinementIsExactOnAPlane) {
    PlaneCone pc(3);
    auto& [hf, s, b, res, map, P] = pc;
    const Setting settings[] = {{"dummer", 1, "texel", 0, 32},  {"dummer_min", 2, "cell", 1, 32},
                                {"bilinear", 3, "none", 2, 32}, {"dummer_min", 2, "cell", 1, 1},
                                {"bilinear", 3, "none", 2, 2},  {"dummer", 1, "texel", 0, 3}};
    double worst = 0, worst_none = 0;
    long long n = 0, open = 0;
    for (const Setting& st : settings)
        for (double theta : {20.0, 45.0, 70.0, 80.0})
            for (double phi : {0.0, 30.0, 135.0, 250.0}) {
                const Scene<double> sc = test::make_scene(hf, s, b, theta, phi);
                const GivenParams none = {
                    {"map", st.map}, {"min_step", st.min_step}, {"steps", st.steps}};
                const GivenParams lin = {{"map", st.map},
                                         {"min_step", st.min_step},
                                         {"steps", st.steps},
                                         {"refine", "linear"}};
                const auto uv =
                    test::run_method<double>(cone(), test::params_for(cone(), lin), sc, hf, P);
                const auto uv_none =
                    test::run_method<double>(cone(), test::params_for(cone(), none), sc, hf, P);
                const Vec2d D = sc.V.xy() * (1 / sc.V.z);
                const Vec2d m = D * -s;
                for (size_t i = 0; i < P.size(); ++i) {
                    const Vec2d uv0 = P[i] + D * sc.z_top();
                    const Bracket<double> br =
                        cone_loop<double>(sc, map, P[i], st.steps, st.channel, st.min_step_index);
                    const double t_star = plane_hit(hf, uv0, m);
                    open += t_star > br.t1;
                    const Vec2d want = uv0 + m * std::clamp(t_star, br.t0, br.t1);
                    worst = std::max(worst, texel_dist(uv[i], want, hf));
                    if (st.steps == 32)
                        worst_none = std::max(worst_none, texel_dist(uv_none[i], want, hf));
                    ++n;
                }
            }
    EXPECT_LT(worst, 1e-9);
    EXPECT_GT(worst_none, 0.1);
    EXPECT_GT(open, 0);  // some brackets end above the surface: the clamp is exercised
    std::printf(
        "[ cone ] plane: linear refinement %.2g texel from the exact hit (%lld rays, %lld "
        "brackets above it); no refinement up to %.3f texel\n",
        worst, n, open, worst_none);
}

// (b) The method's refinement is Refinement.slang's: the literal transcription above, applied
// to the bracket of the transcribed loop, gives the same uv (CPU float, random fields), and the
// fetch count is the loop's + 2 (linear) or + refine_steps (binary), within max_fetches.
TEST(ConeRefine, RefinementIsTheSourcesOnTheLoopsBracket) {
    struct Case {
        Setting st;
        const char* refine;
        int refine_steps;
    };
    const Case cases[] = {{{"dummer_min", 2, "cell", 1, 32}, "linear", 5},
                          {{"dummer_min", 2, "cell", 1, 32}, "binary", 5},
                          {{"bilinear", 3, "none", 2, 12}, "linear", 5},
                          {{"bilinear", 3, "none", 2, 12}, "binary", 9},
                          {{"dummer", 1, "texel", 0, 6}, "binary", 2},
                          {{"dummer", 1, "texel", 0, 6}, "linear", 5}};
    long long n = 0, off = 0, fetch_off = 0, over = 0;
    for (uint32_t seed : {21u, 22u}) {
        const HeightField hf = test::random_field(24 + int(seed % 2) * 8, 24, seed);
        const double s = 0.05, b = 1;
        const BuiltResource res = build_resource(cone().resources[0], hf, s, b);
        TextureSampler<float> map(*res.spec, *res.image);
        const std::vector<Vec2d> P = test::random_points(300, seed + 100);
        for (const Case& c : cases)
            for (double theta : {30.0, 60.0, 80.0})
                for (double phi : {10.0, 200.0}) {
                    const Scene<double> sc = test::make_scene(hf, s, b, theta, phi);
                    const Scene<float> sf = scene_cast<float>(sc);
                    const ParamValues p =
                        test::params_for(cone(), {{"map", c.st.map},
                                                  {"min_step", c.st.min_step},
                                                  {"steps", c.st.steps},
                                                  {"refine", c.refine},
                                                  {"refine_steps", c.refine_steps}});
                    std::vector<int> fetches;
                    const auto uv = test::run_method<float>(cone(), p, sc, hf, P, &fetches);
                    const int bound = cone().max_fetches(p, sc);
                    const bool lin = std::string(c.refine) == "linear";
                    Slang slang{map, unsigned(c.refine_steps)};
                    const Vec2f D = sf.V.xy() * (1.0f / sf.V.z);
                    for (size_t i = 0; i < P.size(); ++i) {
                        const Vec2f uv0 = Vec2f(P[i]) + D * sf.z_top();
                        const Vec2f u1 = uv0 + D * (-sf.scale);
                        const Bracket<float> br = cone_loop<float>(
                            sf, map, Vec2f(P[i]), c.st.steps, c.st.channel, c.st.min_step_index);
                        const Vec2f want =
                            lin ? slang.refineIntersection_linearApprox(br.t0, br.t1, uv0, u1)
                                : slang.refineIntersection_binarySearch(br.t0, br.t1, uv0, u1);
                        off += !(texel_dist(uv[i], Vec2d(want), hf) <= 1e-4);
                        fetch_off += fetches[i] != br.taken + 1 + (lin ? 2 : c.refine_steps);
                        over += fetches[i] > bound;
                        ++n;
                    }
                }
    }
    // The few apart are rays still above the surface when the steps ran out, on a bracket of
    // ~1e-4 texel: the chord's extrapolation (then clamped) is ill-conditioned, and HLSL's lerp
    // (u0 + t (u1 - u0)) rounds unlike uv0 + m t (measured: 8 of 21600, all linear, steps 12).
    EXPECT_LE(off, n / 1000) << "of " << n;
    EXPECT_EQ(fetch_off, 0);
    EXPECT_EQ(over, 0);
    std::printf(
        "[ cone ] random fields: %lld of %lld refined uv more than 1e-4 texel from "
        "Refinement.slang's\n",
        off, n);
}

// (c) On a plane each bisection halves the bracket around the hit: after k steps
// |t - t*| <= (t1 - t0) / 2^(k+1), t* the exact hit clamped to [t0, t1]; the bound is reached
// to within a factor 2 on some ray.
TEST(ConeRefine, BinaryRefinementHalvesTheErrorPerStepOnAPlane) {
    PlaneCone pc(5);
    auto& [hf, s, b, res, map, P] = pc;
    for (int k : {0, 1, 2, 3, 5, 8, 12}) {
        double worst_ratio = 0;
        int over = 0;
        for (double theta : {30.0, 60.0, 80.0})
            for (double phi : {0.0, 100.0}) {
                const Scene<double> sc = test::make_scene(hf, s, b, theta, phi);
                const ParamValues p = test::params_for(cone(), {{"map", "dummer_min"},
                                                                {"min_step", "cell"},
                                                                {"refine", "binary"},
                                                                {"refine_steps", k}});
                const auto uv = test::run_method<double>(cone(), p, sc, hf, P);
                const Vec2d D = sc.V.xy() * (1 / sc.V.z);
                const Vec2d m = D * -s;
                for (size_t i = 0; i < P.size(); ++i) {
                    const Vec2d uv0 = P[i] + D * sc.z_top();
                    const Bracket<double> br = cone_loop<double>(sc, map, P[i], 32, 2, 1);
                    const double t_star = std::clamp(plane_hit(hf, uv0, m), br.t0, br.t1);
                    const Vec2d d = uv[i] - uv0;
                    const double t = (d.x * m.x + d.y * m.y) / (m.x * m.x + m.y * m.y);
                    const double bound = (br.t1 - br.t0) / std::ldexp(1.0, k + 1);
                    over += !(std::abs(t - t_star) <= bound + 1e-12);
                    worst_ratio = std::max(worst_ratio, std::abs(t - t_star) / bound);
                }
            }
        EXPECT_EQ(over, 0) << "k " << k << ": rays past the bound, the worst at x" << worst_ratio;
        EXPECT_GT(worst_ratio, 0.5) << "k " << k;
    }
}

}  // namespace
}  // namespace pxh

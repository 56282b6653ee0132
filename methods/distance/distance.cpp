// Donnelly, "Per-Pixel Displacement Mapping with Distance Functions", GPU Pearls: GPU Gems 2,
// ch. 8, Addison-Wesley 2005, pp. 123-136: a 3D distance map over the relief's slab, and sphere
// tracing with a fixed number of steps, each step the distance read at the current point
// (shader structure as in cginternals/gloperate source/gloperate/source/primitives/
// TexturedObject.cpp @ 56b28fb8e1cfda9beb8f7a5f6736caed25af7a24: 16 steps, 16 depth layers).
// What pxh does (methods/distance/distance.md):
// - Voxel space: X = u W, Y = v H, Z = (zeta - z_bot) / s D = h D for a point at height zeta
//   (D = `slices`); voxel (i, j, k) has its centre at (i + 1/2, j + 1/2, k + 1/2) and is solid
//   when k + 1/2 <= h(i, j) D (the voxelised surface), and the floor k = -1 is solid.
// - r_dist, per voxel, in voxel units: max(0, b - sqrt(3) / 2), b = the distance from the voxel's
//   box to the nearest solid box (wrapping in X, Y), computed exactly as the Euclidean distance
//   transform (Felzenszwalb and Huttenlocher, "Distance Transforms of Sampled Functions", Theory
//   of Computing 8, 2012, pp. 415-428) of the solid set dilated by one voxel (3 x 3 x 3), whose
//   columns are height columns, so the Z part is closed-form. Trilinear interpolation of these
//   values never exceeds the distance from the point to the solid boxes: a step never enters
//   one (conservative). Stored as a 2D atlas of D slices of W x H texels (nearest, R32F); the
//   trilinear blend is done in both twins from 8 counted fetches.
// - Tracing: from where the eye ray enters the slab, `iterations` steps tau += f(q) / L, with f the
//   trilinear distance at q and L = |(V.x W, V.y H, V.z D / s)| the ray's speed in voxel space;
//   returns the uv at the last tau.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "methods/method.h"
#include "methods/resource.h"

namespace pxh {

// Columns and rows of the atlas of D slices (cols = the smallest c with c^2 >= D).
inline int atlas_cols(int D) {
    int c = 1;
    while (c * c < D) ++c;
    return c;
}
inline int atlas_rows(int D) { return (D + atlas_cols(D) - 1) / atlas_cols(D); }

namespace {

// Squared 1D distance transform of f (Felzenszwalb and Huttenlocher 2012, algorithm DT(f)):
// d[q] = min over p of (q - p)^2 + f[p]. v, z are work arrays of size n and n + 1.
void dt1d(const double* f, int n, double* d, int* v, double* z) {
    const double inf = 1e300;
    auto cut = [&](int q, int p) {  // where the parabolas from q and p intersect
        return ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * q - 2.0 * p);
    };
    int k = 0;
    v[0] = 0;
    z[0] = -inf;
    z[1] = inf;
    for (int q = 1; q < n; ++q) {
        double s = cut(q, v[k]);
        while (s <= z[k]) s = cut(q, v[--k]);  // z[0] = -inf stops it
        ++k;
        v[k] = q;
        z[k] = s;
        z[k + 1] = inf;
    }
    k = 0;
    for (int q = 0; q < n; ++q) {
        while (z[k + 1] < q) ++k;
        const double dq = double(q) - v[k];
        d[q] = dq * dq + f[v[k]];
    }
}

// The periodic transform of one line of n values (stride apart in `line`), in place: the line
// repeated three times, the middle third kept (every nearest site lies within one period).
void dt_periodic(float* line, int n, size_t stride) {
    std::vector<double> f(3 * size_t(n)), d(3 * size_t(n)), z(3 * size_t(n) + 1);
    std::vector<int> v(3 * size_t(n));
    for (int r = 0; r < 3; ++r)
        for (int i = 0; i < n; ++i) f[size_t(r * n + i)] = line[size_t(i) * stride];
    dt1d(f.data(), 3 * n, d.data(), v.data(), z.data());
    for (int i = 0; i < n; ++i) line[size_t(i) * stride] = float(d[size_t(n + i)]);
}

// T(i, j): the highest solid Z index (floor = 0, slice k = k + 1) of the column at (i, j) after
// dilating the solid set by one voxel in X, Y (wrapped) and Z.
std::vector<int> dilated_tops(const HeightField& hf, int D) {
    const int W = hf.width, H = hf.height;
    std::vector<int> top(size_t(W) * H), T(size_t(W) * H);
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            // slices k with k + 1/2 <= h D are solid: Z indices 1 .. floor(h D + 1/2)
            const double t = std::floor(double(hf.at(i, j)) * D + 0.5);
            top[size_t(j) * W + i] = int(std::clamp(t, 0.0, double(D)));
        }
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            int m = 0;
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di)
                    m = std::max(m, top[size_t((j + dj + H) % H) * W + size_t((i + di + W) % W)]);
            T[size_t(j) * W + i] = std::min(D, m + 1);
        }
    return T;
}

ResourceImage build_distance(const HeightField& hf, double, double, int D) {
    const int W = hf.width, H = hf.height, cols = atlas_cols(D);
    const std::vector<int> T = dilated_tops(hf, D);
    ResourceLevel lv;
    lv.width = cols * W;
    lv.height = atlas_rows(D) * H;
    lv.texels.assign(size_t(lv.width) * size_t(lv.height), 0.0f);
    const float margin = float(std::sqrt(3.0) / 2);
    // One task per slice: each writes its own block, so the bytes do not depend on the threads.
    tbb::parallel_for(0, D, [&](int k) {
        const int z = k + 1;  // Z index of slice k (0 = floor)
        std::vector<float> g(size_t(W) * H);
        for (size_t c = 0; c < g.size(); ++c) {
            const double dz = std::max(0, z - T[c]);
            g[c] = float(dz * dz);  // the closed-form Z transform of a column 0 .. T
        }
        for (int j = 0; j < H; ++j) dt_periodic(g.data() + size_t(j) * W, W, 1);
        for (int i = 0; i < W; ++i) dt_periodic(g.data() + i, H, size_t(W));
        const int bx = (k % cols) * W, by = (k / cols) * H;
        for (int j = 0; j < H; ++j)
            for (int i = 0; i < W; ++i)
                lv.texels[size_t(by + j) * size_t(lv.width) + size_t(bx + i)] =
                    std::max(0.0f, std::sqrt(g[size_t(j) * W + i]) - margin);
    });
    return {{std::move(lv)}};
}

}  // namespace

struct Distance {
    struct Config {
        int iterations, slices;
    };
    static MethodInfo describe() {
        MethodInfo m{
            "distance",
            "Donnelly: Per-Pixel Displacement Mapping with Distance Functions, GPU Gems 2, ch. 8, "
            "2005, pp. 123-136; distance transform: Felzenszwalb, Huttenlocher, Theory of "
            "Computing 8, 2012",
            "sphere tracing through a conservative 3D distance map (8 fetches per step)",
            {ParamSpec::integer("iterations", 16, 1, 256, "sphere-tracing steps (8 fetches each)")
                 .to_uniform("p_iterations"),
             ParamSpec::integer("slices", 16, 2, 64, "D: slices of the distance map over the slab")
                 .to_uniform("p_slices")},
            false,
            240};
        ResourceSpec r;
        r.name = "r_dist";
        r.format = TexelFormat::R32F;
        r.filter = TexFilter::Nearest;
        r.wrap = TexWrap::Repeat;
        r.int_param = "slices";
        r.build_with = build_distance;
        r.int_param_default = 16;
        r.help = "atlas of D slices: conservative distance to the voxelised relief, voxel units";
        m.resources = {r};
        return m;
    }
    static Config configure(const ParamValues& p, const std::string&) {
        return {p.get_int("iterations"), p.get_int("slices")};
    }
    static int max_fetches(const Config& c, const Scene<double>&) { return 8 * c.iterations; }
    static GlUniforms gl_uniforms(const Config& c) {
        return {GlUniform::integer("p_atlas_cols", atlas_cols(c.slices))};
    }

    // The stored value at voxel (i, j) of slice k (one fetch, the texel's centre).
    template <typename T>
    static T voxel(TextureSampler<T>& tex, const Scene<T>& sc, int cols, int rows, int i, int j,
                   int k) {
        const int bx = k % cols, by = k / cols;
        const T x = (T(bx * sc.width + i) + T(0.5)) / T(cols * sc.width);
        const T y = (T(by * sc.height + j) + T(0.5)) / T(rows * sc.height);
        return tex.fetch_r(Vec2<T>(x, y), 0);
    }
    // Trilinear distance at uv and voxel height Z (8 fetches), wrapping in u, v; Z clamped to the
    // slice centres.
    template <typename T>
    static T sample(TextureSampler<T>& tex, const Scene<T>& sc, int D, Vec2<T> uv, T Z) {
        const int W = sc.width, H = sc.height, cols = atlas_cols(D), rows = atlas_rows(D);
        const T X = (uv.x - std::floor(uv.x)) * T(W) - T(0.5);
        const T Y = (uv.y - std::floor(uv.y)) * T(H) - T(0.5);
        const T x0 = std::floor(X), y0 = std::floor(Y);
        const T fx = X - x0, fy = Y - y0;
        const int i0 = x0 < T(0) ? W - 1 : int(x0), j0 = y0 < T(0) ? H - 1 : int(y0);
        const int i1 = i0 + 1 >= W ? 0 : i0 + 1, j1 = j0 + 1 >= H ? 0 : j0 + 1;
        const T zc = std::clamp(Z - T(0.5), T(0), T(D - 1));
        const int k0 = std::min(int(std::floor(zc)), D - 2);
        const T fz = zc - T(k0);
        T s[2];
        for (int m = 0; m < 2; ++m) {
            const int k = k0 + m;
            const T t00 = voxel(tex, sc, cols, rows, i0, j0, k);
            const T t10 = voxel(tex, sc, cols, rows, i1, j0, k);
            const T t01 = voxel(tex, sc, cols, rows, i0, j1, k);
            const T t11 = voxel(tex, sc, cols, rows, i1, j1, k);
            const T a = t00 + (t10 - t00) * fx;
            const T c = t01 + (t11 - t01) * fx;
            s[m] = a + (c - a) * fy;
        }
        return s[0] + (s[1] - s[0]) * fz;
    }
    template <typename T>
    static MethodHit<T> eval(const Config& c, const Scene<T>& sc, HeightSampler<T>&,
                             ResourceSamplers<T>& res, Vec2<T> P) {
        const T D = T(c.slices);
        const Vec2<T> E = P + sc.V.xy() * (sc.z_top() / sc.V.z);
        const T kz = sc.V.z * D / sc.scale;  // dZ / dtau
        const T ax = sc.V.x * T(sc.width), ay = sc.V.y * T(sc.height);
        const T L = std::sqrt(ax * ax + ay * ay + kz * kz);
        T tau = T(0);
        for (int it = 0; it < c.iterations; ++it) {
            const Vec2<T> uv = E - sc.V.xy() * tau;
            const T Z = D - tau * kz;
            tau = tau + sample(res[0], sc, c.slices, uv, Z) / L;
        }
        // uv = P + V.xy / V.z (z_top - V.z tau): the eye ray's point at z_top - V.z tau
        return {E - sc.V.xy() * tau, sc.z_top() - sc.V.z * tau};
    }
};
PXH_REGISTER_METHOD(Distance);

}  // namespace pxh

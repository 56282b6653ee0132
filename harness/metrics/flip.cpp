// LDR-FLIP (flip.h). Every constant is the paper's (Andersson et al. 2020, sections 4-5 and
// table 1); "FLIP.h:N" names the line of NVlabs/flip src/cpp/FLIP.h at commit
// 1eb247cabcf2862c2c8207ab15314304394132b9 that holds the same value or choice.
//
// The work is laid out in planes (one float array a channel) so that each 1-D filter runs as a
// weighted sum of whole rows, which the compiler vectorises; each tap is added in the authors'
// order (from -radius to +radius), the horizontal pass before the vertical one.
#include "harness/metrics/flip.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "harness/metrics/metrics.h"

namespace pxh {

namespace {

constexpr float kPi = 3.14159265358979f;  // FLIP.h:101

// The FLIP constants (paper table 1; FLIP.h:125-133): q_c, p_c, p_t, w (degrees), q_f.
constexpr float kQc = 0.7f, kPc = 0.4f, kPt = 0.95f, kW = 0.082f, kQf = 0.5f;

// D65 white in XYZ and its inverse (FLIP.h:106-107).
constexpr FlipColor kWhite{0.950428545f, 1.000000000f, 1.088900371f};
constexpr FlipColor kInvWhite{1.052156925f, 1.000000000f, 0.918357670f};

// The contrast sensitivity functions of Y, Cx (one Gaussian each) and Cz (a sum of two), in the
// form a sqrt(pi / b) exp(-pi^2 x^2 / b), x in degrees (paper eq. 2 and table 1; FLIP.h:567-574).
constexpr float kA1[3] = {1.0f, 1.0f, 34.1f}, kB1[3] = {0.0047f, 0.0053f, 0.04f};
constexpr float kA2[3] = {0.0f, 0.0f, 13.5f}, kB2[3] = {1.0e-5f, 1.0e-5f, 0.025f};

float srgb_to_linear(float c) {  // IEC 61966-2-1 (FLIP.h:330-337)
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

float clamp01(float v) { return std::min(std::max(v, 0.0f), 1.0f); }

// Linear RGB (D65) -> XYZ, the exact rational matrix (FLIP.h:367-386).
FlipColor linear_to_xyz(FlipColor c) {
    return {(10135552.0f / 24577794.0f) * c.x + (8788810.0f / 24577794.0f) * c.y +
                (4435075.0f / 24577794.0f) * c.z,
            (2613072.0f / 12288897.0f) * c.x + (8788810.0f / 12288897.0f) * c.y +
                (887015.0f / 12288897.0f) * c.z,
            (1425312.0f / 73733382.0f) * c.x + (8788810.0f / 73733382.0f) * c.y +
                (70074185.0f / 73733382.0f) * c.z};
}

// XYZ -> linear RGB (FLIP.h:388-406).
FlipColor xyz_to_linear(FlipColor c) {
    return {3.241003275f * c.x + -1.537398934f * c.y + -0.498615861f * c.z,
            -0.969224334f * c.x + 1.875930071f * c.y + 0.041554224f * c.z,
            0.055639423f * c.x + -0.204011202f * c.y + 1.057148933f * c.z};
}

// XYZ -> CIELab against D65 (FLIP.h:408-425).
FlipColor xyz_to_lab(FlipColor c) {
    const float delta = 6.0f / 29.0f, delta3 = delta * delta * delta;
    const float factor = 1.0f / (3.0f * delta * delta), term = 4.0f / 29.0f;
    auto f = [&](float v) { return v > delta3 ? std::pow(v, 1.0f / 3.0f) : factor * v + term; };
    const float fx = f(c.x * kInvWhite.x), fy = f(c.y * kInvWhite.y), fz = f(c.z * kInvWhite.z);
    return {116.0f * fy - 16.0f, 500.0f * (fx - fy), 200.0f * (fy - fz)};
}

// The Hunt adjustment: a and b scaled by 0.01 L (paper section 4.1; FLIP.h:470-473).
FlipColor hunt(FlipColor lab) { return {lab.x, 0.01f * lab.x * lab.y, 0.01f * lab.x * lab.z}; }

// One filter's taps, from -radius to +radius.
using Taps = std::vector<float>;

// The spatial filters of the colour pipeline (FLIP.h:1741-1776, 612-620): radius
// ceil(3 sqrt(b_max / (2 pi^2)) ppd) over all b; the Y and Cx Gaussians normalised to sum 1;
// Cz's two Gaussians each the square root of its 2-D weight (separable), both divided by
// sqrt(sum1^2 + sum2^2).
struct SpatialFilters {
    Taps y, cx, cz1, cz2;
};
SpatialFilters spatial_filters(float ppd) {
    const float pi2 = kPi * kPi;
    const float bmax = std::max({kB1[0], kB1[1], kB1[2], kB2[0], kB2[1], kB2[2]});
    const int r = int(std::ceil(3.0f * std::sqrt(bmax / (2.0f * pi2)) * ppd));
    const float dx = 1.0f / ppd;
    SpatialFilters f;
    float sy = 0, scx = 0, s1 = 0, s2 = 0;
    for (int i = -r; i <= r; ++i) {
        const float x = float(i) * dx, x2 = x * x;
        const auto g = [&](float a, float b) {
            return a * std::sqrt(kPi / b) * std::exp(-pi2 * x2 / b);
        };
        const auto gs = [&](float a, float b) {
            return std::sqrt(a * std::sqrt(kPi / b)) * std::exp(-pi2 * x2 / b);
        };
        f.y.push_back(g(kA1[0], kB1[0]));
        f.cx.push_back(g(kA1[1], kB1[1]));
        f.cz1.push_back(gs(kA1[2], kB1[2]));
        f.cz2.push_back(gs(kA2[2], kB2[2]));
        sy += f.y.back(), scx += f.cx.back(), s1 += f.cz1.back(), s2 += f.cz2.back();
    }
    const float ny = 1.0f / sy, ncx = 1.0f / scx, ncz = 1.0f / std::sqrt(s1 * s1 + s2 * s2);
    for (size_t i = 0; i < f.y.size(); ++i) {
        f.y[i] *= ny, f.cx[i] *= ncx;
        f.cz1[i] *= ncz, f.cz2[i] *= ncz;
    }
    return f;
}

// The feature filters (paper section 4.2; FLIP.h:1780-1825): sigma = 0.5 w ppd pixels, radius
// ceil(3 sigma); the Gaussian normalised to sum 1, its first and second derivatives so that
// their positive weights sum to 1 and their negative weights to -1.
struct FeatureFilters {
    Taps g, dg, ddg;
};
FeatureFilters feature_filters(float ppd) {
    const float sd = 0.5f * kW * ppd;
    const int r = int(std::ceil(3.0f * sd));
    FeatureFilters f;
    float gsum = 0, dpos = 0, dneg = 0, ddpos = 0, ddneg = 0;
    for (int i = -r; i <= r; ++i) {
        const float x = float(i);
        const float g = std::exp(-(x * x) / (2.0f * sd * sd));
        const float dg = -x * g, ddg = (x * x / (sd * sd) - 1.0f) * g;
        gsum += g;
        (dg > 0.0f ? dpos : dneg) += dg > 0.0f ? dg : -dg;
        (ddg > 0.0f ? ddpos : ddneg) += ddg > 0.0f ? ddg : -ddg;
        f.g.push_back(g), f.dg.push_back(dg), f.ddg.push_back(ddg);
    }
    for (size_t i = 0; i < f.g.size(); ++i) {
        f.g[i] /= gsum;
        f.dg[i] /= f.dg[i] > 0.0f ? dpos : dneg;
        f.ddg[i] /= f.ddg[i] > 0.0f ? ddpos : ddneg;
    }
    return f;
}

// A plane's floats are each written before they are read: left uninitialised when allocated
// (zeroing 40-odd planes a call took a quarter of the time).
template <class T>
struct UninitAllocator : std::allocator<T> {
    template <class U>
    struct rebind {
        using other = UninitAllocator<U>;
    };
    UninitAllocator() = default;
    template <class U>
    explicit UninitAllocator(const UninitAllocator<U>&) noexcept {}
    template <class U>
    void construct(U* p) noexcept {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... A>
    void construct(U* p, A&&... a) {
        ::new (static_cast<void*>(p)) U(std::forward<A>(a)...);
    }
};
using Plane = std::vector<float, UninitAllocator<float>>;

template <class F>
void for_rows(int h, const F& f) {
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 16), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y != r.end(); ++y) f(y);
    });
}

// out = in filtered along x with `taps`, the image clamped at its edges (FLIP.h:1853).
Plane filter_x(const Plane& in, int w, int h, const Taps& taps) {
    Plane out(in.size());
    const int r = int(taps.size() / 2);
    for_rows(h, [&](int y) {
        std::vector<float> pad(size_t(w + 2 * r));
        const float* row = in.data() + size_t(y) * size_t(w);
        for (int x = -r; x < w + r; ++x) pad[size_t(x + r)] = row[std::min(std::max(x, 0), w - 1)];
        float* o = out.data() + size_t(y) * size_t(w);
        // 0 + t0 p is t0 p exactly: the first tap sets, the others add, in the authors' order.
        for (int x = 0; x < w; ++x) o[x] = taps[0] * pad[size_t(x)];
        for (size_t k = 1; k < taps.size(); ++k) {
            const float t = taps[k];
            const float* p = pad.data() + k;
            for (int x = 0; x < w; ++x) o[x] += t * p[x];
        }
    });
    return out;
}

// out = in filtered along y with `taps`, the image clamped at its edges (FLIP.h:1882).
Plane filter_y(const Plane& in, int w, int h, const Taps& taps) {
    Plane out(in.size());
    const int r = int(taps.size() / 2);
    for_rows(h, [&](int y) {
        float* o = out.data() + size_t(y) * size_t(w);
        for (int k = -r; k <= r; ++k) {
            const float t = taps[size_t(k + r)];
            const float* p = in.data() + size_t(std::min(std::max(y + k, 0), h - 1)) * size_t(w);
            if (k == -r)
                for (int x = 0; x < w; ++x) o[x] = t * p[x];
            else
                for (int x = 0; x < w; ++x) o[x] += t * p[x];
        }
    });
    return out;
}

// One image in YCxCz, a plane a channel.
struct Ycxcz {
    Plane y, cx, cz;
};
Ycxcz to_ycxcz(const FlipImage& im) {
    const size_t n = size_t(im.w) * size_t(im.h);
    Ycxcz o{Plane(n), Plane(n), Plane(n)};
    const bool srgb = im.encoding == FlipEncoding::srgb;
    for_rows(im.h, [&](int y) {
        for (size_t i = size_t(y) * size_t(im.w); i < size_t(y + 1) * size_t(im.w); ++i) {
            FlipColor c{clamp01(im.rgb[3 * i]), clamp01(im.rgb[3 * i + 1]),
                        clamp01(im.rgb[3 * i + 2])};
            if (srgb) c = {srgb_to_linear(c.x), srgb_to_linear(c.y), srgb_to_linear(c.z)};
            const FlipColor v = linear_to_xyz(c);
            const float X = v.x * kInvWhite.x, Y = v.y * kInvWhite.y, Z = v.z * kInvWhite.z;
            o.y[i] = 116.0f * Y - 16.0f, o.cx[i] = 500.0f * (X - Y), o.cz[i] = 200.0f * (Y - Z);
        }
    });
    return o;
}

// The filtered image in YCxCz: Y and Cx through their Gaussians, Cz through the sum of its two
// (each separable).
Ycxcz spatial_filter(const Ycxcz& c, int w, int h, const SpatialFilters& f) {
    Ycxcz o;
    o.y = filter_y(filter_x(c.y, w, h, f.y), w, h, f.y);
    o.cx = filter_y(filter_x(c.cx, w, h, f.cx), w, h, f.cx);
    o.cz = filter_y(filter_x(c.cz, w, h, f.cz1), w, h, f.cz1);
    const Plane cz2 = filter_y(filter_x(c.cz, w, h, f.cz2), w, h, f.cz2);
    for (size_t i = 0; i < o.cz.size(); ++i) o.cz[i] += cz2[i];
    return o;
}

// The colour difference of each pixel, in [0, 1] (FLIP.h:1830-1940).
Plane color_difference(const Ycxcz& ref, const Ycxcz& test, int w, int h, float ppd) {
    const SpatialFilters f = spatial_filters(ppd);
    const Ycxcz a = spatial_filter(ref, w, h, f), b = spatial_filter(test, w, h, f);
    Plane out(a.y.size());
    for_rows(h, [&](int y) {
        for (size_t i = size_t(y) * size_t(w); i < size_t(y + 1) * size_t(w); ++i)
            out[i] =
                flip_color_remap(flip_hyab(flip_ycxcz_to_lab_hunt({a.y[i], a.cx[i], a.cz[i]}),
                                           flip_ycxcz_to_lab_hunt({b.y[i], b.cx[i], b.cz[i]})));
    });
    return out;
}

// Edges and points of one image's Y (normalised to [0, 1]): the first and second derivatives
// of the Gaussian along x (Gaussian along y) and along y (Gaussian along x).
struct Features {
    Plane dx, ddx, dy, ddy;
};
Features features(const Plane& ylab, int w, int h, const FeatureFilters& f) {
    Plane yn(ylab.size());
    for (size_t i = 0; i < yn.size(); ++i) yn[i] = ylab[i] * (1.0f / 116.0f) + 16.0f / 116.0f;
    const Plane gx = filter_x(yn, w, h, f.g);
    return {filter_y(filter_x(yn, w, h, f.dg), w, h, f.g),
            filter_y(filter_x(yn, w, h, f.ddg), w, h, f.g), filter_y(gx, w, h, f.dg),
            filter_y(gx, w, h, f.ddg)};
}

// The final error, colour ^ (1 - feature) (paper eq. 10; FLIP.h:1944-2043), in place.
void apply_features(const Plane& ref_y, const Plane& test_y, int w, int h, const FeatureFilters& f,
                    Plane& err) {
    const Features a = features(ref_y, w, h, f), b = features(test_y, w, h, f);
    const float norm = 1.0f / std::sqrt(2.0f);
    for_rows(h, [&](int y) {
        for (size_t i = size_t(y) * size_t(w); i < size_t(y + 1) * size_t(w); ++i) {
            const float ea = std::sqrt(a.dx[i] * a.dx[i] + a.dy[i] * a.dy[i]);
            const float eb = std::sqrt(b.dx[i] * b.dx[i] + b.dy[i] * b.dy[i]);
            const float pa = std::sqrt(a.ddx[i] * a.ddx[i] + a.ddy[i] * a.ddy[i]);
            const float pb = std::sqrt(b.ddx[i] * b.ddx[i] + b.ddy[i] * b.ddy[i]);
            const float fd = std::pow(norm * std::max(std::abs(ea - eb), std::abs(pa - pb)), kQf);
            err[i] = std::pow(err[i], 1.0f - fd);
        }
    });
}

FlipResult pool(const Plane& err, const std::vector<uint8_t>* mask) {
    std::vector<double> v;
    v.reserve(err.size());
    for (size_t i = 0; i < err.size(); ++i)
        if (!mask || (*mask)[i]) v.push_back(double(err[i]));
    FlipResult r;
    r.counted = long(v.size());
    if (v.empty()) {
        r.mean = r.p95 = r.max = NAN;
        return r;
    }
    double sum = 0;
    for (double e : v) sum += e;
    r.mean = sum / double(v.size());
    // percentile_sorted's 95th percentile (metrics.h) without sorting it all: the order
    // statistics i and i + 1 around pos = 0.95 (n - 1), interpolated.
    const double pos = 0.95 * double(v.size() - 1);
    const size_t i = size_t(std::floor(pos));
    const auto at = v.begin() + std::ptrdiff_t(i);
    std::nth_element(v.begin(), at, v.end());
    r.max = *std::max_element(at, v.end());
    r.p95 = i + 1 >= v.size()
                ? r.max
                : *at + (*std::min_element(at + 1, v.end()) - *at) * (pos - double(i));
    return r;
}

}  // namespace

FlipColor flip_ycxcz_to_lab_hunt(FlipColor c) {
    // YCxCz -> XYZ (FLIP.h:453-462), -> linear RGB clamped to [0, 1] (FLIP.h:1907-1910).
    const float Y = (c.x + 16.0f) / 116.0f, X = Y + c.y / 500.0f, Z = Y - c.z / 200.0f;
    const FlipColor rgb = xyz_to_linear({X * kWhite.x, Y * kWhite.y, Z * kWhite.z});
    return hunt(xyz_to_lab(linear_to_xyz({clamp01(rgb.x), clamp01(rgb.y), clamp01(rgb.z)})));
}

float flip_hyab(FlipColor a, FlipColor b) {  // paper eq. 4 (FLIP.h:475-480)
    return std::abs(a.x - b.x) + std::sqrt((a.y - b.y) * (a.y - b.y) + (a.z - b.z) * (a.z - b.z));
}

float flip_cmax() {  // the largest distance, pure green to pure blue (FLIP.h:482-489)
    const FlipColor g = hunt(xyz_to_lab(linear_to_xyz({0.0f, 1.0f, 0.0f})));
    const FlipColor b = hunt(xyz_to_lab(linear_to_xyz({0.0f, 0.0f, 1.0f})));
    return std::pow(flip_hyab(g, b), kQc);
}

float flip_color_remap(float hyab) {  // paper eq. 5 (FLIP.h:1925-1936)
    static const float cmax = flip_cmax();
    const float pccmax = kPc * cmax;
    const float d = std::pow(hyab, kQc);
    return d < pccmax ? d * (kPt / pccmax) : kPt + ((d - pccmax) / (cmax - pccmax)) * (1.0f - kPt);
}

FlipResult flip_ldr(const FlipImage& reference, const FlipImage& test, double ppd,
                    const std::vector<uint8_t>* mask, std::vector<float>* map) {
    const int w = reference.w, h = reference.h;
    const size_t n = size_t(std::max(w, 0)) * size_t(std::max(h, 0));
    if (w < 1 || h < 1 || test.w != w || test.h != h || reference.rgb.size() != 3 * n ||
        test.rgb.size() != 3 * n)
        throw std::invalid_argument("flip_ldr: the images are empty or of different sizes");
    if (!(ppd > 0) || !std::isfinite(ppd))
        throw std::invalid_argument("flip_ldr: ppd must be a positive number");
    if (mask && mask->size() != n)
        throw std::invalid_argument("flip_ldr: the mask is not the images' size");
    // Below about 1.7 pixels per degree the feature Gaussian (sigma 0.041 ppd pixels) is zero
    // at its first neighbours in float and its derivatives cannot be normalised (the authors'
    // code gives NaN there).
    const FeatureFilters f = feature_filters(float(ppd));
    for (const Taps* t : {&f.g, &f.dg, &f.ddg})
        for (float v : *t)
            if (!std::isfinite(v))
                throw std::invalid_argument("flip_ldr: ppd " + std::to_string(ppd) +
                                            " is too small for FLIP's feature filters");
    const Ycxcz a = to_ycxcz(reference), b = to_ycxcz(test);
    Plane err = color_difference(a, b, w, h, float(ppd));
    apply_features(a.y, b.y, w, h, f, err);
    FlipResult r = pool(err, mask);
    if (map) map->assign(err.begin(), err.end());
    return r;
}

FlipResult flip_ldr(const std::vector<uint8_t>& reference, const std::vector<uint8_t>& test, int w,
                    int h, double ppd, const std::vector<uint8_t>* mask, std::vector<float>* map) {
    auto to_float = [](const std::vector<uint8_t>& v) {
        std::vector<float> f(v.size());
        for (size_t i = 0; i < v.size(); ++i) f[i] = float(v[i]) / 255.0f;
        return f;
    };
    const std::vector<float> a = to_float(reference), b = to_float(test);
    return flip_ldr(FlipImage{a, w, h}, FlipImage{b, w, h}, ppd, mask, map);
}

}  // namespace pxh

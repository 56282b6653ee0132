// The pyramid tracer of the curved truth: see curved_pyramid.h, and docs/internals/tracers.md
// ("Curved bases: the pyramid tracer") for why no crossing is missed.
#include "harness/truth/curved_pyramid.h"

#include <sys/mman.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include "harness/truth/cell_solver.h"
#include "harness/truth/exact_tracer.h"

namespace pxh {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;
constexpr double kEps = 2.220446049250313e-16;

// Asks the kernel to back [p, p + bytes) with 2 MB pages where it can (MADV_COLLAPSE, Linux
// 6.1 and later; a hint: refused or unknown, nothing changes). The traversal reads the pyramid's
// lower levels and the texels at scattered cells; on a 2048^2 field each is 16 MB, whose 4 KB
// pages overflow the TLB.
void ask_huge_pages(const void* p, size_t bytes) {
#if defined(__linux__)
    constexpr uintptr_t kHuge = uintptr_t(2) << 20;
    const uintptr_t a = (reinterpret_cast<uintptr_t>(p) + kHuge - 1) & ~(kHuge - 1);
    const uintptr_t b = (reinterpret_cast<uintptr_t>(p) + bytes) & ~(kHuge - 1);
    // (synchronous: the kernel copies the pages; above 512 MB left to 4 KB pages)
    if (b > a && b - a <= (uintptr_t(512) << 20))
        (void)madvise(reinterpret_cast<void*>(a), b - a, 25 /* MADV_COLLAPSE */);
#else
    (void)p;
    (void)bytes;
#endif
}

// The first (smallest) root > 0 of A x^2 + 2 B x + C = 0 whose point passes `ok`, or inf.
template <typename Ok>
double first_root(double A, double B, double C, Ok&& ok) {
    double r[2];
    int n = 0;
    if (A == 0) {
        if (B != 0) r[n++] = -C / (2 * B);
    } else {
        const double disc = B * B - A * C;
        if (!(disc >= 0)) return kInf;
        const double q = -(B + std::copysign(std::sqrt(disc), B));
        r[n++] = q / A;
        r[n++] = q != 0 ? C / q : 0.0;
        if (r[0] > r[1]) std::swap(r[0], r[1]);
    }
    for (int i = 0; i < n; ++i)
        if (std::isfinite(r[i]) && ok(r[i])) return r[i];
    return kInf;
}

// atan2(y, x) to a few ulp of the result (and to a few ulp relative to it below 1/128), about a
// quarter of libm's cost: the ratio r in [0, 1] of the smaller to the larger magnitude, reduced
// about the nearest c = i / 64 by atan(r) = atan(c) + atan((r - c) / (1 + r c)), whose argument
// is under 1/128, where five odd terms of atan's series leave below 1e-24. The traversal's and
// the safe steps' azimuth; the bisection and the residual take std::atan2, as the walk does.
struct FastAtan2 {
    double table[65];
    FastAtan2() {
        for (int i = 0; i <= 64; ++i) table[i] = std::atan(i / 64.0);
    }
    double operator()(double y, double x) const {
        const double ay = std::abs(y), ax = std::abs(x);
        const bool swap = ay > ax;
        const double num = swap ? ax : ay, den = swap ? ay : ax;
        if (!(den > 0)) return std::atan2(y, x);  // zeros, NaN
        const double r = num / den;
        const int i = int(r * 64 + 0.5);
        const double c = i * (1.0 / 64);
        const double w = i == 0 ? r : (r - c) / (1 + r * c);
        const double w2 = w * w;
        double a =
            table[i] + w * (1 - w2 * (1.0 / 3 - w2 * (1.0 / 5 - w2 * (1.0 / 7 - w2 * (1.0 / 9)))));
        if (swap) a = kPi / 2 - a;
        if (x < 0) a = kPi - a;
        return y < 0 ? -a : a;
    }
};
const FastAtan2 fast_atan2;

}  // namespace

bool CurvedPyramid::supports(const BaseSurface& base) {
    const std::string n = base.name();
    return n == "cylinder" || n == "sphere" || n == "plane";
}

namespace {
CurvedPyramid::Path path_of(ExactTracer::RayPath p) {
    if (p == ExactTracer::RayPath::avx512) return CurvedPyramid::Path::avx512;
    if (p == ExactTracer::RayPath::avx2) return CurvedPyramid::Path::avx2;
    return CurvedPyramid::Path::scalar;
}
}  // namespace

CurvedPyramid::Path CurvedPyramid::default_path() { return path_of(ExactTracer::default_path()); }

CurvedPyramid::Path CurvedPyramid::cpu_path() { return path_of(ExactTracer::cpu_best_path()); }

std::string CurvedPyramid::path_name(Path p) {
    switch (p) {
        case Path::avx512:
            return "avx512: 8 rays to a vector, double";
        case Path::avx2:
            return "avx2: 4 rays to a vector, double";
        default:
            return "scalar double";
    }
}

const double* CurvedPyramid::atan_table() { return fast_atan2.table; }

void CurvedPyramid::trace_many(const WorldRay* rays, size_t n, One* out, long long max_steps,
                               Path path, const std::atomic<bool>* stop) const {
    // never above what the CPU has; the plane keeps the scalar path (the runner's plane truth is
    // the exact tracer); AVX2's lookups take 32-bit indices
    path = std::min(path, cpu_path());
    const bool small = max_.size() < (size_t(1) << 31) && hf_.texels.size() < (size_t(1) << 31);
#if PXH_PYRAMID_LANES
    if (kind_ != Kind::plane && path == Path::avx512)
        return trace_avx512(rays, n, out, max_steps, stop);
    if (kind_ != Kind::plane && path == Path::avx2 && small)
        return trace_avx2(rays, n, out, max_steps, stop);
#else
    (void)small;
#endif
    long long spent = 0;
    for (size_t k = 0; k < n; ++k) {
        if (spent > max_steps || (stop && stop->load(std::memory_order_relaxed))) {
            out[k] = One{};  // not started: the budget is spent (the caller throws)
            continue;
        }
        out[k] = trace_one(rays[k], max_steps - spent + 4096);
        spent += out[k].steps;
    }
}

CurvedPyramid::CurvedPyramid(const HeightField& hf, double scale, double bias,
                             const BaseSurface& base)
    : hf_(hf), s_(scale), b_(bias), base_(base), W_(hf.width), H_(hf.height) {
    const std::string n = base.name();
    if (n == "cylinder") kind_ = Kind::cylinder;
    else if (n == "sphere") kind_ = Kind::sphere;
    else if (n == "plane") kind_ = Kind::plane;
    else throw std::invalid_argument("the pyramid tracer has no closed form for base '" + n + "'");
    R_ = kind_ == Kind::plane ? 0.0 : base.radius();
    rmin_ = R_ - s_ * b_;  // the bottom shell: R > s b (the curved bases require it)
    margin_ = 16 * kEps * (R_ + std::abs(s_) * (1 + std::abs(b_)) + 1);
    tiny_ = 1e-10 / double(std::max(W_, H_));
    // level 0: per cell (its corners texels i, i + 1 and j, j + 1, wrapped), the largest corner
    // over the cell dilated by one cell on each side: texels i - 1 .. i + 2, j - 1 .. j + 2
    const int W = W_, H = H_;
    std::vector<float> rowmax(size_t(W) * H);
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            float m = -kInf;
            for (int di = -1; di <= 2; ++di) m = std::max(m, hf.wrapped(int64_t(i) + di, j));
            rowmax[size_t(j) * W + i] = m;
        }
    std::vector<float> l0(size_t(W) * H);
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            float m = -kInf;
            for (int dj = -1; dj <= 2; ++dj)
                m = std::max(m, rowmax[size_t(wrap_index(int64_t(j) + dj, H)) * W + i]);
            l0[size_t(j) * W + i] = m;
        }
    std::vector<float>().swap(rowmax);
    if (kind_ == Kind::sphere) {
        // the rows' latitudes over the sphere (from pole to pole, within 4 tiles of the field)
        const double half = kPi / 2 * R_ * H + 2;
        lat_lo_ = std::max<int64_t>(int64_t(std::floor(0.5 * H - half)), -4 * int64_t(H));
        const int64_t hi = std::min<int64_t>(int64_t(std::ceil(0.5 * H + half)), 5 * int64_t(H));
        for (int64_t d = lat_lo_; d <= hi; ++d) lat_.push_back(make_latitude(d));
        for (int64_t d = lat_lo_; d <= hi; ++d) row_speeds_.push_back(make_speeds(d));
    }
    speeds_ = make_speeds(0);
    // the levels one after another in max_ (level k from off_[k])
    nx_.push_back(W);
    ny_.push_back(H);
    off_.push_back(0);
    while (nx_.back() > 1 || ny_.back() > 1) {
        off_.push_back(off_.back() + int64_t(nx_.back()) * ny_.back());
        nx_.push_back((nx_.back() + 1) / 2);
        ny_.push_back((ny_.back() + 1) / 2);
    }
    max_.assign(size_t(off_.back()) + size_t(nx_.back()) * size_t(ny_.back()), -kInf);
    std::copy(l0.begin(), l0.end(), max_.begin());
    std::vector<float>().swap(l0);
    for (size_t k = 1; k < nx_.size(); ++k) {
        const int px = nx_[k - 1], py = ny_[k - 1], qx = nx_[k];
        const float* lower = max_.data() + off_[k - 1];
        float* up = max_.data() + off_[k];
        for (int j = 0; j < py; ++j)
            for (int i = 0; i < px; ++i) {
                float& m = up[size_t(j / 2) * qx + size_t(i / 2)];
                m = std::max(m, lower[size_t(j) * px + i]);
            }
    }
    ask_huge_pages(max_.data(), max_.size() * sizeof(float));
    ask_huge_pages(hf.texels.data(), hf.texels.size() * sizeof(float));
}

void CurvedPyramid::break_for_test(const Breakage& b) {
    breakage_ = b;
    for (float& m : max_)
        for (int k = 0; k < b.shrink_ulps; ++k)
            m = std::nextafter(m, -std::numeric_limits<float>::infinity());
}

CurvedPyramid::Geo CurvedPyramid::geo(Vec3d p, bool fast) const {
    // BaseSurface::coords of the three bases, the same expressions (so the same doubles);
    // `fast`: the cylinder's height by sqrt, not hypot (within an ulp or two of R: the
    // traversal's, whose shells carry a margin)
    switch (kind_) {
        case Kind::plane:
            return {p.x, p.y, p.z};
        case Kind::cylinder: {
            const double x = p.x - 0.5, z = p.z + R_;
            if (fast) return {0.5 + R_ * fast_atan2(x, z), p.y, std::sqrt(x * x + z * z) - R_};
            return {0.5 + R_ * std::atan2(x, z), p.y, std::hypot(x, z) - R_};
        }
        case Kind::sphere:
        default: {
            const Vec3d q{p.x - 0.5, p.y - 0.5, p.z + R_};
            const double r = std::sqrt(v3_dot(q, q));
            if (fast) {
                const double e = fast_atan2(q.y, std::sqrt(q.x * q.x + q.z * q.z));
                return {0.5 + R_ * fast_atan2(q.x, q.z), 0.5 + R_ * e, r - R_};
            }
            const double e = std::asin(std::clamp(q.y / r, -1.0, 1.0));
            return {0.5 + R_ * std::atan2(q.x, q.z), 0.5 + R_ * e, r - R_};
        }
    }
}

double CurvedPyramid::height_exact(Vec3d p) const {
    // BaseSurface::coords(p).height of the three bases, the same expressions (no azimuth)
    switch (kind_) {
        case Kind::plane:
            return p.z;
        case Kind::cylinder:
            return std::hypot(p.x - 0.5, p.z + R_) - R_;
        case Kind::sphere:
        default: {
            const Vec3d q{p.x - 0.5, p.y - 0.5, p.z + R_};
            return std::sqrt(v3_dot(q, q)) - R_;
        }
    }
}

double CurvedPyramid::g_at(const WorldRay& r, double t, Geo* at) const {
    const Geo c = geo(v3_add(r.o, v3_scale(r.d, t)));
    if (at) *at = c;
    HeightSampler<double> hs(hf_, s_, b_);
    return c.height - hs.z({c.u, c.v});
}

// g and dg/dt at t; (ci, cj) is the cell whose bilinear patch gave them.
CurvedPyramid::Eval CurvedPyramid::eval(const WorldRay& r, double t, int64_t& ci,
                                        int64_t& cj) const {
    const Vec3d p = v3_add(r.o, v3_scale(r.d, t));
    const Vec3d d = r.d;
    double height, du, dv, dheight;
    Geo c{};
    switch (kind_) {
        case Kind::plane:
            c = {p.x, p.y, p.z};
            du = d.x;
            dv = d.y;
            dheight = d.z;
            break;
        case Kind::cylinder: {
            const double x = p.x - 0.5, z = p.z + R_;
            const double rho = std::sqrt(x * x + z * z);
            c = {0.5 + R_ * fast_atan2(x, z), p.y, rho - R_};
            dheight = (x * d.x + z * d.z) / rho;
            du = R_ * (z * d.x - x * d.z) / (rho * rho);
            dv = d.y;
            break;
        }
        case Kind::sphere:
        default: {
            const Vec3d q{p.x - 0.5, p.y - 0.5, p.z + R_};
            const double r2 = v3_dot(q, q), rr = std::sqrt(r2);
            const double qd = v3_dot(q, d), rho2 = q.x * q.x + q.z * q.z;
            const double rho = std::sqrt(rho2);
            c = {0.5 + R_ * fast_atan2(q.x, q.z), 0.5 + R_ * fast_atan2(q.y, rho), rr - R_};
            dheight = qd / rr;
            du = R_ * (q.z * d.x - q.x * d.z) / rho2;
            dv = R_ * (d.y * r2 - q.y * qd) / (r2 * rho);
            break;
        }
    }
    height = c.height;
    // bilinear_texels, the same operations, with its derivatives
    const double x = c.u * double(W_) - 0.5, y = c.v * double(H_) - 0.5;
    const double fx0 = std::floor(x), fy0 = std::floor(y);
    const double fx = x - fx0, fy = y - fy0;
    ci = bilinear_index(fx0);
    cj = bilinear_index(fy0);
    const int i0 = int(wrap_index(ci, W_));
    const int j0 = int(wrap_index(cj, H_));
    const int i1 = i0 + 1 == W_ ? 0 : i0 + 1, j1 = j0 + 1 == H_ ? 0 : j0 + 1;
    const float* row0 = hf_.texels.data() + size_t(j0) * W_;
    const float* row1 = hf_.texels.data() + size_t(j1) * W_;
    const double h00 = row0[i0], h10 = row0[i1], h01 = row1[i0], h11 = row1[i1];
    const double a = h00 + (h10 - h00) * fx;
    const double b = h01 + (h11 - h01) * fx;
    const double h = a + (b - a) * fy;
    const double hx = (h10 - h00) + ((h11 - h01) - (h10 - h00)) * fy;
    const double hy = b - a;
    Eval out;
    out.g = height - s_ * (h - b_);
    out.dg = dheight - s_ * (hx * double(W_) * du + hy * double(H_) * dv);
    return out;
}

CurvedPyramid::CellBounds CurvedPyramid::cell_bounds(int64_t ci, int64_t cj) const {
    // the height field's differences over the cell dilated by one cell (texels ci - 1 .. ci + 2)
    double gx = 0, gy = 0, gxy = 0;
    double t[4][4];
    const int64_t i0 = wrap_index(ci, W_), j0 = wrap_index(cj, H_);
    if (i0 >= 1 && i0 + 2 < W_ && j0 >= 1 && j0 + 2 < H_) {  // inside the tile: no wrapping
        const float* row = hf_.texels.data() + size_t(j0 - 1) * size_t(W_) + size_t(i0 - 1);
        for (int dj = 0; dj < 4; ++dj, row += W_)
            for (int di = 0; di < 4; ++di) t[dj][di] = row[di];
    } else {
        for (int dj = 0; dj < 4; ++dj)
            for (int di = 0; di < 4; ++di) t[dj][di] = hf_.wrapped(i0 - 1 + di, j0 - 1 + dj);
    }
    for (int dj = 0; dj < 4; ++dj)
        for (int di = 0; di < 3; ++di) gx = std::max(gx, std::abs(t[dj][di + 1] - t[dj][di]));
    for (int dj = 0; dj < 3; ++dj)
        for (int di = 0; di < 4; ++di) gy = std::max(gy, std::abs(t[dj + 1][di] - t[dj][di]));
    for (int dj = 0; dj < 3; ++dj)
        for (int di = 0; di < 3; ++di)
            gxy = std::max(gxy,
                           std::abs(t[dj][di] - t[dj][di + 1] - t[dj + 1][di] + t[dj + 1][di + 1]));
    return bounds_of(cj, gx, gy, gxy);
}

CurvedPyramid::CellBounds CurvedPyramid::bounds_of(int64_t cj, double gx, double gy,
                                                   double gxy) const {
    const double W = W_, H = H_;
    const Speeds sp = speeds(cj);
    const double su = sp.su, sv = sp.sv, uu = sp.uu, vv = sp.vv, hh = sp.hh;
    const double as = std::abs(s_);
    CellBounds cb;
    cb.L = (1 + as * (W * gx * su + H * gy * sv)) * (1 + 1e-12);
    cb.K = (hh + as * (W * gx * uu + H * gy * vv + 2 * W * H * gxy * su * sv)) * (1 + 1e-12);
    return cb;
}

double CurvedPyramid::angle_exit(double x, double z, double dx, double dz, double L,
                                 double delta) const {
    // The azimuth phi about the axis moves monotonically along a line, in the direction of the
    // ray's angular momentum L = z dx - x dz, and sweeps less than pi in all, so the ray leaves
    // the wedge only through the half-plane at phi_f = phi + sign(L) delta ahead of it. In the
    // frame of the point's own direction (sin phi, cos phi) = (x, z) / rho, the ray's offset
    // across that half-plane is -rho sin(delta) + tau (|L| cos(delta) - B sin(delta)) / rho
    // (B = x dx + z dz), zero at tau = rho^2 sin(delta) / (|L| cos(delta) - B sin(delta)): a
    // closed form with no cancellation. A denominator <= 0: the line never turns that far.
    if (delta >= kPi) return kInf;
    if (delta <= 0) return 0;
    double sn, cs;
    if (delta < 0.25) {  // Taylor to delta^13: below 1e-17 relative
        const double d2 = delta * delta;
        // (reciprocals multiplied: no division on this path)
        constexpr double k3 = 1.0 / 6, k5 = 1.0 / 20, k7 = 1.0 / 42, k9 = 1.0 / 72, k11 = 1.0 / 110,
                         k13 = 1.0 / 156;
        constexpr double k2 = 0.5, k4 = 1.0 / 12, k6 = 1.0 / 30, k8 = 1.0 / 56, k10 = 1.0 / 90,
                         k12 = 1.0 / 132;
        sn = delta *
             (1 -
              d2 * k3 *
                  (1 - d2 * k5 * (1 - d2 * k7 * (1 - d2 * k9 * (1 - d2 * k11 * (1 - d2 * k13))))));
        cs =
            1 - d2 * k2 *
                    (1 - d2 * k4 * (1 - d2 * k6 * (1 - d2 * k8 * (1 - d2 * k10 * (1 - d2 * k12)))));
    } else {
        sn = std::sin(delta);
        cs = std::cos(delta);
    }
    const double rho2 = x * x + z * z, B = x * dx + z * dz;
    const double den = std::abs(L) * cs - B * sn;
    if (!(den > 0)) return kInf;
    return rho2 * sn / den;
}

double CurvedPyramid::cone_exit(Vec3d q, Vec3d d, const Latitude& lat, bool upward) const {
    const double e = lat.e;
    // Latitude e: q_y cos e = rho sin e (squared: both nappes). The ray leaves upward (latitude
    // rising) through the upper boundary, downward through the lower one. A root is refused
    // only where it is clearly on the other nappe or crossed the wrong way: where rounding
    // leaves that in doubt (a boundary within rounding of the equator, a ray parallel to it)
    // the root counts as an exit, which is conservative. A boundary at the equator to within
    // 1e-14 rad (node borders at v = 0.5, rounded) is the equatorial plane.
    const double qq = v3_dot(q, q), scale = std::sqrt(qq);
    const double tol_y = 64 * kEps * (scale + 1);
    const double tol_r = 64 * kEps * (qq + 1);
    auto wrong_way = [&](double tau) {
        const Vec3d a = v3_add(q, v3_scale(d, tau));
        const double rate = d.y * v3_dot(a, a) - a.y * v3_dot(a, d);  // r^2 cos(lat) lat'
        return upward ? rate < -tol_r : rate > tol_r;
    };
    const double tol = -0.5 * tiny_;
    if (std::abs(e) < 1e-14) {
        if (d.y == 0) return kInf;
        const double tau = -q.y / d.y;
        if (!(tau > tol) || wrong_way(tau)) return kInf;
        return std::max(tau, 0.0);
    }
    const double c2 = lat.c2, s2 = lat.s2;
    const double A = d.y * d.y * c2 - (d.x * d.x + d.z * d.z) * s2;
    const double B = q.y * d.y * c2 - (q.x * d.x + q.z * d.z) * s2;
    const double C = q.y * q.y * c2 - (q.x * q.x + q.z * q.z) * s2;
    const double tau = first_root(A, B, C, [&](double t) {
        if (!(t > tol)) return false;
        const double y = q.y + t * d.y;
        if (e > 0 ? y < -tol_y : y > tol_y) return false;  // the other nappe
        return !wrong_way(t);
    });
    return std::isfinite(tau) ? std::max(tau, 0.0) : kInf;
}

CurvedPyramid::Speeds CurvedPyramid::speeds(int64_t cj) const {
    if (kind_ != Kind::sphere) return speeds_;
    if (cj >= lat_lo_ && cj - lat_lo_ < int64_t(row_speeds_.size()))
        return row_speeds_[size_t(cj - lat_lo_)];
    return make_speeds(cj);
}

CurvedPyramid::Speeds CurvedPyramid::make_speeds(int64_t cj) const {
    // bounds over the segment (above the bottom shell, r >= rmin): speeds |u'|, |v'|, second
    // derivatives |u''|, |v''| and of the height over the base |height''|
    Speeds sp;
    if (kind_ == Kind::cylinder) {
        sp.su = R_ / rmin_;
        sp.uu = 2 * R_ / (rmin_ * rmin_);
        sp.hh = 1 / rmin_;
    } else if (kind_ == Kind::sphere) {
        const double c = latitude(cj).cos_cell;
        const double rho = rmin_ * c, r2 = rmin_ * rmin_;
        sp.su = R_ / rho;
        sp.sv = R_ / rmin_;
        sp.uu = 2 * R_ / (rho * rho);
        sp.vv = R_ * (3 / (r2 * c) + 1 / (r2 * c * c * c));
        sp.hh = 1 / rmin_;
    }
    return sp;
}

CurvedPyramid::Latitude CurvedPyramid::latitude(int64_t d) const {
    if (d >= lat_lo_ && d - lat_lo_ < int64_t(lat_.size())) return lat_[size_t(d - lat_lo_)];
    return make_latitude(d);
}

CurvedPyramid::Latitude CurvedPyramid::make_latitude(int64_t d) const {
    // the node border between rows d - 1 and d of cells: v = (d + 0.5) / H, e = (v - 0.5) / R
    Latitude l;
    const double v = (double(d) + 0.5) * (1.0 / H_);
    l.e = (v - 0.5) / R_;
    l.c2 = std::cos(l.e) * std::cos(l.e);
    l.s2 = std::sin(l.e) * std::sin(l.e);
    // cell_bounds' least cos(latitude) over cell row d dilated by one cell
    const double e0 = ((double(d) - 0.5) / H_ - 0.5) / R_;
    const double e1 = ((double(d) + 2.5) / H_ - 0.5) / R_;
    const double emax = std::min(std::max(std::abs(e0), std::abs(e1)), kPi / 2);
    l.cos_cell = std::max(std::cos(emax), 1e-3);
    return l;
}

double CurvedPyramid::node_exit(const WorldRay& r, Vec3d p, const Geo& c, int64_t c0, int64_t c1,
                                int64_t d0, int64_t d1) const {
    const double iw = 1.0 / W_, ih = 1.0 / H_;
    const double u0 = (double(c0) + 0.5) * iw, u1 = (double(c1) + 0.5) * iw;
    const double v0 = (double(d0) + 0.5) * ih, v1 = (double(d1) + 0.5) * ih;
    const Vec3d d = r.d;
    double tu = kInf, tv = kInf;
    if (kind_ == Kind::plane) {
        if (d.x > 0) tu = std::max((u1 - p.x) / d.x, 0.0);
        if (d.x < 0) tu = std::max((u0 - p.x) / d.x, 0.0);
        if (d.y > 0) tv = std::max((v1 - p.y) / d.y, 0.0);
        if (d.y < 0) tv = std::max((v0 - p.y) / d.y, 0.0);
        return std::min(tu, tv);
    }
    // u: the azimuth about the axis (y), monotone along the ray in the direction of its
    // angular momentum; the sector is clipped to (-pi, pi], where coords wraps
    const double x = p.x - 0.5, z = p.z + R_;
    const double L = z * d.x - x * d.z;
    const double lo = -kPi * R_ + 0.5, hi = kPi * R_ + 0.5;
    if (L != 0 && !(u0 <= lo && u1 >= hi)) {
        const double sigma = L > 0 ? 1.0 : -1.0;
        const double u_f = sigma > 0 ? std::min(u1, hi) : std::max(u0, lo);
        tu = angle_exit(x, z, d.x, d.z, L, sigma * (u_f - c.u) / R_);
    }
    if (kind_ == Kind::cylinder) {
        if (d.y > 0) tv = std::max((v1 - p.y) / d.y, 0.0);
        if (d.y < 0) tv = std::max((v0 - p.y) / d.y, 0.0);
    } else {
        const Vec3d q{x, p.y - 0.5, z};
        const Latitude l0 = latitude(d0), l1 = latitude(d1);
        if (l1.e < kPi / 2) tv = std::min(tv, cone_exit(q, d, l1, true));
        if (l0.e > -kPi / 2) tv = std::min(tv, cone_exit(q, d, l0, false));
    }
    return std::min(tu, tv);
}

double CurvedPyramid::shell_entry(const WorldRay& r, Vec3d p, double height_now,
                                  double offset) const {
    if (height_now <= offset) return 0;
    const Vec3d d = r.d;
    if (kind_ == Kind::plane) return d.z < 0 ? (height_now - offset) / -d.z : kInf;
    // |q + tau d|^2 = (R + offset)^2 from outside: c = (rho - r)(rho + r) without cancellation
    Vec3d q{p.x - 0.5, p.y - 0.5, p.z + R_};
    Vec3d dd = d;
    if (kind_ == Kind::cylinder) q.y = dd.y = 0;
    const double A = v3_dot(dd, dd), B = v3_dot(q, dd);
    if (!(B < 0)) return kInf;  // moving away from the axis (centre): never nearer
    const double rho = R_ + height_now, rr = R_ + offset;
    const double C = (height_now - offset) * (rho + rr);
    const double disc = B * B - A * C;
    if (!(disc >= 0)) return kInf;
    const double q2 = -B + std::sqrt(disc);  // > 0
    return (C / q2) * (1 - 4 * kEps);        // the nearer root, taken a little early
}

double CurvedPyramid::bisect(const WorldRay& r, double lo, double hi, double& g_hi,
                             Geo& c_hi) const {
    // as the walk: g(lo) > 0 (or lo is where the walk started), g(hi) <= 0; g_hi and c_hi: g
    // and the coordinates at the returned hi where the bisection evaluated it there, else NaN
    g_hi = NAN;
    for (int i = 0; i < 200 && hi - lo > 0; ++i) {
        const double mid = lo + 0.5 * (hi - lo);
        if (mid <= lo || mid >= hi) break;
        Geo c;
        const double g = g_at(r, mid, &c);
        if (g <= 0) {
            hi = mid;
            g_hi = g;
            c_hi = c;
        } else {
            lo = mid;
        }
    }
    return hi;
}

CurvedPyramid::Chord CurvedPyramid::chord(const WorldRay& r) const {
    // the walk's chord: enter the shell under the top (or start in it), end where the ray
    // leaves it through the top again or meets the bottom (the walk's own calls)
    Chord c;
    const double top = s_ * (1 - b_), bottom = -s_ * b_;
    if (height_exact(r.o) > top) {
        c.t0 = base_.hit(r.o, r.d, top, 0, false);
        if (!std::isfinite(c.t0)) return c;
    }
    const double t_leave = base_.hit(r.o, r.d, top, c.t0, true);
    const double t_floor = base_.hit(r.o, r.d, bottom, c.t0, false);
    c.t_end = std::isfinite(t_floor) ? t_floor : t_leave;
    if (std::isfinite(t_floor) && std::isfinite(t_leave)) c.t_end = std::min(t_floor, t_leave);
    c.ok = std::isfinite(c.t_end);
    c.floor_ends = std::isfinite(t_floor) && c.t_end == t_floor;
    return c;
}

void CurvedPyramid::finish(const WorldRay& r, double lo, double hi, One& out, double g_hi,
                           const Geo* c_hi) const {
    out.hit = true;
    double g;
    Geo c{};
    out.t = bisect(r, lo, hi, g, c);
    if (std::isnan(g)) {  // at hi itself: the caller's evaluation there, or a new one
        if (c_hi && !std::isnan(g_hi)) {
            g = g_hi;
            c = *c_hi;
        } else {
            g = g_at(r, out.t, &c);
        }
    }
    out.residual = std::abs(g);
    out.u = c.u;
    out.v = c.v;
}

void CurvedPyramid::floor_end(const WorldRay& r, double t_safe, double t_end, One& out) const {
    Geo c;
    const double g = g_at(r, t_end, &c);
    if (g <= 0) return finish(r, t_safe, t_end, out, g, &c);
    out.hit = true;
    out.t = t_end;
    out.residual = std::abs(g);
    out.u = c.u;
    out.v = c.v;
}

CurvedPyramid::CellEnd CurvedPyramid::cell_steps(const WorldRay& r, const CellWalk& w, double& tt,
                                                 double& t_safe, One& out,
                                                 long long max_steps) const {
    // steps that never pass a crossing, from tt to the cell's exit tb
    const CellBounds cb = cell_bounds(w.ci, w.cj);
    const double tb = w.tb;
    for (;;) {
        int64_t ei, ej;
        if (++out.steps > max_steps) return CellEnd::over_budget;
        const Eval ev = eval(r, tt, ei, ej);
        if (ev.g <= 0) {
            // after a safe step, at or below only by rounding: the crossing is within a few
            // ulp before tt (else anywhere after t_safe)
            const double lo = tt - 8 * kEps * std::abs(tt);
            finish(r, lo > t_safe && g_at(r, lo) > 0 ? lo : t_safe, tt, out);
            return CellEnd::hit;
        }
        t_safe = tt;
        double step = ev.g / cb.L;  // Lipschitz: across cells too (dilated bounds)
        if (ei == w.ci && ej == w.cj) {
            // the quadratic lower bound, within this cell's patch only
            const double den = std::sqrt(ev.dg * ev.dg + 2 * cb.K * ev.g) - ev.dg;
            const double newton = den > 0 ? 2 * ev.g / den : (den == 0 ? kInf : 0.0);
            step = std::max(step, std::min(newton, tb - tt));
        }
        if (tt + step >= tb) {
            if (ev.g / cb.L >= tb + w.tiny - tt) {
                tt = tb + w.tiny;  // certified past the cell's exit
                return CellEnd::left;
            }
            if (tb >= w.t_end) {  // certified to the end of the chord
                tt = w.t_end;
                return CellEnd::chord_end;
            }
            if (tt < tb) {  // to the exit, evaluated there
                tt = tb;
                continue;
            }
            if (ei != w.ci || ej != w.cj) return CellEnd::left;  // past it: the traversal goes on
            tt += w.tiny;  // still in it by rounding: past the exit by 1e-10 texel
            return CellEnd::left;
        }
        const double ulps = 8 * kEps * std::abs(tt);
        if (step < ulps) {
            // the safe step is down to a few ulp of t (at a crossing it is Newton's, so the
            // root lies just past it): a step of 8 ulp taken as it is, bisected if it ends at
            // or below the surface
            const double t2 = std::min(tt + ulps, w.t_end);
            Geo c2;
            const double g2 = g_at(r, t2, &c2);
            if (g2 <= 0) {
                finish(r, tt, t2, out, g2, &c2);
                return CellEnd::hit;
            }
            tt = t2;
            if (tt >= w.t_end) return CellEnd::chord_end;
            t_safe = tt;
            continue;
        }
        tt += step;
    }
}

CurvedPyramid::One CurvedPyramid::trace_one(const WorldRay& r, long long max_steps) const {
    One out;
    const Chord ch = chord(r);
    if (!ch.ok) return out;
    const double t_end = ch.t_end;
    const int top_level = levels() - 1;
    int k = top_level;
    double t = ch.t0;
    double t_safe = ch.t0;  // g > 0 on (t_safe, t) or t_safe is the start: a bisection's lo
    // the point's coordinates, kept while t stays (descents at one point)
    Vec3d p{};
    Geo c{};
    int64_t ci = 0, cj = 0;
    double t_geo = NAN;
    while (t < t_end) {
        if (++out.steps > max_steps) return One{false, 0, 0, out.steps};
        if (t != t_geo) {
            p = v3_add(r.o, v3_scale(r.d, t));
            c = geo(p, true);
            ci = bilinear_index(std::floor(c.u * double(W_) - 0.5));
            cj = bilinear_index(std::floor(c.v * double(H_) - 0.5));
            t_geo = t;
        }
        // the node of level k holding the point, in unwrapped cells [c0, c1) x [d0, d1)
        const int64_t TI = cell_solver::floor_div(ci, W_), TJ = cell_solver::floor_div(cj, H_);
        const int64_t ni = (ci - TI * W_) >> k, nj = (cj - TJ * H_) >> k;
        const double hi = s_ * (double(node_max(k, ni, nj)) - b_) + margin_;
        const double tiny = tiny_ + 4 * kEps * std::abs(t);
        const double t_low = t + shell_entry(r, p, c.height, hi);
        const bool skip =
            breakage_.skip_level >= 0 && k == breakage_.skip_level && (ni + nj) % 5 == 0;
        if (t_low == t && k > 0 && !skip) {  // at or under the node's bound here: down
            --k;
            continue;
        }
        double t_exit = kInf;  // the top level's bound holds everywhere (every tile)
        if (k < top_level) {
            const int64_t c0 = TI * W_ + (ni << k),
                          c1 = TI * W_ + std::min((ni + 1) << k, int64_t(W_));
            const int64_t d0 = TJ * H_ + (nj << k),
                          d1 = TJ * H_ + std::min((nj + 1) << k, int64_t(H_));
            t_exit = t + node_exit(r, p, c, c0, c1, d0, d1);
        }
        if ((t_low > t && t_low >= t_exit + tiny) || skip) {
            // the ray stays above the node's relief until it leaves the node: cleared
            t = std::max(t_exit, t) + tiny;
            t_safe = t;
            k = std::min(k + 1, top_level);
            continue;
        }
        if (k > 0) {
            if (t_low > t && t_low < t_end) {  // moved down to the shell: two levels down
                t = t_low;
                t_safe = t;
                k = std::max(k - 2, 0);
                continue;
            }
            --k;
            continue;
        }
        // a cell still in question: steps that never pass a crossing, to its exit
        const double ta = std::max(t, std::min(t_low, t_exit));
        const CellWalk w{ci, cj, std::min(std::max(t_exit, ta), t_end), t_end, tiny};
        double tt = ta;
        const CellEnd e = cell_steps(r, w, tt, t_safe, out, max_steps);
        if (e == CellEnd::over_budget) return One{false, 0, 0, out.steps};
        if (e == CellEnd::hit) return out;
        t = tt;
        k = std::min(1, top_level);
        if (e == CellEnd::chord_end) break;
    }
    // as the walk: its last step ends on the bottom shell, where the relief is met
    if (ch.floor_ends) floor_end(r, t_safe, t_end, out);
    return out;
}

}  // namespace pxh

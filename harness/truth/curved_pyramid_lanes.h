// The pyramid tracer's rays in vector lanes (issue 62, item 2): CurvedPyramid::trace_one,
// L::N rays to a vector, each lane's result bit for bit trace_one's (hit, t, residual, steps,
// the hit's u and v).
//
// Each lane is one ray's walk through the same states as trace_one: the traversal (a node of
// the pyramid at the current t) or the certified steps in a cell. A round takes one traversal
// visit for every lane in the traversal and one cell step for every lane in a cell, over 32
// lanes (kSets vectors) in turn; after each round the lanes trade rays (compact) so that those in
// the traversal sit in the first vectors and those in a cell in the last, since each phase steps
// every vector holding one of its lanes:
// - in lanes: the point and its base coordinates (the table atan2), the node's tile, cell and
//   indices (exact in doubles), its bound and the sphere's latitude borders (L::lookup), the
//   shell's entry root and the node's exit (the wedge; the cylinder's slab or the sphere's two
//   latitude cones), trace_one's decision as masks; in a cell, g and g' from the gathered
//   texels, the two safe steps (g / L and the quadratic bound's root) and the step's outcome;
// - per lane, in scalar code: the chord at a ray's start, a cell's bounds (its texels a row to
//   a vector), the bisection at a hit (CurvedPyramid::finish: the bases' own expressions, with
//   libm) and the rare cases (a cell index beyond 2^51, a latitude outside the table).
// A lane whose ray is done takes the next one. Every lane operation is the scalar expression's
// IEEE operation (lanes.h: no fused multiply-add, min and max as std's), and the rare lanes
// that take libm there (sin and cos of a wedge over 0.25 rad, atan2 of a point on the axis)
// take the same call, so the lanes' doubles are the scalar code's
// (tests/truth/curved_pyramid_lanes_test.cpp; docs/internals/tracers.md, "Issue 62, sixth
// session").
//
// Included only by the translation units of one vector width each (curved_pyramid_avx512.cpp,
// curved_pyramid_avx2.cpp), after their `#pragma GCC target`.
#pragma once
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>

#include "harness/truth/cell_solver.h"
#include "harness/truth/curved_pyramid.h"
#include "harness/truth/lanes.h"

namespace pxh {

template <class L>
struct PyramidLanes {
    using D = typename L::D;
    using M = typename L::M;
    static constexpr int V = L::N;  // lanes to a vector
    // vectors stepped in turn (32 lanes in all), so that their chains overlap
    static constexpr int kSets = 32 / V;
    static constexpr int N = V * kSets;
    static constexpr unsigned kVectorBits = (1u << V) - 1;
    static_assert(N <= 32, "the lanes are tracked in 32-bit masks");
    static constexpr unsigned kAllLanes = N == 32 ? ~0u : (1u << N) - 1;
    static constexpr double kInf = std::numeric_limits<double>::infinity();
    static constexpr double kPi = 3.14159265358979323846;
    static constexpr double kEps = 2.220446049250313e-16;
    using Kind = CurvedPyramid::Kind;
    using One = CurvedPyramid::One;

    const CurvedPyramid& P;
    const double* atan_table;                       // atan(i / 64), i = 0 .. 64: fast_atan2's
    const double iw = 1.0 / P.W_, ih = 1.0 / P.H_;  // node_exit's
    enum Mode : uint8_t { free_lane, traverse, in_cell };

    // the lanes' state, a ray each
    alignas(64) double ox[N], oy[N], oz[N], dx[N], dy[N], dz[N];
    alignas(64) double t[N], t_safe[N], t_end[N];
    // a cell's walk: its exit, 1e-10 texel (and a few ulp of t), the steps' bounds, t there
    alignas(64) double tb[N], tiny[N], cL[N], cK[N], tt[N];
    // scratch between the lanes' arithmetic and the scalar decisions
    alignas(64) double px[N], py[N], pz[N], gu[N], gh[N], fx0[N], fy0[N];
    alignas(64) double hi[N], u0[N], u1[N], v0[N], v1[N];
    alignas(64) double e0[N], c20[N], s20[N], e1[N], c21[N], s21[N];
    alignas(64) double t_low[N], t_exit[N];
    alignas(64) double h00[N], h10[N], h01[N], h11[N], fx[N], fy[N], dh[N], du[N], dv[N];
    alignas(64) double g[N], gL[N], newton[N];
    // the level (a whole number), and per visit: the node has a sector (below the top), is
    // skipped (break_for_test), the cell's patch is the walk's (1 or 0)
    alignas(64) double kd[N], hasx[N], skipf[N], own[N], cid[N], cjd[N];
    alignas(64) double roomd[N];  // steps left in the budget after this visit
    int64_t ci[N], cj[N];
    uint8_t mode[N], floor_ends[N];
    // the pyramid's levels, and the sphere's latitude table
    const float* lev[64];
    int64_t lnx[64];
    int top;
    // per level k: 2^-k, 2^k, the nodes in a row, the level's offset in the pyramid
    alignas(64) double inv_pow2[64], pow2[64], nxd[64], offd[64];
    long long steps[N], cap[N];
    size_t ray[N];

    PyramidLanes(const CurvedPyramid& p, const double* table) : P(p), atan_table(table) {
        for (double* a :
             {ox,  oy, oz,  dx,     dy,    dz,     t,     t_safe, t_end, tb,  tiny, cL, cK, tt,
              px,  py, pz,  gu,     gh,    fx0,    fy0,   hi,     u0,    u1,  v0,   v1, e0, c20,
              s20, e1, c21, s21,    t_low, t_exit, h00,   h10,    h01,   h11, fx,   fy, dh, du,
              dv,  g,  gL,  newton, kd,    hasx,   skipf, own,    cid,   cjd, roomd})
            for (int l = 0; l < N; ++l) a[l] = 0;
        for (int l = 0; l < N; ++l) {
            dz[l] = -1;
            ci[l] = cj[l] = 0;
            mode[l] = free_lane;
            floor_ends[l] = 0;
            steps[l] = cap[l] = 0;
            ray[l] = 0;
        }
        top = P.levels() - 1;
        for (int i = 0; i < 64; ++i) {
            const int li = std::min(i, top);
            lev[i] = P.max_.data() + P.off_[size_t(li)];
            lnx[i] = P.nx_[size_t(li)];
            inv_pow2[i] = std::ldexp(1.0, -i);
            pow2[i] = std::ldexp(1.0, i);
            nxd[i] = double(lnx[i]);
            offd[i] = double(P.off_[size_t(li)]);
        }
    }

    // ---- lane arithmetic ----
    static D c(double a) { return L::set(a); }
    static D ld(const double* a) { return L::load(a); }
    // std::min and std::max: the first argument unless the second is strictly smaller / larger
    static D smin(D a, D b) { return L::select(L::lt(b, a), b, a); }
    static D smax(D a, D b) { return L::select(L::lt(a, b), b, a); }
    static M isfinite(D a) { return L::lt(L::abs(a), c(kInf)); }
    // a cell index's place in its tile, i - floor(i / n) n: exact for |i| under 2^52
    static D in_tile(D i, D n) { return L::sub(i, L::mul(L::floor(L::div(i, n)), n)); }
    // the pyramid's index of the node of level k over the tile's cell (xl, yl)
    D node_index(D k, D xl, D yl) const {
        const D sk = level(inv_pow2, k);
        return L::add(L::add(level(offd, k), L::mul(L::floor(L::mul(yl, sk)), level(nxd, k))),
                      L::floor(L::mul(xl, sk)));
    }
    // a per-level table's entry at level k: a permute where the pyramid has at most 16 levels
    D level(const double* table, D k) const {
        return top < 16 ? L::lookup16(table, k) : L::lookup(table, k);
    }

    template <class F>
    static void each(M m, F&& f) {
        for (unsigned b = L::bits(m); b; b &= b - 1) f(__builtin_ctz(b));
    }

    // CurvedPyramid's fast_atan2, lane by lane (std::atan2 where the larger magnitude is not > 0)
    D atan2(D y, D x) const {
        const D ay = L::abs(y), ax = L::abs(x);
        const M swap = L::gt(ay, ax);
        const D num = L::select(swap, ax, ay), den = L::select(swap, ay, ax);
        const M bad = L::mnot(L::gt(den, c(0)));
        D r = L::div(num, den);
        r = L::select(L::eq(r, r), r, c(0));  // NaN lanes (fixed below) read table[0]
        const D i = L::floor(L::add(L::mul(r, c(64)), c(0.5)));
        const D ci64 = L::mul(i, c(1.0 / 64));
        const D w =
            L::select(L::eq(i, c(0)), r, L::div(L::sub(r, ci64), L::add(c(1), L::mul(r, ci64))));
        const D w2 = L::mul(w, w);
        D p = L::sub(c(1.0 / 7), L::mul(w2, c(1.0 / 9)));
        p = L::sub(c(1.0 / 5), L::mul(w2, p));
        p = L::sub(c(1.0 / 3), L::mul(w2, p));
        p = L::sub(c(1), L::mul(w2, p));
        D a = L::add(L::lookup(atan_table, i), L::mul(w, p));
        a = L::select(swap, L::sub(c(kPi / 2), a), a);
        a = L::select(L::lt(x, c(0)), L::sub(c(kPi), a), a);
        a = L::select(L::lt(y, c(0)), L::neg(a), a);
        if (L::any(bad)) {
            alignas(64) double ya[V], xa[V], out[V];
            L::store(ya, y);
            L::store(xa, x);
            L::store(out, a);
            each(bad, [&](int l) { out[l] = std::atan2(ya[l], xa[l]); });
            a = L::load(out);
        }
        return a;
    }

    // the point o + t d, its base coordinates by geo(p, true), its cell's corner indices as
    // doubles (floor(u W - 0.5), floor(v H - 0.5))
    void traverse_coords(int o) {
        const D T = ld(t + o);
        const D x0 = L::add(ld(ox + o), L::mul(ld(dx + o), T));
        const D y0 = L::add(ld(oy + o), L::mul(ld(dy + o), T));
        const D z0 = L::add(ld(oz + o), L::mul(ld(dz + o), T));
        L::store(px + o, x0);
        L::store(py + o, y0);
        L::store(pz + o, z0);
        const D R = c(P.R_);
        D u, v, h;
        if (P.kind_ == Kind::cylinder) {
            const D x = L::sub(x0, c(0.5)), z = L::add(z0, R);
            u = L::add(c(0.5), L::mul(R, atan2(x, z)));
            v = y0;
            h = L::sub(L::sqrt(L::add(L::mul(x, x), L::mul(z, z))), R);
        } else {
            const D qx = L::sub(x0, c(0.5)), qy = L::sub(y0, c(0.5)), qz = L::add(z0, R);
            const D r = L::sqrt(L::add(L::add(L::mul(qx, qx), L::mul(qy, qy)), L::mul(qz, qz)));
            const D e = atan2(qy, L::sqrt(L::add(L::mul(qx, qx), L::mul(qz, qz))));
            u = L::add(c(0.5), L::mul(R, atan2(qx, qz)));
            v = L::add(c(0.5), L::mul(R, e));
            h = L::sub(r, R);
        }
        L::store(gu + o, u);
        L::store(gh + o, h);
        L::store(fx0 + o, L::floor(L::sub(L::mul(u, c(double(P.W_))), c(0.5))));
        L::store(fy0 + o, L::floor(L::sub(L::mul(v, c(double(P.H_))), c(0.5))));
    }

    // shell_entry(r, p, height, hi) and node_exit(r, p, c, node) for every lane
    void traverse_bounds(int o) {
        const D x0 = ld(px + o), y0 = ld(py + o), z0 = ld(pz + o), DX = ld(dx + o), DY = ld(dy + o),
                DZ = ld(dz + o);
        const D H = ld(gh + o), off = ld(hi + o), R = c(P.R_), T = ld(t + o);
        const bool cyl = P.kind_ == Kind::cylinder;
        {  // the shell's entry root
            const D qx = L::sub(x0, c(0.5)), qz = L::add(z0, R);
            const D qy = cyl ? c(0) : L::sub(y0, c(0.5)), ddy = cyl ? c(0) : DY;
            const D A = L::add(L::add(L::mul(DX, DX), L::mul(ddy, ddy)), L::mul(DZ, DZ));
            const D B = L::add(L::add(L::mul(qx, DX), L::mul(qy, ddy)), L::mul(qz, DZ));
            const D rho = L::add(R, H), rr = L::add(R, off);
            const D C = L::mul(L::sub(H, off), L::add(rho, rr));
            const D disc = L::sub(L::mul(B, B), L::mul(A, C));
            const D q2 = L::add(L::neg(B), L::sqrt(disc));
            D se = L::mul(L::div(C, q2), c(1 - 4 * kEps));
            se = L::select(L::ge(disc, c(0)), se, c(kInf));
            se = L::select(L::lt(B, c(0)), se, c(kInf));
            se = L::select(L::le(H, off), c(0), se);
            L::store(t_low + o, L::add(T, se));
        }
        // the node's exit: the wedge in u
        const D x = L::sub(x0, c(0.5)), z = L::add(z0, R);
        const D Lm = L::sub(L::mul(z, DX), L::mul(x, DZ));
        const D lo = c(-kPi * P.R_ + 0.5), hiu = c(kPi * P.R_ + 0.5);
        const D U0 = ld(u0 + o), U1 = ld(u1 + o);
        const M angle = L::mandnot(L::ne(Lm, c(0)), L::mand(L::le(U0, lo), L::ge(U1, hiu)));
        const M pos = L::gt(Lm, c(0));
        const D sigma = L::select(pos, c(1), c(-1));
        const D uf = L::select(pos, smin(U1, hiu), smax(U0, lo));
        const D delta = L::div(L::mul(sigma, L::sub(uf, ld(gu + o))), R);
        D tu = L::select(angle, angle_exit(angle, x, z, DX, DZ, Lm, delta), c(kInf));
        D tv = c(kInf);
        if (cyl) {
            const D up = smax(L::div(L::sub(ld(v1 + o), y0), DY), c(0));
            const D down = smax(L::div(L::sub(ld(v0 + o), y0), DY), c(0));
            tv = L::select(L::gt(DY, c(0)), up, L::select(L::lt(DY, c(0)), down, c(kInf)));
        } else {
            const D qy = L::sub(y0, c(0.5));
            const D E1 = ld(e1 + o), E0 = ld(e0 + o);
            const M m1 = L::lt(E1, c(kPi / 2)), m0 = L::gt(E0, c(-kPi / 2));
            if (L::any(m1))
                tv = L::select(
                    m1,
                    smin(tv, cone_exit<true>(x, qy, z, DX, DY, DZ, E1, ld(c21 + o), ld(s21 + o))),
                    tv);
            if (L::any(m0))
                tv = L::select(
                    m0,
                    smin(tv, cone_exit<false>(x, qy, z, DX, DY, DZ, E0, ld(c20 + o), ld(s20 + o))),
                    tv);
        }
        L::store(t_exit + o, L::add(T, smin(tu, tv)));
    }

    D angle_exit(M active, D x, D z, D DX, D DZ, D Lm, D delta) const {
        const D d2 = L::mul(delta, delta);
        auto kq = [&](double v) { return L::mul(d2, c(v)); };
        D s = L::sub(c(1), kq(1.0 / 156));
        s = L::sub(c(1), L::mul(kq(1.0 / 110), s));
        s = L::sub(c(1), L::mul(kq(1.0 / 72), s));
        s = L::sub(c(1), L::mul(kq(1.0 / 42), s));
        s = L::sub(c(1), L::mul(kq(1.0 / 20), s));
        D sn = L::mul(delta, L::sub(c(1), L::mul(kq(1.0 / 6), s)));
        D q = L::sub(c(1), kq(1.0 / 132));
        q = L::sub(c(1), L::mul(kq(1.0 / 90), q));
        q = L::sub(c(1), L::mul(kq(1.0 / 56), q));
        q = L::sub(c(1), L::mul(kq(1.0 / 30), q));
        q = L::sub(c(1), L::mul(kq(1.0 / 12), q));
        D cs = L::sub(c(1), L::mul(kq(0.5), q));
        // wedges of 0.25 rad or more (the upper levels): libm, as the scalar code
        const M wide = L::mand(active, L::mand(L::ge(delta, c(0.25)), L::lt(delta, c(kPi))));
        if (L::any(wide)) {
            alignas(64) double da[V], sa[V], ca[V];
            L::store(da, delta);
            L::store(sa, sn);
            L::store(ca, cs);
            each(wide, [&](int l) {
                sa[l] = std::sin(da[l]);
                ca[l] = std::cos(da[l]);
            });
            sn = L::load(sa);
            cs = L::load(ca);
        }
        const D rho2 = L::add(L::mul(x, x), L::mul(z, z));
        const D B = L::add(L::mul(x, DX), L::mul(z, DZ));
        const D den = L::sub(L::mul(L::abs(Lm), cs), L::mul(B, sn));
        D out = L::select(L::gt(den, c(0)), L::div(L::mul(rho2, sn), den), c(kInf));
        out = L::select(L::le(delta, c(0)), c(0), out);
        return L::select(L::ge(delta, c(kPi)), c(kInf), out);
    }

    template <bool upward>
    D cone_exit(D qx, D qy, D qz, D DX, D DY, D DZ, D e, D c2, D s2) const {
        const D qq = L::add(L::add(L::mul(qx, qx), L::mul(qy, qy)), L::mul(qz, qz));
        const D scale = L::sqrt(qq);
        const D tol_y = L::mul(c(64 * kEps), L::add(scale, c(1)));
        const D tol_r = L::mul(c(64 * kEps), L::add(qq, c(1)));
        const D tol = c(-0.5 * P.tiny_);
        auto wrong_way = [&](D tau) {
            const D ax = L::add(qx, L::mul(DX, tau)), ay = L::add(qy, L::mul(DY, tau)),
                    az = L::add(qz, L::mul(DZ, tau));
            const D aa = L::add(L::add(L::mul(ax, ax), L::mul(ay, ay)), L::mul(az, az));
            const D ad = L::add(L::add(L::mul(ax, DX), L::mul(ay, DY)), L::mul(az, DZ));
            const D rate = L::sub(L::mul(DY, aa), L::mul(ay, ad));
            return upward ? L::lt(rate, L::neg(tol_r)) : L::gt(rate, tol_r);
        };
        // a boundary at the equator: the plane y = 0
        const M flat = L::lt(L::abs(e), c(1e-14));
        D eq_tau = L::div(L::neg(qy), DY);
        {
            const M refuse = L::mor(L::mnot(L::gt(eq_tau, tol)), wrong_way(eq_tau));
            eq_tau = L::select(L::mor(L::eq(DY, c(0)), refuse), c(kInf), smax(eq_tau, c(0)));
        }
        // the cone q_y^2 cos^2 e = rho^2 sin^2 e: the first root on its nappe, crossed the
        // right way
        const D A =
            L::sub(L::mul(L::mul(DY, DY), c2), L::mul(L::add(L::mul(DX, DX), L::mul(DZ, DZ)), s2));
        const D B =
            L::sub(L::mul(L::mul(qy, DY), c2), L::mul(L::add(L::mul(qx, DX), L::mul(qz, DZ)), s2));
        const D C =
            L::sub(L::mul(L::mul(qy, qy), c2), L::mul(L::add(L::mul(qx, qx), L::mul(qz, qz)), s2));
        const D nan = c(std::numeric_limits<double>::quiet_NaN());
        const M linear = L::eq(A, c(0));
        const D lin = L::select(L::ne(B, c(0)), L::div(L::neg(C), L::mul(c(2), B)), nan);
        const D disc = L::sub(L::mul(B, B), L::mul(A, C));
        const D qr = L::neg(L::add(B, L::copysign(L::sqrt(disc), B)));
        D r0 = L::div(qr, A);
        D r1 = L::select(L::ne(qr, c(0)), L::div(C, qr), c(0));
        const M sw = L::gt(r0, r1);
        const D lo = L::select(sw, r1, r0), hi2 = L::select(sw, r0, r1);
        const M real = L::ge(disc, c(0));
        r0 = L::select(linear, lin, L::select(real, lo, nan));
        r1 = L::select(linear, nan, L::select(real, hi2, nan));
        auto ok = [&](D r) {
            const D y = L::add(qy, L::mul(r, DY));
            const M nappe_pos = L::lt(y, L::neg(tol_y)), nappe_neg = L::gt(y, tol_y);
            const M epos = L::gt(e, c(0));
            const M wrong_nappe = L::mor(L::mand(epos, nappe_pos), L::mandnot(nappe_neg, epos));
            return L::mandnot(L::mandnot(L::mand(isfinite(r), L::gt(r, tol)), wrong_nappe),
                              wrong_way(r));
        };
        const M ok0 = ok(r0), ok1 = ok(r1);
        D tau = L::select(ok0, r0, L::select(ok1, r1, c(kInf)));
        tau = L::select(isfinite(tau), smax(tau, c(0)), c(kInf));
        return L::select(flat, eq_tau, tau);
    }

    // eval(r, tt): g, g' and the cell's indices as doubles; then, from the texels, g, g / L and
    // the quadratic bound's step
    void cell_coords(int o) {
        const D T = ld(tt + o), DX = ld(dx + o), DY = ld(dy + o), DZ = ld(dz + o), R = c(P.R_);
        const D x0 = L::add(ld(ox + o), L::mul(DX, T));
        const D y0 = L::add(ld(oy + o), L::mul(DY, T));
        const D z0 = L::add(ld(oz + o), L::mul(DZ, T));
        D u, v, h, dheight, dU, dV;
        if (P.kind_ == Kind::cylinder) {
            const D x = L::sub(x0, c(0.5)), z = L::add(z0, R);
            const D rho = L::sqrt(L::add(L::mul(x, x), L::mul(z, z)));
            u = L::add(c(0.5), L::mul(R, atan2(x, z)));
            v = y0;
            h = L::sub(rho, R);
            dheight = L::div(L::add(L::mul(x, DX), L::mul(z, DZ)), rho);
            dU = L::div(L::mul(R, L::sub(L::mul(z, DX), L::mul(x, DZ))), L::mul(rho, rho));
            dV = DY;
        } else {
            const D qx = L::sub(x0, c(0.5)), qy = L::sub(y0, c(0.5)), qz = L::add(z0, R);
            const D r2 = L::add(L::add(L::mul(qx, qx), L::mul(qy, qy)), L::mul(qz, qz));
            const D rr = L::sqrt(r2);
            const D qd = L::add(L::add(L::mul(qx, DX), L::mul(qy, DY)), L::mul(qz, DZ));
            const D rho2 = L::add(L::mul(qx, qx), L::mul(qz, qz));
            const D rho = L::sqrt(rho2);
            u = L::add(c(0.5), L::mul(R, atan2(qx, qz)));
            v = L::add(c(0.5), L::mul(R, atan2(qy, rho)));
            h = L::sub(rr, R);
            dheight = L::div(qd, rr);
            dU = L::div(L::mul(R, L::sub(L::mul(qz, DX), L::mul(qx, DZ))), rho2);
            dV = L::div(L::mul(R, L::sub(L::mul(DY, r2), L::mul(qy, qd))), L::mul(r2, rho));
        }
        L::store(gh + o, h);
        L::store(dh + o, dheight);
        L::store(du + o, dU);
        L::store(dv + o, dV);
        const D x = L::sub(L::mul(u, c(double(P.W_))), c(0.5));
        const D y = L::sub(L::mul(v, c(double(P.H_))), c(0.5));
        const D X0 = L::floor(x), Y0 = L::floor(y);
        L::store(fx0 + o, X0);
        L::store(fy0 + o, Y0);
        L::store(fx + o, L::sub(x, X0));
        L::store(fy + o, L::sub(y, Y0));
    }

    void cell_values(int o) {
        const D FX = ld(fx + o), FY = ld(fy + o);
        const D H00 = ld(h00 + o), H10 = ld(h10 + o), H01 = ld(h01 + o), H11 = ld(h11 + o);
        const D a = L::add(H00, L::mul(L::sub(H10, H00), FX));
        const D b = L::add(H01, L::mul(L::sub(H11, H01), FX));
        const D h = L::add(a, L::mul(L::sub(b, a), FY));
        const D hx =
            L::add(L::sub(H10, H00), L::mul(L::sub(L::sub(H11, H01), L::sub(H10, H00)), FY));
        const D hy = L::sub(b, a);
        const D s = c(P.s_);
        const D G = L::sub(ld(gh + o), L::mul(s, L::sub(h, c(P.b_))));
        const D dG =
            L::sub(ld(dh + o), L::mul(s, L::add(L::mul(L::mul(hx, c(double(P.W_))), ld(du + o)),
                                                L::mul(L::mul(hy, c(double(P.H_))), ld(dv + o)))));
        L::store(g + o, G);
        L::store(gL + o, L::div(G, ld(cL + o)));
        const D den =
            L::sub(L::sqrt(L::add(L::mul(dG, dG), L::mul(L::mul(c(2), ld(cK + o)), G))), dG);
        const D nt = L::select(L::gt(den, c(0)), L::div(L::mul(c(2), G), den),
                               L::select(L::eq(den, c(0)), c(kInf), c(0)));
        L::store(newton + o, nt);
    }

    // ---- scalar, per lane: trace_one's decisions ----
    WorldRay ray_of(int l) const { return WorldRay{{ox[l], oy[l], oz[l]}, {dx[l], dy[l], dz[l]}}; }

    // the ray's walk is over: as trace_one after its loop (the bottom shell ends the chord)
    void end_of_chord(int l, One* out) {
        One o;
        o.steps = steps[l];
        if (floor_ends[l]) P.floor_end(ray_of(l), t_safe[l], t_end[l], o);
        out[ray[l]] = o;
        mode[l] = free_lane;
    }

    void over_budget(int l, One* out) {
        out[ray[l]] = One{false, 0, 0, steps[l]};
        mode[l] = free_lane;
    }

    // the node of level k holding the lane's point, and its bound: a loop of its own over the
    // lanes, without a branch on their data, so that the reads of the pyramid overlap
    int64_t ni_[N], nj_[N], TI_[N], TJ_[N];
    void traverse_bound(int l) {
        const int64_t W = P.W_, Hh = P.H_;
        ci[l] = bilinear_index(fx0[l]);
        cj[l] = bilinear_index(fy0[l]);
        cid[l] = double(ci[l]);
        cjd[l] = double(cj[l]);
        const int kk = int(kd[l]);
        const int64_t TI = cell_solver::floor_div(ci[l], W), TJ = cell_solver::floor_div(cj[l], Hh);
        const int64_t ni = (ci[l] - TI * W) >> kk, nj = (cj[l] - TJ * Hh) >> kk;
        TI_[l] = TI;
        TJ_[l] = TJ;
        ni_[l] = ni;
        nj_[l] = nj;
        hi[l] =
            P.s_ * (double(lev[kk][size_t(nj) * size_t(lnx[kk]) + size_t(ni)]) - P.b_) + P.margin_;
    }

    // Prefetches, for the vector's lanes, what the next phase reads at their cell (fx0, fy0):
    // the pyramid's node at level k and at the level below (where a lane goes down at the same
    // point), or the cell's two texel rows; every set's before any set reads them, so that the
    // reads of a round overlap.
    void prefetch_nodes(int o) {
        const D X0 = ld(fx0 + o), Y0 = ld(fy0 + o), K = ld(kd + o);
        const D Wd = c(double(P.W_)), Hd = c(double(P.H_));
        const D xl = in_tile(X0, Wd), yl = in_tile(Y0, Hd);
        const M ok = L::mand(L::mand(L::ge(xl, c(0)), L::lt(xl, Wd)),
                             L::mand(L::ge(yl, c(0)), L::lt(yl, Hd)));
        alignas(64) double at[2][V];
        for (int lower = 0; lower < 2; ++lower) {
            const D k = lower ? smax(L::sub(K, c(1)), c(0)) : K;
            L::store(at[lower], L::select(ok, node_index(k, xl, yl), c(0)));
        }
        for (int i = 0; i < V; ++i) {
            __builtin_prefetch(P.max_.data() + int64_t(at[0][i]));
            __builtin_prefetch(P.max_.data() + int64_t(at[1][i]));
        }
    }

    void prefetch_texels(int o) {
        const D X0 = ld(fx0 + o), Y0 = ld(fy0 + o);
        const D Wd = c(double(P.W_)), Hd = c(double(P.H_));
        const D i0 = in_tile(X0, Wd), j0 = in_tile(Y0, Hd);
        const M ok = L::mand(L::mand(L::ge(i0, c(0)), L::lt(i0, Wd)),
                             L::mand(L::ge(j0, c(0)), L::lt(j0, Hd)));
        const D j1 = L::select(L::eq(L::add(j0, c(1)), Hd), c(0), L::add(j0, c(1)));
        alignas(64) double r0[V], r1[V];
        L::store(r0, L::select(ok, L::add(L::mul(j0, Wd), i0), c(0)));
        L::store(r1, L::select(ok, L::add(L::mul(j1, Wd), i0), c(0)));
        const float* tex = P.hf_.texels.data();
        for (int i = 0; i < V; ++i) {
            __builtin_prefetch(tex + int64_t(r0[i]));
            __builtin_prefetch(tex + int64_t(r1[i]));
        }
    }

    // traverse_bound and traverse_node in lanes, for the vector's lanes in `act` whose cell
    // index is under 2^51 (its tile and its place in the tile exact in doubles, the node's indices
    // too) and, on the sphere, whose borders' latitudes are in the table; the others are
    // returned, for the scalar code
    unsigned traverse_nodes(int o, unsigned act_bits) {
        const M act = L::from_bits(act_bits);
        const D X0 = ld(fx0 + o), Y0 = ld(fy0 + o), K0 = ld(kd + o), T = ld(t + o);
        const D Wd = c(double(P.W_)), Hd = c(double(P.H_));
        // the tile (TI, TJ) and the cell in it: floor(ci / W) is exact below 2^52
        const D TI = L::floor(L::div(X0, Wd)), TJ = L::floor(L::div(Y0, Hd));
        const D xl = L::sub(X0, L::mul(TI, Wd)), yl = L::sub(Y0, L::mul(TJ, Hd));
        M in = L::mand(act, L::mand(L::lt(L::abs(X0), c(0x1p51)), L::lt(L::abs(Y0), c(0x1p51))));
        in = L::mand(in, L::mand(L::mand(L::ge(xl, c(0)), L::lt(xl, Wd)),
                                 L::mand(L::ge(yl, c(0)), L::lt(yl, Hd))));
        // the node's bound at level k, and where trace_one would go down at this point (the point
        // at or under the bound: the shell's entry is t itself), the levels below, each a visit
        // (a step) of its own as there, as long as the budget allows: the lane's next visit is
        // at the first level whose bound lies under the point, or at level 0
        auto bound_at = [&](D k, M m) {
            const D mx = L::lookup(P.max_.data(), L::select(m, node_index(k, xl, yl), c(0)));
            return L::add(L::mul(c(P.s_), L::sub(mx, c(P.b_))), c(P.margin_));
        };
        D K = K0, bound = bound_at(K0, in);
        if (P.breakage_.skip_level < 0) {
            const D height = ld(gh + o), room = ld(roomd + o);
            D extra = c(0);
            auto more = [&](M m) {
                return L::mand(m, L::mand(L::mand(L::le(height, bound), L::gt(K, c(0))),
                                          L::le(L::add(extra, c(1)), room)));
            };
            M down = more(in);
            if (L::any(down)) {
                do {
                    K = L::select(down, L::sub(K, c(1)), K);
                    extra = L::select(down, L::add(extra, c(1)), extra);
                    bound = L::select(down, bound_at(K, down), bound);
                    down = more(down);
                } while (L::any(down));
                alignas(64) double ex[V];
                L::store(ex, extra);
                for (int i = 0; i < V; ++i) steps[o + i] += (long long)ex[i];
                L::store(kd + o, K);
            }
        }
        const D sk = level(inv_pow2, K), pk = level(pow2, K);
        const D ni = L::floor(L::mul(xl, sk)), nj = L::floor(L::mul(yl, sk));
        const M below_top = L::lt(K, c(double(top)));
        L::store(hasx + o, L::select(below_top, c(1), c(0)));
        L::store(tiny + o,
                 L::select(act, L::add(c(P.tiny_), L::mul(c(4 * kEps), L::abs(T))), ld(tiny + o)));
        L::store(cid + o, L::select(act, X0, ld(cid + o)));
        L::store(cjd + o, L::select(act, Y0, ld(cjd + o)));
        const D tw = L::mul(TI, Wd), th = L::mul(TJ, Hd);
        const D c0 = L::add(tw, L::mul(ni, pk)),
                c1 = L::add(tw, smin(L::mul(L::add(ni, c(1)), pk), Wd));
        const D d0 = L::add(th, L::mul(nj, pk)),
                d1 = L::add(th, smin(L::mul(L::add(nj, c(1)), pk), Hd));
        L::store(u0 + o, L::select(below_top, L::mul(L::add(c0, c(0.5)), c(iw)), c(-kInf)));
        L::store(u1 + o, L::select(below_top, L::mul(L::add(c1, c(0.5)), c(iw)), c(kInf)));
        L::store(v0 + o, L::mul(L::add(d0, c(0.5)), c(ih)));
        L::store(v1 + o, L::mul(L::add(d1, c(0.5)), c(ih)));
        if (P.kind_ == Kind::sphere) {
            static_assert(sizeof(CurvedPyramid::Latitude) == 4 * sizeof(double));
            const D lo = c(double(P.lat_lo_)), rows = c(double(P.lat_.size()));
            const D i0 = L::sub(d0, lo), i1 = L::sub(d1, lo);
            const M ok0 = L::mand(L::ge(i0, c(0)), L::lt(i0, rows));
            const M ok1 = L::mand(L::ge(i1, c(0)), L::lt(i1, rows));
            in = L::mand(in, L::mor(L::mand(ok0, ok1), L::mnot(below_top)));
            const M get = L::mand(in, below_top);
            const D j0 = L::select(get, L::mul(i0, c(4)), c(0));
            const D j1 = L::select(get, L::mul(i1, c(4)), c(0));
            const double* base = &P.lat_[0].e;
            L::store(e0 + o, L::select(get, L::lookup(base, j0), c(-kPi)));
            L::store(e1 + o, L::select(get, L::lookup(base, j1), c(kPi)));
            L::store(c20 + o, L::lookup(base + 1, j0));
            L::store(s20 + o, L::lookup(base + 2, j0));
            L::store(c21 + o, L::lookup(base + 1, j1));
            L::store(s21 + o, L::lookup(base + 2, j1));
        }
        L::store(hi + o, bound);
        if (P.breakage_.skip_level >= 0) {
            alignas(64) double na[V], nb[V];
            L::store(na, ni);
            L::store(nb, nj);
            for (unsigned b = L::bits(in); b; b &= b - 1) {
                const int i = __builtin_ctz(b);
                skipf[o + i] = int(kd[o + i]) == P.breakage_.skip_level &&
                               (int64_t(na[i]) + int64_t(nb[i])) % 5 == 0;
            }
        }
        return L::bits(L::mandnot(act, in));
    }

    // the node's sector
    void traverse_node(int l) {
        const int64_t W = P.W_, Hh = P.H_;
        const int kk = int(kd[l]);
        const int64_t TI = TI_[l], TJ = TJ_[l], ni = ni_[l], nj = nj_[l];
        tiny[l] = P.tiny_ + 4 * kEps * std::abs(t[l]);
        skipf[l] =
            P.breakage_.skip_level >= 0 && kk == P.breakage_.skip_level && (ni + nj) % 5 == 0;
        const bool below_top = kk < top;
        hasx[l] = below_top;
        if (!below_top) {
            u0[l] = -kInf;  // no wedge, no cone (the result is not used)
            u1[l] = kInf;
            e0[l] = -kPi;
            e1[l] = kPi;
            return;
        }
        const int64_t c0 = TI * W + (ni << kk), c1 = TI * W + std::min((ni + 1) << kk, W);
        const int64_t d0 = TJ * Hh + (nj << kk), d1 = TJ * Hh + std::min((nj + 1) << kk, Hh);
        u0[l] = (double(c0) + 0.5) * iw;
        u1[l] = (double(c1) + 0.5) * iw;
        v0[l] = (double(d0) + 0.5) * ih;
        v1[l] = (double(d1) + 0.5) * ih;
        if (P.kind_ == Kind::sphere) {
            const CurvedPyramid::Latitude a = P.latitude(d0), b = P.latitude(d1);
            e0[l] = a.e;
            c20[l] = a.c2;
            s20[l] = a.s2;
            e1[l] = b.e;
            c21[l] = b.c2;
            s21[l] = b.s2;
        }
    }

    // after the node's bounds, trace_one's decision for the vector's lanes in `act`: down a
    // level at the same point, cleared (past the node's exit, up a level), down to the shell
    // (two levels down), down a level, or into the cell (the lanes returned, whose cell walk
    // starts here: tt, tb)
    unsigned traverse_decide(int o, unsigned act_bits) {
        const M act = L::from_bits(act_bits);
        const D T = ld(t + o), TL = ld(t_low + o), K = ld(kd + o), TEND = ld(t_end + o);
        const D TINY = ld(tiny + o);
        const M skip = L::ne(ld(skipf + o), c(0));
        const D TE = L::select(L::ne(ld(hasx + o), c(0)), ld(t_exit + o), c(kInf));
        const M kpos = L::gt(K, c(0));
        const M desc1 = L::mand(act, L::mandnot(L::mand(L::eq(TL, T), kpos), skip));
        const M after1 = L::mandnot(act, desc1);
        const M clear =
            L::mand(after1, L::mor(L::mand(L::gt(TL, T), L::ge(TL, L::add(TE, TINY))), skip));
        const M rest = L::mandnot(after1, clear);
        const M drop = L::mand(L::mand(rest, kpos), L::mand(L::gt(TL, T), L::lt(TL, TEND)));
        const M desc2 = L::mandnot(L::mand(rest, kpos), drop);
        const M cell = L::mandnot(rest, kpos);
        D nt = L::select(clear, L::add(smax(TE, T), TINY), T);
        nt = L::select(drop, TL, nt);
        D nk = L::select(L::mor(desc1, desc2), L::sub(K, c(1)), K);
        nk = L::select(clear, smin(L::add(K, c(1)), c(double(top))), nk);
        nk = L::select(drop, smax(L::sub(K, c(2)), c(0)), nk);
        L::store(t + o, nt);
        L::store(kd + o, nk);
        L::store(t_safe + o, L::select(L::mor(clear, drop), nt, ld(t_safe + o)));
        const D ta = smax(T, smin(TL, TE));
        L::store(tt + o, L::select(cell, ta, ld(tt + o)));
        L::store(tb + o, L::select(cell, smin(smax(TE, ta), TEND), ld(tb + o)));
        return L::bits(cell);
    }

    // CurvedPyramid::cell_bounds, its 4 x 4 texels a row to a vector of 4 doubles where the
    // dilated cell lies inside the tile (the scalar function elsewhere): the same differences
    // (|a - b| and ((a - b) - c) + d are the scalar's operations lane by lane) and their maxima
    // (exact in any order), so the same bounds
    static __m256d shifted(__m256d a) { return _mm256_permute4x64_pd(a, 0xF9); }  // a1 a2 a3 a3
    static double largest(__m256d a) {
        alignas(32) double v[4];
        _mm256_store_pd(v, a);
        return std::max(std::max(v[0], v[1]), std::max(v[2], v[3]));
    }
    CurvedPyramid::CellBounds cell_bounds(int64_t cell_i, int64_t cell_j) const {
        const int64_t W = P.W_, Hh = P.H_;
        const int64_t i0 = wrap_index(cell_i, W), j0 = wrap_index(cell_j, Hh);
        if (!(i0 >= 1 && i0 + 2 < W && j0 >= 1 && j0 + 2 < Hh))
            return P.cell_bounds(cell_i, cell_j);
        const float* row = P.hf_.texels.data() + size_t(j0 - 1) * size_t(W) + size_t(i0 - 1);
        __m256d r[4];
        for (int dj = 0; dj < 4; ++dj) r[dj] = _mm256_cvtps_pd(_mm_loadu_ps(row + dj * W));
        const __m256d sign = _mm256_set1_pd(-0.0);
        __m256d gx = _mm256_setzero_pd(), gy = gx, gxy = gx;
        for (int dj = 0; dj < 4; ++dj)
            gx = _mm256_max_pd(gx, _mm256_andnot_pd(sign, _mm256_sub_pd(shifted(r[dj]), r[dj])));
        for (int dj = 0; dj < 3; ++dj) {
            gy = _mm256_max_pd(gy, _mm256_andnot_pd(sign, _mm256_sub_pd(r[dj + 1], r[dj])));
            const __m256d e = _mm256_add_pd(
                _mm256_sub_pd(_mm256_sub_pd(r[dj], shifted(r[dj])), r[dj + 1]), shifted(r[dj + 1]));
            gxy = _mm256_max_pd(gxy, _mm256_andnot_pd(sign, e));
        }
        return P.bounds_of(cell_j, largest(gx), largest(gy), largest(gxy));
    }

    // cell_texels in lanes, for the vector's lanes in `act` with the cell's indices under 2^51
    // (the others are returned, for the scalar code)
    unsigned cell_texels(int o, unsigned act_bits) {
        const M act = L::from_bits(act_bits);
        const D X0 = ld(fx0 + o), Y0 = ld(fy0 + o);
        const D Wd = c(double(P.W_)), Hd = c(double(P.H_));
        const M in =
            L::mand(act, L::mand(L::lt(L::abs(X0), c(0x1p51)), L::lt(L::abs(Y0), c(0x1p51))));
        const D i0 = in_tile(X0, Wd), j0 = in_tile(Y0, Hd);
        const D i1 = L::select(L::eq(L::add(i0, c(1)), Wd), c(0), L::add(i0, c(1)));
        const D j1 = L::select(L::eq(L::add(j0, c(1)), Hd), c(0), L::add(j0, c(1)));
        const D r0 = L::select(in, L::mul(j0, Wd), c(0)), r1 = L::select(in, L::mul(j1, Wd), c(0));
        const D a0 = L::select(in, i0, c(0)), a1 = L::select(in, i1, c(0));
        const float* tex = P.hf_.texels.data();
        L::store(h00 + o, L::lookup(tex, L::add(r0, a0)));
        L::store(h10 + o, L::lookup(tex, L::add(r0, a1)));
        L::store(h01 + o, L::lookup(tex, L::add(r1, a0)));
        L::store(h11 + o, L::lookup(tex, L::add(r1, a1)));
        const M mine = L::mand(L::eq(X0, ld(cid + o)), L::eq(Y0, ld(cjd + o)));
        L::store(own + o, L::select(mine, c(1), c(0)));
        return L::bits(L::mandnot(act, in));
    }

    void cell_texels(int l) {
        const int64_t ei = bilinear_index(fx0[l]), ej = bilinear_index(fy0[l]);
        const int W = P.W_, Hh = P.H_;
        const int i0 = int(wrap_index(ei, W)), j0 = int(wrap_index(ej, Hh));
        const int i1 = i0 + 1 == W ? 0 : i0 + 1, j1 = j0 + 1 == Hh ? 0 : j0 + 1;
        const float* row0 = P.hf_.texels.data() + size_t(j0) * size_t(W);
        const float* row1 = P.hf_.texels.data() + size_t(j1) * size_t(W);
        h00[l] = row0[i0];
        h10[l] = row0[i1];
        h01[l] = row1[i0];
        h11[l] = row1[i1];
        own[l] = ei == ci[l] && ej == cj[l];
    }

    // cell_steps' loop after its evaluation at tt, for the vector's lanes in `act`: on in the
    // cell (tt moved), back to the traversal (`leave`), the chord's end (`chord`), at or
    // below the surface (`below`: a hit) or a safe step under 8 ulp of t (`small`); the last
    // two go on per lane (cell_rare)
    struct CellOut {
        unsigned leave, chord, below, small;
    };
    CellOut cell_decide(int o, unsigned act_bits) {
        const M act = L::from_bits(act_bits);
        const D T = ld(tt + o), G = ld(g + o), GL = ld(gL + o), TB = ld(tb + o);
        const D TE = ld(t_end + o), TINY = ld(tiny + o);
        const M ownm = L::ne(ld(own + o), c(0));
        const M below = L::mand(act, L::le(G, c(0)));
        const M go = L::mandnot(act, below);
        L::store(t_safe + o, L::select(go, T, ld(t_safe + o)));
        const D step = L::select(ownm, smax(GL, smin(ld(newton + o), L::sub(TB, T))), GL);
        const M reach = L::mand(go, L::ge(L::add(T, step), TB));
        const M leave1 = L::mand(reach, L::ge(GL, L::sub(L::add(TB, TINY), T)));
        const M r2 = L::mandnot(reach, leave1);
        const M chord = L::mand(r2, L::ge(TB, TE));
        const M r3 = L::mandnot(r2, chord);
        const M to_exit = L::mand(r3, L::lt(T, TB));
        const M r4 = L::mandnot(r3, to_exit);
        const M leave3 = L::mand(r4, ownm);
        const M on = L::mandnot(go, reach);
        const M small = L::mand(on, L::lt(step, L::mul(c(8 * kEps), L::abs(T))));
        const M adv = L::mandnot(on, small);
        D nt = L::select(leave1, L::add(TB, TINY), T);
        nt = L::select(chord, TE, nt);
        nt = L::select(to_exit, TB, nt);
        nt = L::select(leave3, L::add(T, TINY), nt);
        nt = L::select(adv, L::add(T, step), nt);
        L::store(tt + o, nt);
        return {L::bits(L::mor(leave1, r4)), L::bits(chord), L::bits(below), L::bits(small)};
    }

    void hit(int l, double lo, double hi_t, One* out, double g_hi = NAN,
             const CurvedPyramid::Geo* c_hi = nullptr) {
        One r;
        r.steps = steps[l];
        P.finish(ray_of(l), lo, hi_t, r, g_hi, c_hi);
        out[ray[l]] = r;
        mode[l] = free_lane;
    }

    // at or below the surface (`below`), or a safe step under 8 ulp of t: as cell_steps
    void cell_rare(int l, bool below, One* out) {
        const WorldRay r = ray_of(l);
        double& T = tt[l];
        if (below) {
            const double lo = T - 8 * kEps * std::abs(T);
            return hit(l, lo > t_safe[l] && P.g_at(r, lo) > 0 ? lo : t_safe[l], T, out);
        }
        const double te = t_end[l];
        const double ulps = 8 * kEps * std::abs(T);
        const double t2 = std::min(T + ulps, te);
        CurvedPyramid::Geo c2;
        const double g2 = P.g_at(r, t2, &c2);
        if (g2 <= 0) return hit(l, T, t2, out, g2, &c2);
        T = t2;
        if (T >= te) {
            t[l] = T;
            return end_of_chord(l, out);
        }
        t_safe[l] = T;
    }

    // a lane takes the next ray that enters the shell (the others are misses with no steps)
    bool start(int l, const WorldRay* rays, size_t n, size_t& next, One* out, long long max_steps,
               long long& spent) {
        while (next < n) {
            const size_t idx = next++;
            const CurvedPyramid::Chord ch = P.chord(rays[idx]);
            if (!ch.ok) {
                out[idx] = One{};
                continue;
            }
            ox[l] = rays[idx].o.x;
            oy[l] = rays[idx].o.y;
            oz[l] = rays[idx].o.z;
            dx[l] = rays[idx].d.x;
            dy[l] = rays[idx].d.y;
            dz[l] = rays[idx].d.z;
            t[l] = t_safe[l] = ch.t0;
            t_end[l] = ch.t_end;
            floor_ends[l] = ch.floor_ends;
            kd[l] = top;
            steps[l] = 0;
            cap[l] = std::max<long long>(max_steps - spent, 0) + 4096;
            ray[l] = idx;
            mode[l] = traverse;
            return true;
        }
        mode[l] = free_lane;
        return false;
    }

    // the rays' steps, done and under way, past max_steps + 4096, or the caller's stop set
    bool over(long long spent, long long max_steps, const std::atomic<bool>* stop) const {
        if (stop && stop->load(std::memory_order_relaxed)) return true;
        long long all = spent;
        for (int l = 0; l < N; ++l)
            if (mode[l] != free_lane) all += steps[l];
        return all > max_steps + 4096;
    }

    // Lanes a and b trade rays: the state a lane keeps from round to round (the rest is
    // written in a round before it is read). A lane's result does not depend on its place, so
    // only which vector does the work changes.
    void swap_lanes(int a, int b) {
        for (double* x :
             {ox, oy, oz, dx, dy, dz, t, t_safe, t_end, tb, tiny, cL, cK, tt, kd, cid, cjd})
            std::swap(x[a], x[b]);
        std::swap(ci[a], ci[b]);
        std::swap(cj[a], cj[b]);
        std::swap(mode[a], mode[b]);
        std::swap(floor_ends[a], floor_ends[b]);
        std::swap(steps[a], steps[b]);
        std::swap(cap[a], cap[b]);
        std::swap(ray[a], ray[b]);
    }
    // Lanes in the traversal to the first places, lanes in a cell to the last, so that a round
    // steps as few vectors as it can: each phase steps every vector holding a lane in it.
    void compact(unsigned tr, unsigned ce) {
        const int nt = __builtin_popcount(tr), nc = __builtin_popcount(ce);
        const unsigned want_t = nt == 32 ? ~0u : (1u << nt) - 1;
        const unsigned want_c = (nc == 0 ? 0u : (kAllLanes >> (N - nc)) << (N - nc)) & ~want_t;
        // a vector count to gain: rounds where the phases already sit apart are left alone
        auto vectors = [](unsigned m) {
            int v = 0;
            for (int o = 0; o < N; o += V) v += ((m >> o) & kVectorBits) != 0;
            return v;
        };
        if (vectors(tr) + vectors(ce) <= vectors(want_t) + vectors(want_c)) return;
        unsigned out_t = tr & ~want_t, in_t = want_t & ~tr;
        for (; out_t; out_t &= out_t - 1, in_t &= in_t - 1) {
            const int a = __builtin_ctz(out_t), b = __builtin_ctz(in_t);
            swap_lanes(a, b);
            if ((ce >> b) & 1) ce = (ce & ~(1u << b)) | (1u << a);
        }
        unsigned out_c = ce & ~want_c, in_c = want_c & ~ce;
        for (; out_c; out_c &= out_c - 1, in_c &= in_c - 1)
            swap_lanes(__builtin_ctz(out_c), __builtin_ctz(in_c));
    }

    void run(const WorldRay* rays, size_t n, One* out, long long max_steps,
             const std::atomic<bool>* stop) {
        size_t next = 0;
        long long spent = 0;
        auto lanes_in = [&](uint8_t m) {  // the lanes in mode m, a bit each
            if constexpr (N == 32) {
                const __m256i v = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(mode));
                return unsigned(
                    _mm256_movemask_epi8(_mm256_cmpeq_epi8(v, _mm256_set1_epi8(char(m)))));
            } else if constexpr (N == 16) {
                const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(mode));
                return unsigned(_mm_movemask_epi8(_mm_cmpeq_epi8(v, _mm_set1_epi8(char(m)))));
            } else {
                unsigned b = 0;
                for (int l = 0; l < N; ++l) b |= unsigned(mode[l] == m) << l;
                return b;
            }
        };
        auto charge = [&](int l) { spent += steps[l]; };
        for (int l = 0; l < N; ++l) start(l, rays, n, next, out, max_steps, spent);
        for (;;) {
            // the traversal's visits
            unsigned tr = lanes_in(traverse);
            for (unsigned b = tr; b; b &= b - 1) {
                const int l = __builtin_ctz(b);
                if (!(t[l] < t_end[l])) {
                    end_of_chord(l, out);
                    charge(l);
                    tr &= ~(1u << l);
                } else if (++steps[l] > cap[l]) {
                    over_budget(l, out);
                    charge(l);
                    tr &= ~(1u << l);
                } else {
                    roomd[l] = double(cap[l] - steps[l]);
                }
            }
            if (tr) {
                for (int o = 0; o < N; o += V)
                    if ((tr >> o) & kVectorBits) {
                        traverse_coords(o);
                        prefetch_nodes(o);
                    }
                for (int o = 0; o < N; o += V) {
                    if (!((tr >> o) & kVectorBits)) continue;
                    const unsigned rest = traverse_nodes(o, (tr >> o) & kVectorBits);
                    for (unsigned b = rest; b; b &= b - 1) {
                        traverse_bound(o + __builtin_ctz(b));
                        traverse_node(o + __builtin_ctz(b));
                    }
                }
                for (int o = 0; o < N; o += V)
                    if ((tr >> o) & kVectorBits) traverse_bounds(o);
                for (int o = 0; o < N; o += V) {
                    if (!((tr >> o) & kVectorBits)) continue;
                    const unsigned enter = traverse_decide(o, (tr >> o) & kVectorBits);
                    for (unsigned b = enter; b; b &= b - 1) {
                        const int l = o + __builtin_ctz(b);
                        ci[l] = int64_t(cid[l]);
                        cj[l] = int64_t(cjd[l]);
                        const CurvedPyramid::CellBounds cb = cell_bounds(ci[l], cj[l]);
                        cL[l] = cb.L;
                        cK[l] = cb.K;
                        mode[l] = in_cell;
                    }
                }
            }
            // the cells' steps
            unsigned ce = lanes_in(in_cell);
            for (unsigned b = ce; b; b &= b - 1) {
                const int l = __builtin_ctz(b);
                if (++steps[l] > cap[l]) {
                    over_budget(l, out);
                    charge(l);
                    ce &= ~(1u << l);
                }
            }
            if (ce) {
                for (int o = 0; o < N; o += V)
                    if ((ce >> o) & kVectorBits) {
                        cell_coords(o);
                        prefetch_texels(o);
                    }
                for (int o = 0; o < N; o += V) {
                    if (!((ce >> o) & kVectorBits)) continue;
                    const unsigned rest = cell_texels(o, (ce >> o) & kVectorBits);
                    for (unsigned b = rest; b; b &= b - 1) cell_texels(o + __builtin_ctz(b));
                }
                for (int o = 0; o < N; o += V)
                    if ((ce >> o) & kVectorBits) cell_values(o);
                for (int o = 0; o < N; o += V) {
                    if (!((ce >> o) & kVectorBits)) continue;
                    const CellOut r = cell_decide(o, (ce >> o) & kVectorBits);
                    for (unsigned b = r.leave; b; b &= b - 1) {
                        const int l = o + __builtin_ctz(b);
                        t[l] = tt[l];
                        kd[l] = std::min(1, top);
                        mode[l] = traverse;
                    }
                    for (unsigned b = r.chord; b; b &= b - 1) {
                        const int l = o + __builtin_ctz(b);
                        t[l] = tt[l];
                        end_of_chord(l, out);
                        charge(l);
                    }
                    for (unsigned b = r.below | r.small; b; b &= b - 1) {
                        const int l = o + __builtin_ctz(b);
                        cell_rare(l, (r.below >> (l - o)) & 1, out);
                        if (mode[l] == free_lane) charge(l);
                    }
                }
            }
            if (over(spent, max_steps, stop)) {
                // the budget is spent: the rays under way end over it, the rest unstarted
                for (unsigned b = ~lanes_in(free_lane) & kAllLanes; b; b &= b - 1)
                    over_budget(__builtin_ctz(b), out);
                for (; next < n; ++next) out[next] = One{};
                return;
            }
            if (next < n)
                for (unsigned b = lanes_in(free_lane); b; b &= b - 1)
                    start(__builtin_ctz(b), rays, n, next, out, max_steps, spent);
            if (lanes_in(free_lane) == kAllLanes) return;
            compact(lanes_in(traverse), lanes_in(in_cell));
        }
    }
};

}  // namespace pxh

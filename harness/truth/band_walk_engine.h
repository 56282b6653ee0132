// The vector band walk (internal to harness/truth), written once over a vector type `O` (O::N
// lanes: band_walk_avx2.cpp's 4, band_walk_avx512.cpp's 8), each file including it after its
// target pragma and after every header it needs (so that only this walk takes the target).
//
// A band's rays, started in order of p0 by the scalar code (ViewTracer::start: the first
// candidate run, the scan passed on from ray to ray), are walked O::N at a time, each lane a ray
// of the band: a step tests every lane's current cell at once as the scalar walk does
// (ViewTracer::walk: the same exit times, the same corners, the solver's first test), solves
// the cells that pass it in vector arithmetic that is solve_patch_inline and first_root operation
// for operation (no contraction: each product rounded), and moves each lane to its next cell by
// the scalar walk's tie rule. What a step cannot do in lanes is done per lane in scalar code:
// a lane whose ray hits, reaches the slab bottom or leaves its column (the next candidate run,
// ViewTracer::next_column, the entry cell, ViewTracer::enter) and the rare cell whose root needs
// first_root's bisection (the scalar solver, ViewTracer::solve). A lane whose ray is done takes
// the band's next ray. So every ray solves the cells the scalar walk solves, in its order, with
// the same arithmetic: the same hits bit for bit (and the same cell counts).
#pragma once
#ifndef PXH_BAND_SETS
#define PXH_BAND_SETS 3
#endif

namespace pxh::band_walk {

template <class O>
class Walker {
  public:
    using D = typename O::D;
    using M = typename O::M;
    static constexpr int N = O::N;
    using Start = ViewTracer::Start;
    // A set of lanes: their rays (st_ index), candidate run, column offset and cells solved,
    // and the vectors' state, the current cell (global and wrapped) as doubles (exact integers).
    struct Lanes {
        size_t ray_[N] = {};
        int64_t o_[N] = {}, q_[N] = {};
        int cells_[N] = {};
        alignas(64) double X0_[N], Y0_[N], ci_[N], cj_[N], wi_[N], wj_[N];
        alignas(64) double old_ci_[N], old_cj_[N], old_wi_[N], old_wj_[N], t_[N], tau_out_[N];
    };
    // kSets sets stepped in turn: a set's lanes written by its events (scalar stores) are read
    // as vectors only after the other sets' steps, when the stores have reached the cache (read
    // at once, each vector load would wait for the stores to drain).

    Walker(const ViewTracer& vt, ViewTracer::Band& band, const Start* st, const size_t* ks,
           size_t n, Hits& out)
        : vt_(vt), band_(band), st_(st), ks_(ks), n_(n), out_(out) {
        const ViewTracer::Ray& r = st[0].r;
        hx_ = r.dX != 0;
        hy_ = r.dY != 0;
        sx_ = r.sx;
        sy_ = r.sy;
        ox_ = sx_ > 0 ? 1 : 0;
        oy_ = sy_ > 0 ? 1 : 0;
        idx_ = r.inv_dX;
        idy_ = r.inv_dY;
        dX_ = r.dX;
        dY_ = r.dY;
        vz_ = r.vz;
        zt_ = r.zt;
        tmax_ = r.tau_max;
        s_ = vt.scale();
        b_ = vt.bias();
        W_ = vt.tracer_width();
        H_ = vt.tracer_height();
        pairs_ = reinterpret_cast<const double*>(vt.column_pairs());
    }

    template <bool MX>
    void run() {
        int active[kSets] = {};
        for (int k = 0; k < kSets; ++k)
            for (int s = 0; s < N; ++s)
                if (fill(sets_[k], s)) active[k] |= 1 << s;
        for (bool any = true; any;) {
            any = false;
            for (int k = 0; k < kSets; ++k)
                if (active[k]) {
                    active[k] = step<MX>(sets_[k], active[k]);
                    any = true;
                }
        }
    }

  private:
    // Lane s takes the band's next ray that has a cell to walk (rays with none are done here);
    // false, the lane idle (on cell (0, 0), so that its reads stay in the field), when none is left.
    bool fill(Lanes& L, int s) {
        while (next_ < n_) {
            const size_t i = next_++;
            const Start& a = st_[i];
            int64_t ci = 0, cj = 0;
            if (a.o > vt_.last_offset(band_, a) || !vt_.enter(band_, a, a.o, ci, cj)) {
                out_.set(ks_[i], vt_.hit(a.r, a.r.tau_max, 0));
                continue;
            }
            L.ray_[s] = i;
            L.o_[s] = a.o;
            L.q_[s] = a.q;
            L.cells_[s] = 0;
            L.X0_[s] = a.r.X0;
            L.Y0_[s] = a.r.Y0;
            place(L, s, ci, cj);
            return true;
        }
        L.X0_[s] = L.Y0_[s] = 0;
        place(L, s, 0, 0);
        return false;
    }
    void place(Lanes& L, int s, int64_t ci, int64_t cj) {
        L.ci_[s] = double(ci);
        L.cj_[s] = double(cj);
        L.wi_[s] = double(wrap_index(ci, W_));
        L.wj_[s] = double(wrap_index(cj, H_));
    }

    // The cells' solve where they pass the first test: solve_patch_inline, lane by lane the
    // same operations (tau_in from ExactTracer::Ray::enter, the quadratic's coefficients).
    D solve(D ci, D cj, D X0, D Y0, D tau_out, const D f[4], M& hard) const {
        const D zero = O::set1(0);
        D tau_in = zero;
        if (hx_) tau_in = O::max(O::mul(O::sub(O::add(ci, O::set1(1 - ox_)), X0), O::set1(idx_)),
                                 tau_in);
        if (hy_) tau_in = O::max(O::mul(O::sub(O::add(cj, O::set1(1 - oy_)), Y0), O::set1(idy_)),
                                 tau_in);
        const D dX = O::set1(dX_), dY = O::set1(dY_), s = O::set1(s_);
        const D fx0 = O::sub(O::add(X0, O::mul(tau_in, dX)), ci);
        const D fy0 = O::sub(O::add(Y0, O::mul(tau_in, dY)), cj);
        const D h00 = f[0], h10 = f[1], h01 = f[2], h11 = f[3];
        const D A = O::sub(h10, h00), B = O::sub(h01, h00);
        const D C = O::add(O::sub(O::sub(h00, h10), h01), h11);
        const D h0 = O::add(O::add(O::add(h00, O::mul(A, fx0)), O::mul(B, fy0)),
                            O::mul(O::mul(C, fx0), fy0));
        const D h1 = O::add(O::add(O::mul(A, dX), O::mul(B, dY)),
                            O::mul(C, O::add(O::mul(fx0, dY), O::mul(fy0, dX))));
        const D h2 = O::mul(O::mul(C, dX), dY);
        const D c0 = O::sub(O::sub(O::set1(zt_), O::mul(tau_in, O::set1(vz_))),
                            O::mul(s, O::sub(h0, O::set1(b_))));
        const D c1 = O::sub(O::set1(-vz_), O::mul(s, h1));
        const D c2 = O::mul(O::set1(-s_), h2);
        const D t = first_root(c0, c1, c2, O::sub(tau_out, tau_in), hard);
        const M direct = O::le(c0, zero);
        hard = O::andnot(direct, hard);
        const D found = O::blend(O::ge(t, zero), O::set1(-1), O::add(tau_in, t));
        return O::blend(direct, found, tau_in);
    }

    // cell_solver::first_root, lane by lane; `hard`: the lanes that need its bisection (their
    // result is left to the scalar solver).
    static D first_root(D c0, D c1, D c2, D len, M& hard) {
        const D zero = O::set1(0), c2len = O::mul(c2, len);
        const D f_end = O::add(c0, O::mul(O::add(c1, c2len), len));
        const D bend = O::add(c1, O::mul(O::mul(O::set1(2), c2), len));
        const M early = O::mand(O::gt(f_end, zero),
                                O::mor(O::le(c2, zero), O::mor(O::ge(c1, zero), O::le(bend, zero))));
        const D a2 = O::mul(O::mul(O::abs(c2), len), len);
        const D scale = O::add(O::add(O::abs(c0), O::mul(O::abs(c1), len)), a2);
        const M lin = O::le(a2, O::mul(O::set1(1e-14), scale));
        D best = O::set1(-1);
        auto consider = [&](M m, D t) {
            const M in = O::mand(m, O::mand(O::ge(t, zero), O::le(t, len)));
            best = O::blend(O::mand(in, O::mor(O::lt(best, zero), O::lt(t, best))), best, t);
        };
        consider(O::mand(lin, O::lt(c1, zero)), O::div(O::neg(c0), c1));
        const D disc = O::sub(O::mul(c1, c1), O::mul(O::mul(O::set1(4), c2), c0));
        const M quad = O::andnot(lin, O::ge(disc, zero));
        const D q = O::mul(O::set1(-0.5), O::add(c1, O::copysign(O::sqrt(disc), c1)));
        const M qm = O::mand(quad, O::ne(q, zero));
        consider(qm, O::div(q, c2));
        consider(qm, O::div(c0, q));
        hard = O::andnot(early, O::mand(O::lt(best, zero), O::le(f_end, zero)));
        return O::blend(early, best, O::set1(-1));
    }

    template <bool MX>
    int step(Lanes& L, int active);
    // A lane's event after a step (hit, slab bottom, column left, bisection): false when its ray
    // is done (the lane then takes the next).
    template <bool MX>
    bool event(Lanes& L, int s, bool hit, bool hard, bool bottom, bool major, double t,
               double tau_out);

    const ViewTracer& vt_;
    ViewTracer::Band& band_;
    const Start* st_;
    const size_t* ks_;
    size_t n_, next_ = 0;
    Hits& out_;
    bool hx_, hy_;
    int sx_, sy_, ox_, oy_;
    double idx_, idy_, dX_, dY_, vz_, zt_, tmax_, s_, b_;
    int64_t W_, H_;
    const double* pairs_;  // column_pairs_: a cell column's two texels per 8 bytes
    static constexpr int kSets = PXH_BAND_SETS;
    Lanes sets_[kSets];
};

template <class O>
template <bool MX>
int Walker<O>::step(Lanes& L, int active) {
    const D X0 = O::load(L.X0_), Y0 = O::load(L.Y0_), ci = O::load(L.ci_), cj = O::load(L.cj_);
    const D wi = O::load(L.wi_), wj = O::load(L.wj_);
    const D inf = O::set1(std::numeric_limits<double>::infinity());
    const D Wd = O::set1(double(W_)), Hd = O::set1(double(H_)), one = O::set1(1);
    // trace_naive's exit_x / exit_y and the cell's exit.
    const D ex = hx_ ? O::mul(O::sub(O::add(ci, O::set1(ox_)), X0), O::set1(idx_)) : inf;
    const D ey = hy_ ? O::mul(O::sub(O::add(cj, O::set1(oy_)), Y0), O::set1(idy_)) : inf;
    const D tau_out = O::min(O::min(ex, ey), O::set1(tmax_));
    // The corners, from column_pairs_ (as solve_cell_pairs reads them).
    const D wi1 = O::blend(O::eq(O::add(wi, one), Wd), O::add(wi, one), O::set1(0));
    const D row = O::mul(wj, Wd);
    D f[4];
    O::corners(pairs_, O::add(row, wi), O::add(row, wi1), f);
    const D top = O::max(O::max(f[0], f[1]), O::max(f[2], f[3]));
    const M below = O::gt(O::sub(O::set1(zt_), O::mul(tau_out, O::set1(vz_))),
                          O::mul(O::set1(s_), O::sub(top, O::set1(b_))));
    const int cand = O::bits(below) ^ ((1 << N) - 1);
    D t = O::set1(-1);
    int hard = 0;
    if (cand & active) {
        M hm;
        t = O::blend(below, solve(ci, cj, X0, Y0, tau_out, f, hm), t);
        hard = O::bits(hm) & cand;
    }
    const int hit = O::bits(O::ge(t, O::set1(0)));
    const int bottom = O::bits(O::ge(tau_out, O::set1(tmax_)));
    const M sx = O::le(ex, ey);
    const int major = MX ? O::bits(sx) : O::bits(sx) ^ ((1 << N) - 1);
    // Every lane to its next cell (those whose ray ends here are refilled below).
    O::store(L.old_ci_, ci);
    O::store(L.old_cj_, cj);
    O::store(L.old_wi_, wi);
    O::store(L.old_wj_, wj);
    O::store(L.t_, t);
    O::store(L.tau_out_, tau_out);
    const D dx = O::set1(sx_), dy = O::set1(sy_);
    const D nwi = O::add(wi, dx), nwj = O::add(wj, dy);
    const D zero = O::set1(0);
    const D wwi = O::blend(O::lt(nwi, zero), O::blend(O::eq(nwi, Wd), nwi, zero), O::sub(Wd, one));
    const D wwj = O::blend(O::lt(nwj, zero), O::blend(O::eq(nwj, Hd), nwj, zero), O::sub(Hd, one));
    O::store(L.ci_, O::blend(sx, ci, O::add(ci, dx)));
    O::store(L.wi_, O::blend(sx, wi, wwi));
    O::store(L.cj_, O::blend(sx, O::add(cj, dy), cj));
    O::store(L.wj_, O::blend(sx, wwj, wj));
    for (int m = active; m; m &= m - 1) ++L.cells_[__builtin_ctz(unsigned(m))];
    for (int m = active & (hit | hard | bottom | major); m; m &= m - 1) {
        const int s = __builtin_ctz(unsigned(m));
        if (!event<MX>(L, s, (hit >> s) & 1, (hard >> s) & 1, (bottom >> s) & 1, (major >> s) & 1,
                       L.t_[s], L.tau_out_[s]) &&
            !fill(L, s))
            active &= ~(1 << s);
    }
    return active;
}

template <class O>
template <bool MX>
bool Walker<O>::event(Lanes& L, int s, bool hit, bool hard, bool bottom, bool major, double t,
                      double tau_out) {
    const size_t i = L.ray_[s];
    const Start& a = st_[i];
    if (hard) {  // the scalar solver on the cell just tested
        t = vt_.solve(a.r, int64_t(L.old_ci_[s]), int64_t(L.old_cj_[s]), int64_t(L.old_wi_[s]),
                      int64_t(L.old_wj_[s]), tau_out);
        hit = t >= 0;
    }
    if (hit || bottom) {
        out_.set(ks_[i], vt_.hit(a.r, hit ? t : tmax_, L.cells_[s]));
        return false;
    }
    if (!major) return true;
    // Left through the major face: the next column of the scalar walk's scan.
    const int64_t o_next = L.o_[s] + 1;
    vt_.next_column(band_, a, L.o_[s], L.q_[s]);
    if (L.o_[s] > vt_.last_offset(band_, a)) {
        out_.set(ks_[i], vt_.hit(a.r, tmax_, L.cells_[s]));
        return false;
    }
    if (L.o_[s] != o_next) {
        int64_t ci = 0, cj = 0;
        if (!vt_.enter(band_, a, L.o_[s], ci, cj)) {
            out_.set(ks_[i], vt_.hit(a.r, tmax_, L.cells_[s]));
            return false;
        }
        place(L, s, ci, cj);
    }
    return true;
}

}  // namespace pxh::band_walk

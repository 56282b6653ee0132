// The vector band walk's solver (internal to harness/truth), written once over a vector type
// `O` (O::N lanes: band_walk_avx2.cpp's 4, band_walk_avx512.cpp's 8), each file including it
// after its target pragma and after every header it needs (so that only this code takes the
// target).
//
// A band's rays, started in order of p0 by the scalar code (ViewTracer::start: the first
// candidate run, the scan passed on from ray to ray), are walked by the scalar walk in steps
// (ViewTracer::begin, resume: the same cells in the same order as ViewTracer::walk), each to the
// next cell that the solver's first test lets through (a candidate). Candidates of O::N rays are
// solved at once, in vector arithmetic that is solve_patch_inline and cell_solver::first_root
// operation for operation (no contraction: each product rounded), the rare cell whose root needs
// first_root's bisection by the scalar solver (ViewTracer::solve). A ray whose candidate holds
// no hit walks on to its next candidate. So every ray solves the cells the scalar walk solves,
// with the same arithmetic: the same hits bit for bit (and the same cell counts).
#pragma once

namespace pxh::band_walk {

template <class O>
class Batch {
  public:
    using D = typename O::D;
    using M = typename O::M;
    static constexpr int N = O::N;
    using Start = ViewTracer::Start;
    using WalkState = ViewTracer::WalkState;

    Batch(const ViewTracer& vt, ViewTracer::Band& band, const Start* st, const size_t* ks, size_t n,
          Hits& out)
        : vt_(vt), band_(band), st_(st), ks_(ks), n_(n), out_(out) {
        const ViewTracer::Ray& r = st[0].r;
        hx_ = r.dX != 0;
        hy_ = r.dY != 0;
        ox_ = r.sx > 0 ? 1 : 0;
        oy_ = r.sy > 0 ? 1 : 0;
        idx_ = r.inv_dX;
        idy_ = r.inv_dY;
        dX_ = r.dX;
        dY_ = r.dY;
        vz_ = r.vz;
        zt_ = r.zt;
        s_ = vt.scale();
        b_ = vt.bias();
    }

    // Every ray walked to its hit: rays join as they reach their first candidate, candidates
    // are solved N at a time.
    void run() {
        for (size_t i = 0; i < n_; ++i) {
            WalkState& w = pend_[held_];
            w.st = st_ + i;
            if (!vt_.begin(band_, w)) finish(w, w.st->r.tau_max);
            else if (++held_ == N)
                while (held_ == N) solve_held();  // (every ray may walk on to another candidate)
        }
        while (held_ > 0) solve_held();
    }

  private:
    void finish(const WalkState& w, double tau) {
        out_.set(ks_[size_t(w.st - st_)], vt_.hit(w.st->r, tau, w.cells));
    }
    // Solves the held rays' candidates (lanes past held_ repeat lane 0); the rays without a hit
    // walk on, those that reach another candidate stay held.
    void solve_held() {
        alignas(64) double ci[N], cj[N], X0[N], Y0[N], to[N], c[4][N], t[N];
        for (int l = 0; l < N; ++l) {
            const WalkState& w = pend_[l < held_ ? l : 0];
            ci[l] = double(w.ci);
            cj[l] = double(w.cj);
            X0[l] = w.st->r.X0;
            Y0[l] = w.st->r.Y0;
            to[l] = w.tau_out;
            for (int k = 0; k < 4; ++k) c[k][l] = w.f[k];
        }
        const D f[4] = {O::load(c[0]), O::load(c[1]), O::load(c[2]), O::load(c[3])};
        M hard;
        O::store(t, solve(O::load(ci), O::load(cj), O::load(X0), O::load(Y0), O::load(to), f, hard));
        const int scalar = O::bits(hard);
        int kept = 0;
        for (int l = 0; l < held_; ++l) {
            WalkState& w = pend_[l];
            const double tl = (scalar >> l) & 1 ? vt_.solve(w.st->r, w.ci, w.cj, w.wi, w.wj, w.tau_out)
                                                : t[l];
            if (tl >= 0) finish(w, tl);
            else if (!vt_.resume(band_, w)) finish(w, w.st->r.tau_max);
            else pend_[kept++] = w;
        }
        held_ = kept;
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

    const ViewTracer& vt_;
    ViewTracer::Band& band_;
    const Start* st_;
    const size_t* ks_;
    size_t n_;
    Hits& out_;
    bool hx_, hy_;
    int ox_, oy_;
    double idx_, idy_, dX_, dY_, vz_, zt_, s_, b_;
    WalkState pend_[N];  // the held rays, each at a candidate
    int held_ = 0;
};

}  // namespace pxh::band_walk

#include "harness/truth/ground_truth.h"

#include <tbb/parallel_for.h>
#include <xmmintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace pxh {

namespace {

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

std::string scale_problem(double scale) {
    if (std::isfinite(scale) && scale > 0) return "";
    return "scale = " + number(scale) + " is not a finite positive number";
}

std::string travel_problem(double scale, double theta_deg, double travel) {
    return "scale " + number(scale) + " at theta " + number(theta_deg) +
           " deg: the rays travel s tan(theta) = " + number(travel) +
           " tiles sideways through the relief, more than the ground truths' limit of " +
           number(kMaxRayTravelTiles) + " tiles (kMaxRayTravelTiles); lower the scale or the angle";
}

// Throws std::invalid_argument with the reason, if any.
void require(const std::string& problem) {
    if (!problem.empty()) throw std::invalid_argument(problem);
}

}  // namespace

std::string ray_travel_problem(double scale, double theta_deg) {
    if (std::string p = scale_problem(scale); !p.empty()) return p;
    if (!(theta_deg >= 0 && theta_deg < 90))
        return "theta = " + number(theta_deg) + " deg lies outside [0, 90)";
    const double travel = scale * std::tan(theta_deg * M_PI / 180.0);  // view_vector's radians
    return travel <= kMaxRayTravelTiles ? "" : travel_problem(scale, theta_deg, travel);
}

std::string ray_travel_problem(double scale, Vec3d D) {
    if (std::string p = scale_problem(scale); !p.empty()) return p;
    if (!(D.z > 0 && std::isfinite(D.x) && std::isfinite(D.y)))
        return "the ray direction (" + number(D.x) + ", " + number(D.y) + ", " + number(D.z) +
               ") does not point above the surface (theta must lie in [0, 90))";
    const double side = std::sqrt(D.x * D.x + D.y * D.y);
    const double travel = scale * (side / D.z);  // NaN or inf for absurd inputs: refused
    if (travel <= kMaxRayTravelTiles * (1 + 1e-9)) return "";
    return travel_problem(scale, std::atan2(side, D.z) * 180 / M_PI, travel);
}

std::vector<Vec2d> sample_grid(int n) {
    std::vector<Vec2d> p(size_t(n) * n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) p[size_t(j) * n + i] = {(i + 0.5) / n, (j + 0.5) / n};
    return p;
}

Vec3d view_vector(double theta_deg, double phi_deg) {
    const double t = theta_deg * M_PI / 180.0, p = phi_deg * M_PI / 180.0;
    return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

ExactTracer::ExactTracer(const HeightField& hf, double scale, double bias)
    : hf_(hf), s_(scale), b_(bias) {
    require(scale_problem(scale));
    const int W = hf.width, H = hf.height;
    column_pairs_.resize(2 * hf.texels.size());
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            column_pairs_[2 * (size_t(j) * W + i)] = hf.at(i, j);
            column_pairs_[2 * (size_t(j) * W + i) + 1] = hf.wrapped(i, j + 1);
        }
    std::vector<float> cells(hf.texels.size());
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i)
            cells[size_t(j) * W + i] = std::max({hf.wrapped(i, j), hf.wrapped(i + 1, j),
                                                 hf.wrapped(i, j + 1), hf.wrapped(i + 1, j + 1)});
    level_max_.push_back(std::move(cells));
    level_w_.push_back(W);
    level_h_.push_back(H);
    while (level_w_.back() > 1 || level_h_.back() > 1) {
        const int pw = level_w_.back(), ph = level_h_.back();
        const int w = (pw + 1) / 2, h = (ph + 1) / 2;
        const auto& prev = level_max_.back();
        std::vector<float> next(size_t(w) * h);
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                float m = prev[size_t(2 * j) * pw + 2 * i];
                if (2 * i + 1 < pw) m = std::max(m, prev[size_t(2 * j) * pw + 2 * i + 1]);
                if (2 * j + 1 < ph) {
                    m = std::max(m, prev[size_t(2 * j + 1) * pw + 2 * i]);
                    if (2 * i + 1 < pw) m = std::max(m, prev[size_t(2 * j + 1) * pw + 2 * i + 1]);
                }
                next[size_t(j) * w + i] = m;
            }
        level_max_.push_back(std::move(next));
        level_w_.push_back(w);
        level_h_.push_back(h);
    }
    for (size_t l = 0; l < std::min<size_t>(kBandLevels, level_max_.size()); ++l) {
        const int w = level_w_[l], h = level_h_[l];
        std::vector<float> t(level_max_[l].size());
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) t[size_t(i) * h + j] = level_max_[l][size_t(j) * w + i];
        level_max_t_.push_back(std::move(t));
    }
}

namespace {

// Smallest t in [0, len] with c0 + c1 t + c2 t^2 <= 0, given c0 > 0; -1 if none.
double first_root(double c0, double c1, double c2, double len) {
    // Most cells the ray clears end above the surface with no dip in between: f(len) > 0 and
    // f has no minimum inside (concave, or its vertex outside [0, len]).
    if (c0 + (c1 + c2 * len) * len > 0 && (c2 <= 0 || c1 >= 0 || c1 + 2 * c2 * len <= 0)) return -1;
    double best = -1;
    auto consider = [&](double t) {
        if (t >= 0 && t <= len && (best < 0 || t < best)) best = t;
    };
    const double scale = std::abs(c0) + std::abs(c1) * len + std::abs(c2) * len * len;
    if (std::abs(c2) * len * len <= 1e-14 * scale) {
        if (c1 < 0) consider(-c0 / c1);
    } else {
        const double disc = c1 * c1 - 4 * c2 * c0;
        if (disc >= 0) {
            const double q = -0.5 * (c1 + std::copysign(std::sqrt(disc), c1));
            if (q != 0) {
                consider(q / c2);
                consider(c0 / q);
            }
        }
    }
    if (best < 0) {
        // Rounding can hide a crossing that the end value proves: f(len) <= 0 < f(0).
        const double f_end = c0 + (c1 + c2 * len) * len;
        if (f_end <= 0) {
            double lo = 0, hi = len;
            for (int it = 0; it < 80; ++it) {
                const double mid = 0.5 * (lo + hi);
                (c0 + (c1 + c2 * mid) * mid > 0 ? lo : hi) = mid;
            }
            best = hi;
        }
    }
    return best;
}

int64_t floor_div(int64_t a, int64_t n) {
    int64_t q = a / n;
    return (a % n != 0 && ((a < 0) != (n < 0))) ? q - 1 : q;
}

}  // namespace

// The eye ray: E - tau V from the slab top (tau = 0) to the slab bottom (tau_max), in grid
// coordinates X = u W - 0.5 (cell i spans X in [i, i + 1]).
struct ExactTracer::Ray {
    double ex, ey, zt, vx, vy, vz, tau_max;
    double X0, Y0, dX, dY, inv_dX, inv_dY;
    int sx, sy;
    // Closed-form parameters where the ray crosses grid line k (x) or l (y).
    double tx(int64_t k) const { return (double(k) - X0) * inv_dX; }
    double ty(int64_t l) const { return (double(l) - Y0) * inv_dY; }
    double enter(int64_t ci, int64_t cj) const {
        double t = 0;
        if (dX != 0) t = std::max(t, tx(sx > 0 ? ci : ci + 1));
        if (dY != 0) t = std::max(t, ty(sy > 0 ? cj : cj + 1));
        return t;
    }
    // Exit parameters of the box [x0, x1) x [y0, y1) of cells.
    double exit_x(int64_t x0, int64_t x1) const {
        return dX != 0 ? tx(sx > 0 ? x1 : x0) : std::numeric_limits<double>::infinity();
    }
    double exit_y(int64_t y0, int64_t y1) const {
        return dY != 0 ? ty(sy > 0 ? y1 : y0) : std::numeric_limits<double>::infinity();
    }
};

ExactTracer::Ray ExactTracer::make_ray(Vec2d P, Vec3d V) const {
    // Within the travel limit every grid coordinate below (start, exits, the slab bottom) is a
    // few times W x kMaxRayTravelTiles at most: all conversions to integers are in range.
    require(ray_travel_problem(s_, V));
    Ray r;
    r.zt = z_top();
    r.vx = V.x;
    r.vy = V.y;
    r.vz = V.z;
    r.ex = P.x + V.x / V.z * r.zt;
    r.ey = P.y + V.y / V.z * r.zt;
    r.tau_max = s_ / V.z;
    r.X0 = r.ex * hf_.width - 0.5;
    r.Y0 = r.ey * hf_.height - 0.5;
    r.dX = -V.x * hf_.width;
    r.dY = -V.y * hf_.height;
    r.inv_dX = r.dX != 0 ? 1 / r.dX : 0;
    r.inv_dY = r.dY != 0 ? 1 / r.dY : 0;
    r.sx = r.dX > 0 ? 1 : -1;
    r.sy = r.dY > 0 ? 1 : -1;
    return r;
}

ExactTracer::Ray ExactTracer::make_ray(Vec2d P, const Ray& like) const {
    // Bit for bit what make_ray(P, V) computes, without repeating the direction's divisions.
    Ray r = like;
    r.ex = P.x + r.vx / r.vz * r.zt;
    r.ey = P.y + r.vy / r.vz * r.zt;
    r.X0 = r.ex * hf_.width - 0.5;
    r.Y0 = r.ey * hf_.height - 0.5;
    return r;
}

TruthHit ExactTracer::hit_at(const Ray& r, double tau, int cells) const {
    TruthHit h;
    h.uv = {r.ex - tau * r.vx, r.ey - tau * r.vy};
    h.z = r.zt - tau * r.vz;
    h.cells = cells;
    return h;
}

[[gnu::always_inline]] inline double ExactTracer::solve_cell(const Ray& r, int64_t ci, int64_t cj, int64_t wi, int64_t wj,
                               double tau_out) const {
    const int64_t W = hf_.width;
    const int64_t wi1 = wi + 1 == W ? 0 : wi + 1;
    const float* row = column_pairs_.data() + 2 * wj * W;  // (h(i, j), h(i, j + 1)) pairs
    const float f00 = row[2 * wi], f01 = row[2 * wi + 1], f10 = row[2 * wi1], f11 = row[2 * wi1 + 1];
    // The cell's maximum (its corners' maximum, the value the hierarchy is built from).
    const float top = std::max(std::max(f00, f10), std::max(f01, f11));
    if (r.zt - tau_out * r.vz > s_ * (double(top) - b_)) return -1;
    const double tau_in = r.enter(ci, cj);
    const double h00 = f00, h10 = f10, h01 = f01, h11 = f11;
    // Local parameter t = tau - tau_in; fractional cell position is linear in t.
    const double fx0 = r.X0 + tau_in * r.dX - double(ci), fy0 = r.Y0 + tau_in * r.dY - double(cj);
    const double A = h10 - h00, B = h01 - h00, C = h00 - h10 - h01 + h11;
    const double h0 = h00 + A * fx0 + B * fy0 + C * fx0 * fy0;
    const double h1 = A * r.dX + B * r.dY + C * (fx0 * r.dY + fy0 * r.dX);
    const double h2 = C * r.dX * r.dY;
    const double c0 = (r.zt - tau_in * r.vz) - s_ * (h0 - b_);
    if (c0 <= 0) return tau_in;
    const double t = first_root(c0, -r.vz - s_ * h1, -s_ * h2, tau_out - tau_in);
    return t >= 0 ? tau_in + t : -1;
}

double ExactTracer::solve_cell(const Ray& r, int64_t ci, int64_t cj, double tau_out) const {
    return solve_cell(r, ci, cj, wrap_index(ci, hf_.width), wrap_index(cj, hf_.height), tau_out);
}

TruthHit ExactTracer::trace_naive(Vec2d P, Vec3d V) const {
    const Ray r = make_ray(P, V);
    int64_t ci = int64_t(std::floor(r.X0)), cj = int64_t(std::floor(r.Y0));
    for (int cells = 1;; ++cells) {
        const double ex = r.exit_x(ci, ci + 1), ey = r.exit_y(cj, cj + 1);
        const double tau_out = std::min({ex, ey, r.tau_max});
        const double t = solve_cell(r, ci, cj, tau_out);
        if (t >= 0) return hit_at(r, t, cells);
        if (tau_out >= r.tau_max) return hit_at(r, r.tau_max, cells);  // z_bot: on or below
        if (ex <= ey) ci += r.sx; else cj += r.sy;
    }
}

TruthHit ExactTracer::trace(Vec2d P, Vec3d V) const {
    const Ray r = make_ray(P, V);
    const int W = hf_.width, H = hf_.height;
    const int top = int(level_max_.size()) - 1;
    const double inf = std::numeric_limits<double>::infinity();
    const double inv_vz = 1 / r.vz;
    const bool has_x = r.dX != 0, has_y = r.dY != 0;
    // The current cell as tile (ti, tj) and tile-local (li, lj), kept without divisions;
    // (ox, oy) is the ray's start in the current tile's local grid coordinates.
    const int64_t ci0 = int64_t(std::floor(r.X0)), cj0 = int64_t(std::floor(r.Y0));
    int64_t ti = floor_div(ci0, W), tj = floor_div(cj0, H);
    int li = int(ci0 - ti * W), lj = int(cj0 - tj * H);
    double ox = r.X0 - double(ti * W), oy = r.Y0 - double(tj * H);
    const float* level_max[64];
    int level_w[64];
    for (int l = 0; l <= top; ++l) {
        level_max[l] = level_max_[l].data();
        level_w[l] = level_w_[l];
    }
    // Start at the level whose blocks are about half the ray's horizontal travel (in
    // cells): coarser blocks hold most of the ray and their test rarely skips anything.
    const double travel = r.tau_max * std::max(std::abs(r.dX), std::abs(r.dY));
    int level = std::clamp(int(std::ceil(std::log2(std::max(travel, 1.0)))) - 1, 0, top);
    int steps = 0;
    double tau_cur = 0;  // the ray's parameter at the current cell
    for (;;) {
        ++steps;
        const int bi = li >> level, bj = lj >> level;
        const int lx0 = bi << level, ly0 = bj << level;
        const int lx1 = std::min(lx0 + (1 << level), W), ly1 = std::min(ly0 + (1 << level), H);
        const double ex = has_x ? (double(r.sx > 0 ? lx1 : lx0) - ox) * r.inv_dX : inf;
        const double ey = has_y ? (double(r.sy > 0 ? ly1 : ly0) - oy) * r.inv_dY : inf;
        const double tau_out = std::min(std::min(ex, ey), r.tau_max);
        const double z_block =
            s_ * (double(level_max[level][size_t(bj) * size_t(level_w[level]) + size_t(bi)]) - b_);
        if (r.zt - tau_out * r.vz <= z_block) {
            if (level > 0) {
                // The surface may reach the ray in this block, but not before the ray has come
                // down to the block's maximum: move there, then look closer.
                const double t_cross = (r.zt - z_block) * inv_vz;
                if (t_cross > tau_cur) {
                    tau_cur = t_cross;
                    li = std::clamp(int(std::floor(ox + t_cross * r.dX)), lx0, lx1 - 1);
                    lj = std::clamp(int(std::floor(oy + t_cross * r.dY)), ly0, ly1 - 1);
                }
                --level;
                continue;
            }
            const double t = solve_cell(r, ti * W + li, tj * H + lj, tau_out);
            if (t >= 0) return hit_at(r, t, steps);
        }
        if (tau_out >= r.tau_max) return hit_at(r, r.tau_max, steps);
        tau_cur = tau_out;
        // Step into the neighbouring cell across the block's exit face (the naive DDA's
        // choice on a tie).
        int nli = li, nlj = lj;
        if (ex <= ey) {
            nli = r.sx > 0 ? lx1 : lx0 - 1;
            if (level > 0) nlj = std::clamp(int(std::floor(oy + ex * r.dY)), ly0, ly1 - 1);
        } else {
            nlj = r.sy > 0 ? ly1 : ly0 - 1;
            if (level > 0) nli = std::clamp(int(std::floor(ox + ey * r.dX)), lx0, lx1 - 1);
        }
        // Coarser levels are worth a test only once the ray has left their block (inside the
        // same parent, the parent's test would fail again): the parents differ up to the
        // highest bit in which the old and new cell indices differ. Climb one level at most
        // (measured: climbing higher costs more failed tests than it saves).
        const unsigned diff = unsigned(nli ^ li) | unsigned(nlj ^ lj);
        li = nli;
        lj = nlj;
        bool new_tile = false;
        if (li >= W) { li -= W; ++ti; ox -= W; new_tile = true; }
        else if (li < 0) { li += W; --ti; ox += W; new_tile = true; }
        if (lj >= H) { lj -= H; ++tj; oy -= H; new_tile = true; }
        else if (lj < 0) { lj += H; --tj; oy += H; new_tile = true; }
        if (new_tile) level = std::min(level + 1, top);
        else if (diff) level = std::max(level, std::min({31 - __builtin_clz(diff), level + 1, top}));
    }
}

// ---- All rays of a view at once -------------------------------------------------------------
//
// Every eye ray of a view has the same direction, so its path across the grid is the same line
// shifted sideways. Let the major axis be the one the ray crosses faster, p the coordinate along
// it (increasing as the ray advances: column c spans p in [c, c + 1]), q the other one, and
// eta = q - m p (m = dq/dp) the ray's lateral offset, constant along the ray. The ray's height
// is z = C - k p with C = z_top + k p0 fixed per ray. Rays are grouped in bands of lateral
// width w; over columns [ca, cb) a band's rays cover q in [eta_lo + m p, eta_lo + w + m p], so
// the cells they can cross there are known, and with M the maximum of those cells' maxima
// (read from the maximum mipmap's level l, blocks of 2^l cells, runs of 2^l columns)
//     U = s (M - b) + k cb
// bounds what any of its rays can meet: a ray reaches the surface in the run only if U >= C
// (its lowest point there is C - k cb). A ray scans U (with maxima over blocks of 16 and 256
// runs to skip fast) for the first such run, walks its cells as trace_naive does (same cell
// order, same tie rule, same solve_cell), and resumes the scan if the ray clears them. Runs
// skipped hold no cell trace_naive would solve (a margin of 1e-9 relative absorbs rounding, and
// the band's cells are widened by 1e-6 grid units), so the hits are trace_naive's own.
namespace {
// Maximum of p[0 .. n), n >= 1.
inline float range_max(const float* p, int64_t n) {
    if (n < 4) return std::max(std::max(p[0], p[n / 2]), p[n - 1]);  // covers n = 1, 2, 3
    __m128 m = _mm_loadu_ps(p);
    for (int64_t q = 4; q + 4 <= n; q += 4) m = _mm_max_ps(m, _mm_loadu_ps(p + q));
    m = _mm_max_ps(m, _mm_loadu_ps(p + n - 4));
    m = _mm_max_ps(m, _mm_movehl_ps(m, m));
    m = _mm_max_ss(m, _mm_shuffle_ps(m, m, 1));
    return _mm_cvtss_f32(m);
}
}  // namespace

class ViewTracer {
  public:
    using Ray = ExactTracer::Ray;

    ViewTracer(const ExactTracer& tr, Vec2d P0, Vec3d V) : t_(tr), like_(tr.make_ray(P0, V)) {
        const Ray& r = like_;
        major_x_ = std::abs(r.dX) >= std::abs(r.dY);
        const double dM = major_x_ ? r.dX : r.dY, dm = major_x_ ? r.dY : r.dX;
        dmaj_ = std::abs(dM);
        sa_ = dM > 0 ? 1 : -1;
        m_ = dmaj_ > 0 ? dm / dmaj_ : 0;
        k_ = dmaj_ > 0 ? r.vz / dmaj_ : 0;
        inv_k_ = 1 / k_;
        z_max_ = tr.s_ * (double(tr.level_max_.back()[0]) - tr.b_);
        nmaj_ = major_x_ ? tr.hf_.width : tr.hf_.height;
        nmin_ = major_x_ ? tr.hf_.height : tr.hf_.width;
        use_level(0);
    }
    // Bounds from the maximum mipmap's level l (blocks of 2^l cells): coarser, fewer misses.
    void use_level(int l) {
        l_ = std::min(l, int(t_.level_max_t_.size()) - 1);
        nmin_l_ = major_x_ ? t_.level_h_[size_t(l_)] : t_.level_w_[size_t(l_)];
        cmax_ = (major_x_ ? t_.level_max_t_ : t_.level_max_)[size_t(l_)].data();
        // Blocks a quarter of a chunk long (256 runs of 2^l columns): a chunk's coarse bound
        // reads about 4 block columns by the few block rows its band crosses there.
        coarse_ = std::min(l_ + 6, int(t_.level_max_.size()) - 1);
    }
    int level() const { return l_; }
    bool major_x() const { return major_x_; }
    int sign() const { return sa_; }
    double slope() const { return m_; }
    // Worth it once a ray crosses a few columns; else the per-ray walk is as good.
    bool useful() const { return dmaj_ * like_.tau_max >= 2; }
    Ray ray(Vec2d P) const { return t_.make_ray(P, like_); }
    double p0(const Ray& r) const { return sa_ * major(r); }

    struct Scan {
        int64_t c0;       // the column trace_naive starts in
        int64_t c_first;  // columns before lie wholly above the highest surface point
        int64_t c_last;   // the column holding the slab bottom (plus one)
        double Cm;        // C less the rounding margin
    };
    Scan scan(const Ray& r) const {
        Scan sc;
        const int64_t i0 = int64_t(std::floor(major(r)));
        sc.c0 = sa_ > 0 ? i0 : -i0 - 1;
        const double p0 = this->p0(r);
        const double C = r.zt + k_ * p0;
        sc.Cm = C - 1e-9 * (std::abs(C) + t_.s_);
        sc.c_last = int64_t(std::floor(p0 + r.tau_max * dmaj_)) + 1;
        const double first = std::ceil((sc.Cm - z_max_) * inv_k_) - 2;  // 2 to spare for rounding
        sc.c_first = first > double(sc.c0) ? (first < double(sc.c_last) ? int64_t(first) : sc.c_last)
                                           : sc.c0;
        return sc;
    }

    struct Band {
        // U per run of 2^l columns (l: the mipmap level), with maxima over blocks of 16 and 256
        // runs, built a chunk of 256 runs at a time when a ray first needs it. Until then the
        // chunk's sblk holds a coarser bound (from a coarser mipmap level), and a chunk whose
        // coarse bound no ray reaches is never built: rays that skim low ground for thousands
        // of tiles (grazing views) cost a bound per chunk there, not one per run, and memory
        // only for the chunks built.
        double eta_lo = 0, w = 1;
        int64_t base = 0;            // column where run 0 starts (a multiple of 2^l)
        int64_t chunks = 0;          // chunks [0, chunks) have a bound in sblk
        std::vector<double> sblk;    // per chunk of 256 runs: the max of its U once built, else
                                     // the coarse bound (never below that max)
        std::vector<int32_t> slot;   // per chunk: where U and blk hold it once built, else -1
        int32_t used = 0;            // chunks held in U and blk
        std::vector<double> U;       // bound per run, chunk by chunk (slot k: U[256 k ..])
        std::vector<double> blk;     // max of U over blocks of 16 runs (slot k: blk[16 k ..])
    };

    // The band's cells over p in [ca, cb]: minor index in [lo0 + m p, hi0 + m p] (widened by
    // 1e-6 grid units, so that cells touched only by rounding are included too); the first
    // such index and their count, for columns [ca, cb).
    std::pair<int64_t, int64_t> minor_cells(const Band& band, int64_t ca, int64_t cb) const {
        const double eps = 1e-6;
        const double lo0 = band.eta_lo - eps, hi0 = band.eta_lo + band.w + eps;
        const double qa = m_ * double(ca), qb = m_ * double(cb);
        const int64_t j0 = int64_t(std::floor(lo0 + std::min(qa, qb)));
        return {j0, int64_t(std::floor(hi0 + std::max(qa, qb))) - j0 + 1};
    }

    // Coarse bounds for chunks [band.chunks, c]: the maximum over the coarse mipmap level's
    // blocks holding the chunk's cells (they hold every level-l block its runs read, so the
    // bound is never below the chunk's U, in floating point too), at the chunk's last column.
    void extend(Band& band, int64_t c) const {
        band.sblk.resize(size_t(c + 1));
        band.slot.resize(size_t(c + 1));
        const int64_t len = int64_t(256) << l_;  // a chunk's columns
        for (int64_t k = band.chunks; k <= c; ++k) {
            const int64_t ca = band.base + k * len, cb = ca + len;
            const auto [j0, n] = minor_cells(band, ca, cb);
            const float mx = region_max(sa_ > 0 ? ca : -cb, len, j0, n);
            band.sblk[size_t(k)] = t_.s_ * (double(mx) - t_.b_) + k_ * double(cb);
            band.slot[size_t(k)] = -1;
        }
        band.chunks = c + 1;
    }

    // Maximum over the blocks of the coarse level holding cells [a0, a0 + na) along the major
    // axis and [b0, b0 + nb) along the minor one (both taken modulo the field).
    float region_max(int64_t a0, int64_t na, int64_t b0, int64_t nb) const {
        const int L = coarse_;
        // Block index ranges along one axis: one, or two where the cells wrap.
        auto ranges = [L](int64_t c0, int64_t n, int64_t cells, int64_t r[4]) {
            if (n >= cells) { r[0] = 0; r[1] = (cells - 1) >> L; return 1; }
            const int64_t s = wrap_index(c0, cells), e = s + n - 1;
            if (e < cells) { r[0] = s >> L; r[1] = e >> L; return 1; }
            r[0] = s >> L; r[1] = (cells - 1) >> L; r[2] = 0; r[3] = (e - cells) >> L;
            return 2;
        };
        int64_t ra[4], rb[4];
        const int na_r = ranges(a0, na, nmaj_, ra), nb_r = ranges(b0, nb, nmin_, rb);
        const float* lv = t_.level_max_[size_t(L)].data();
        const int64_t lw = t_.level_w_[size_t(L)];
        float mx = -std::numeric_limits<float>::infinity();
        for (int x = 0; x < na_r; ++x)
            for (int y = 0; y < nb_r; ++y)
                for (int64_t A = ra[2 * x]; A <= ra[2 * x + 1]; ++A)
                    for (int64_t B = rb[2 * y]; B <= rb[2 * y + 1]; ++B)
                        mx = std::max(mx, major_x_ ? lv[B * lw + A] : lv[A * lw + B]);
        return mx;
    }

    // Builds chunk c's U and blk (c < band.chunks); its sblk becomes their maximum.
    void build(Band& band, int64_t c) const {
        const int32_t k = band.used++;
        band.slot[size_t(c)] = k;
        if (band.U.size() < size_t(band.used) << 8) {
            band.U.resize(size_t(band.used) << 8);
            band.blk.resize(size_t(band.used) << 4);
        }
        const double s = t_.s_, b = t_.b_;
        const int64_t len = int64_t(1) << l_;
        double* U = band.U.data() + (size_t(k) << 8);  // run q at U[q - begin]
        const int64_t begin = c << 8, end = begin + 256;
        for (int64_t q = begin; q < end; ++q) {
            const int64_t ca = band.base + (q << l_), cb = ca + len;  // columns [ca, cb)
            const auto [j0, n] = minor_cells(band, ca, cb);
            // The run's cell columns: len consecutive ones from t (mod nmaj), through every
            // block column they touch (one when nmaj is a multiple of 2^l: runs are aligned).
            int64_t t = wrap_index(sa_ > 0 ? ca : -cb, nmaj_);
            float mx = -std::numeric_limits<float>::infinity();
            for (int64_t left = std::min(len, nmaj_); left > 0;) {
                const int64_t I = t >> l_, next = std::min((I + 1) << l_, nmaj_);
                mx = std::max(mx, block_column_max(I, j0, n));
                left -= next - t;
                t = next == nmaj_ ? 0 : next;
            }
            U[q - begin] = s * (double(mx) - b) + k_ * double(cb);
        }
        auto reduce = [](const double* u) {
            double mx = u[0];
            for (int k = 1; k < 16; ++k) mx = std::max(mx, u[k]);
            return mx;
        };
        double* blk = band.blk.data() + (size_t(k) << 4);
        for (int i = 0; i < 16; ++i) blk[i] = reduce(U + 16 * i);
        band.sblk[size_t(c)] = reduce(blk);
    }

    // Maximum over the level-l blocks of block column I that hold cells j0 .. j0 + n - 1.
    float block_column_max(int64_t I, int64_t j0, int64_t n) const {
        const float* col = cmax_ + I * nmin_l_;
        if (n >= nmin_) return range_max(col, nmin_l_);
        const int64_t jw = wrap_index(j0, nmin_), jl = jw + n - 1;
        if (jl < nmin_) return range_max(col + (jw >> l_), (jl >> l_) - (jw >> l_) + 1);
        return std::max(range_max(col + (jw >> l_), nmin_l_ - (jw >> l_)),  // wraps once
                        range_max(col, ((jl - nmin_) >> l_) + 1));
    }

    // The first run in [q, q_last] whose bound reaches Cm, or q_last + 1.
    int64_t find(Band& band, int64_t q, int64_t q_last, double Cm) const {
        while (q <= q_last) {
            const int64_t c = q >> 8;
            if (c >= band.chunks) extend(band, c);
            if (band.sblk[size_t(c)] < Cm) { q = (q | 255) + 1; continue; }
            const int32_t k = band.slot[size_t(c)];
            if (k < 0) {
                build(band, c);  // then test the chunk's own maximum
                continue;
            }
            const size_t at = size_t(k) << 8;  // the chunk's run 0 in U
            if (band.blk[(at + size_t(q & 255)) >> 4] < Cm) { q = (q | 15) + 1; continue; }
            const double* U = band.U.data() + at;  // run q at U[q & 255]
            for (const int64_t e = std::min(q | 15, q_last); q <= e; ++q)
                if (U[q & 255] >= Cm) return q;
        }
        return q_last + 1;
    }

    // A ray ready to walk: its first candidate run q and column offset o.
    struct Start {
        Ray r;
        Scan sc;
        int64_t q, o;
    };
    // Finds the ray's first candidate (lb: a column no later than it; rays taken in order of
    // p0 pass on their own first candidate) and asks the memory system early for the texels
    // of the cell the ray enters there, which it will most likely solve.
    Start start(Band& band, Vec2d P, int64_t& lb) const {
        Start st{ray(P), {}, 0, 0};
        st.sc = scan(st.r);
        const int64_t o_start = std::max(st.sc.c_first, lb) - band.base;
        st.q = find(band, o_start >> l_, (st.sc.c_last - band.base) >> l_, st.sc.Cm);
        st.o = std::max(st.q << l_, o_start);
        lb = band.base + st.o;
        const int64_t c = band.base + st.o, i = sa_ > 0 ? c : -c - 1;
        const Ray& r = st.r;
        const double T = major_x_ ? r.tx(r.sx > 0 ? i : i + 1) : r.ty(r.sy > 0 ? i : i + 1);
        const double g = std::floor((major_x_ ? r.Y0 : r.X0) + T * (major_x_ ? r.dY : r.dX));
        if (std::abs(g) < 1e15) {
            const int64_t W = t_.hf_.width, H = t_.hf_.height;
            const int64_t ci = wrap_index(major_x_ ? i : int64_t(g), W);
            const int64_t cj = wrap_index(major_x_ ? int64_t(g) : i, H);
            _mm_prefetch(reinterpret_cast<const char*>(t_.column_pairs_.data() + 2 * (cj * W + ci)), _MM_HINT_T0);
        }
        return st;
    }
    TruthHit trace(Band& band, const Start& st) const {
        return major_x_ ? walk<true>(band, st) : walk<false>(band, st);
    }

  private:
    // Each candidate column's cells as trace_naive walks them; the scan resumes when the ray
    // clears a column.
    template <bool MX>
    TruthHit walk(Band& band, const Start& st) const {
        const Ray& r = st.r;
        const Scan& sc = st.sc;
        const int64_t o_last = sc.c_last - band.base, q_last = o_last >> l_;
        int64_t q = st.q, o = st.o;
        int cells = 0;
        int64_t ci = 0, cj = 0, o_next = -1;  // (ci, cj): the entry cell of column o_next
        const double X0 = r.X0, Y0 = r.Y0, idx = r.inv_dX, idy = r.inv_dY;
        const double tmax = r.tau_max;
        const double inf = std::numeric_limits<double>::infinity();
        const bool hx = r.dX != 0, hy = r.dY != 0;
        const int sx = r.sx, sy = r.sy;
        const int64_t ox = sx > 0 ? 1 : 0, oy = sy > 0 ? 1 : 0;
        const int64_t W = t_.hf_.width, H = t_.hf_.height;
        for (; o <= o_last; o = ((o + 1) >> l_) == q ? o + 1 : (q = find(band, (o + 1) >> l_, q_last, sc.Cm)) << l_) {
            const int64_t c = band.base + o;
            if (o != o_next) {
                // trace_naive's cell on entering column c: the first from its start cell whose
                // minor exit is not passed yet (on a tie trace_naive steps in x first).
                const int64_t i = sa_ > 0 ? c : -c - 1;
                const double Q0 = MX ? r.Y0 : r.X0;
                const int64_t g0 = int64_t(std::floor(Q0));
                int64_t g = g0;
                if (c != sc.c0) {
                    const double T = MX ? r.tx(r.sx > 0 ? i : i + 1) : r.ty(r.sy > 0 ? i : i + 1);
                    if (T >= r.tau_max) return t_.hit_at(r, r.tau_max, cells);
                    auto exit_minor = [&](int64_t q) { return MX ? r.exit_y(q, q + 1) : r.exit_x(q, q + 1); };
                    const int sm = MX ? r.sy : r.sx;
                    g = int64_t(std::floor(Q0 + T * (MX ? r.dY : r.dX)));
                    if (MX) {
                        while (exit_minor(g) < T) g += sm;
                        while (g != g0 && exit_minor(g - sm) >= T) g -= sm;
                    } else {
                        while (exit_minor(g) <= T) g += sm;
                        while (g != g0 && exit_minor(g - sm) > T) g -= sm;
                    }
                    ci = MX ? i : g;
                    cj = MX ? g : i;
                } else {
                    ci = int64_t(std::floor(r.X0));
                    cj = int64_t(std::floor(r.Y0));
                }
            }
            int64_t wi = wrap_index(ci, W), wj = wrap_index(cj, H);
            for (;;) {
                ++cells;
                // trace_naive's exit_x / exit_y, from locals.
                const double ex = hx ? (double(ci + ox) - X0) * idx : inf;
                const double ey = hy ? (double(cj + oy) - Y0) * idy : inf;
                const double tau_out = std::min({ex, ey, tmax});
                const double t = t_.solve_cell(r, ci, cj, wi, wj, tau_out);
                if (t >= 0) return t_.hit_at(r, t, cells);
                if (tau_out >= tmax) return t_.hit_at(r, tmax, cells);
                if (ex <= ey) {
                    ci += sx;
                    wi += sx;
                    if (wi == W) wi = 0;
                    else if (wi < 0) wi = W - 1;
                    if (MX) break;
                } else {
                    cj += sy;
                    wj += sy;
                    if (wj == H) wj = 0;
                    else if (wj < 0) wj = H - 1;
                    if (!MX) break;
                }
            }
            o_next = o + 1;  // left through the major face: (ci, cj) is column o + 1's entry cell
        }
        return t_.hit_at(r, r.tau_max, cells);
    }

    double major(const Ray& r) const { return major_x_ ? r.X0 : r.Y0; }

    const ExactTracer& t_;
    Ray like_;  // the direction-dependent part of every ray
    bool major_x_;
    int sa_;
    double dmaj_, m_, k_, inv_k_, z_max_;
    int64_t nmaj_, nmin_;  // grid cells along the major / minor axis
    int l_ = 0;            // the mipmap level the bounds are built from
    int coarse_ = 0;       // the level of the chunks' coarse bounds
    int64_t nmin_l_ = 0;   // its blocks along the minor axis
    const float* cmax_;    // its block maxima, minor-contiguous: [major block * nmin_l + minor block]
};

namespace {

// Traces the rays of one band, given in order of p0 (ties in order of k), one ray ahead: the
// next ray's first candidate is found (and its texels requested) before the current one walks.
class BandRun {
  public:
    BandRun(const ViewTracer& vt, ViewTracer::Band& band, TruthHit* out) : vt_(vt), band_(band), out_(out) {}
    void begin(double eta_lo, double w) {
        band_.eta_lo = eta_lo;
        band_.w = w;
        band_.chunks = 0;
        band_.used = 0;
        any_ = false;
    }
    void add(Vec2d P, size_t k) {
        if (!any_) {
            // Run 0 starts at the earliest first column (the first ray's), in whole runs.
            band_.base = vt_.scan(vt_.ray(P)).c_first & ~((int64_t(1) << vt_.level()) - 1);
            lb_ = band_.base;
            cur_ = vt_.start(band_, P, lb_);
            k_ = k;
            any_ = true;
            return;
        }
        const ViewTracer::Start next = vt_.start(band_, P, lb_);
        out_[k_] = vt_.trace(band_, cur_);
        cur_ = next;
        k_ = k;
    }
    void end() {
        if (any_) out_[k_] = vt_.trace(band_, cur_);
        any_ = false;
    }

  private:
    const ViewTracer& vt_;
    ViewTracer::Band& band_;
    TruthHit* out_;
    bool any_ = false;
    ViewTracer::Start cur_{};
    size_t k_ = 0;
    int64_t lb_ = 0;
};

// Band width in grid units: about the rays' spacing (the side of the grid area per ray), so
// that a band holds a row of rays; narrower bands bound more tightly but cost a bound per run.
double band_width(double area, size_t rays) {
    return std::clamp(std::round(std::sqrt(area / double(std::max<size_t>(rays, 1)))), 1.0, 8.0);
}

// The mipmap level the bounds come from: blocks about half the band's width (level 0, the
// cells themselves, for bands one cell wide), small arrays that stay in cache.
int band_level(double w) {
    return std::max(0, int(std::lround(std::log2(w / 2))));
}

}  // namespace

void ExactTracer::trace_grid(int n, Vec3d V, std::vector<TruthHit>& out) const {
    require(ray_travel_problem(s_, V));  // before any band's bounds grow with the travel
    out.resize(size_t(n) * size_t(std::max(n, 0)));
    if (n <= 0) return;
    auto sample = [n](int64_t i, int64_t j) { return Vec2d{(double(i) + 0.5) / n, (double(j) + 0.5) / n}; };
    ViewTracer vt(*this, sample(0, 0), V);
    if (!vt.useful()) {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, out.size(), 256), [&](const auto& rg) {
            for (size_t k = rg.begin(); k < rg.end(); ++k) out[k] = trace_naive(sample(int64_t(k % n), int64_t(k / n)), V);
        });
        return;
    }
    // Bands of rays, each traced in order of p0 (its start along the major axis), enumerated
    // without sorting: a sample's p0 depends only on its major index a, its lateral offset
    // eta = q0 - m p0 only grows with its minor index b, so band by band, for each a in order
    // of p0, the band's samples are a run of b, followed from one a to the next.
    const bool mx = vt.major_x();
    auto ij = [mx](int64_t a, int64_t b) { return mx ? std::pair{a, b} : std::pair{b, a}; };
    std::vector<double> maj(static_cast<size_t>(n)), mnr(static_cast<size_t>(n));  // X0 or Y0 by index
    for (int64_t t = 0; t < n; ++t) {
        const ExactTracer::Ray r = vt.ray(sample(t, t));
        maj[size_t(t)] = mx ? r.X0 : r.Y0;
        mnr[size_t(t)] = mx ? r.Y0 : r.X0;
    }
    auto eta = [&](int64_t a, int64_t b) { return mnr[size_t(b)] - vt.slope() * (vt.sign() * maj[size_t(a)]); };
    // eta is monotone in a and in b: its extremes lie at the corners.
    double eta_lo = std::numeric_limits<double>::infinity(), eta_hi = -eta_lo;
    for (int64_t a : {int64_t(0), int64_t(n - 1)})
        for (int64_t b : {int64_t(0), int64_t(n - 1)}) eta_lo = std::min(eta_lo, eta(a, b)), eta_hi = std::max(eta_hi, eta(a, b));
    const double spacing = double(n - 1) / n;  // the samples' extent, in tiles
    const double area = std::max(1.0, spacing * hf_.width) * std::max(1.0, spacing * hf_.height);
    const double w = band_width(area, size_t(n) * size_t(n));
    vt.use_level(band_level(w));
    const double inv_w = 1 / w;
    const int64_t bands = int64_t(std::floor((eta_hi - eta_lo) * inv_w)) + 1;
    auto band = [&](int64_t a, int64_t b) {
        return std::min(bands - 1, int64_t((eta(a, b) - eta_lo) * inv_w));
    };
    tbb::parallel_for(tbb::blocked_range<int64_t>(0, bands, 1), [&](const auto& rg) {
        ViewTracer::Band mem;
        BandRun run(vt, mem, out.data());
        for (int64_t bd = rg.begin(); bd < rg.end(); ++bd) {
            run.begin(eta_lo + double(bd) * w, w);
            int64_t b0 = -1;  // the band's first b at the current a
            for (int64_t step = 0; step < n; ++step) {
                const int64_t a = vt.sign() > 0 ? step : n - 1 - step;  // p0 grows
                if (b0 < 0) {  // first a: search (band grows with b)
                    int64_t lo = 0, hi = n;
                    while (lo < hi) {
                        const int64_t mid = (lo + hi) / 2;
                        if (band(a, mid) < bd) lo = mid + 1;
                        else hi = mid;
                    }
                    b0 = lo;
                } else {
                    while (b0 < n && band(a, b0) < bd) ++b0;
                    while (b0 > 0 && band(a, b0 - 1) >= bd) --b0;
                }
                for (int64_t b = b0; b < n && band(a, b) == bd; ++b) {
                    const auto [i, j] = ij(a, b);
                    run.add(sample(i, j), size_t(j) * size_t(n) + size_t(i));
                }
            }
            run.end();
        }
    });
}

bool ExactTracer::occluded(Vec2d uv, double z0, Vec3d L) const {
    if (!(L.z > 0)) return true;  // light at or below the horizon
    require(ray_travel_problem(s_, L));  // the walk below is as long as the travel
    const int W = hf_.width, H = hf_.height;
    const double zt = z_top();
    if (z0 >= zt) return false;
    const double tau_max = (zt - z0) / L.z;  // the ray leaves the slab here
    const double X0 = uv.x * W - 0.5, Y0 = uv.y * H - 0.5;
    const double dX = L.x * W, dY = L.y * H;
    int64_t ci = int64_t(std::floor(X0)), cj = int64_t(std::floor(Y0));
    const int step_i = dX > 0 ? 1 : -1, step_j = dY > 0 ? 1 : -1;
    const double inf = std::numeric_limits<double>::infinity();
    const double tdx = dX != 0 ? 1.0 / std::abs(dX) : inf, tdy = dY != 0 ? 1.0 / std::abs(dY) : inf;
    double tmx = dX > 0 ? (double(ci) + 1 - X0) / dX : (dX < 0 ? (X0 - double(ci)) / -dX : inf);
    double tmy = dY > 0 ? (double(cj) + 1 - Y0) / dY : (dY < 0 ? (Y0 - double(cj)) / -dY : inf);
    // The start lies on the surface (f = 0 there): only a clear dip below counts.
    const double eps = 1e-12 * std::max(s_, 1e-300);
    // The highest surface point: once the ray is at or above it, no later cell's test below can
    // pass (the ray only rises), so the answer is known without walking the rest of the travel.
    const double z_max = s_ * (double(level_max_.back()[0]) - b_);
    double tau_in = 0;
    for (;;) {
        const double tau_out = std::min({tmx, tmy, tau_max});
        const int64_t wi = wrap_index(ci, W), wj = wrap_index(cj, H);
        const double z_in = z0 + tau_in * L.z;  // the ray's lowest point in this cell
        if (z_in >= z_max) return false;
        if (z_in < s_ * (double(level_max_[0][size_t(wj) * W + wi]) - b_)) {
            const double h00 = hf_.at(int(wi), int(wj));
            const double h10 = hf_.wrapped(wi + 1, wj), h01 = hf_.wrapped(wi, wj + 1);
            const double h11 = hf_.wrapped(wi + 1, wj + 1);
            const double fx0 = X0 + tau_in * dX - double(ci), fy0 = Y0 + tau_in * dY - double(cj);
            const double A = h10 - h00, B = h01 - h00, C = h00 - h10 - h01 + h11;
            const double h0 = h00 + A * fx0 + B * fy0 + C * fx0 * fy0;
            const double h1 = A * dX + B * dY + C * (fx0 * dY + fy0 * dX);
            const double h2 = C * dX * dY;
            // f(t) = ray z - surface z, t in [0, len]; occluded if f < -eps somewhere.
            const double c0 = z_in - s_ * (h0 - b_), c1 = L.z - s_ * h1, c2 = -s_ * h2;
            const double len = tau_out - tau_in;
            auto f = [&](double t) { return c0 + (c1 + c2 * t) * t; };
            if (f(len) < -eps) return true;
            if (c2 > 0) {
                const double tv = -c1 / (2 * c2);
                if (tv > 0 && tv < len && f(tv) < -eps) return true;
            }
            // Leaving the start point downhill into the surface (f(0) = 0, f' < 0).
            if (tau_in == 0 && c0 <= eps && c1 < 0) return true;
        }
        if (tau_out >= tau_max) return false;
        tau_in = tau_out;
        if (tmx <= tmy) { ci += step_i; tmx += tdx; } else { cj += step_j; tmy += tdy; }
    }
}

GroundTruth trace_ground_truth(const HeightField& hf, double scale, double bias, Vec3d V, int n,
                               const Vec3d* L) {
    return trace_ground_truth(ExactTracer(hf, scale, bias), V, n, L);
}

GroundTruth trace_ground_truth(const ExactTracer& tracer, Vec3d V, int n, const Vec3d* L) {
    if (L && L->z > 0) require(ray_travel_problem(tracer.scale(), *L));  // before any tracing
    std::vector<TruthHit> hits;
    tracer.trace_grid(n, V, hits);
    GroundTruth gt;
    gt.uv.resize(hits.size());
    gt.z.resize(hits.size());
    if (L) gt.lit.resize(hits.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, hits.size(), 256), [&](const auto& r) {
        for (size_t k = r.begin(); k < r.end(); ++k) {
            gt.uv[k] = hits[k].uv;
            gt.z[k] = hits[k].z;
            if (L) gt.lit[k] = !tracer.occluded(hits[k].uv, hits[k].z, *L);
        }
    });
    double sum = 0;
    for (const TruthHit& h : hits) sum += h.cells;
    gt.cells_mean = hits.empty() ? 0 : sum / double(hits.size());
    return gt;
}

}  // namespace pxh

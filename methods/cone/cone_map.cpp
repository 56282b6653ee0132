// Cone map generation (methods/cone/cone_map.h; sources cited there).
#include "methods/cone/cone_map.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace pxh::cone_maps {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A max pyramid over a W x H array: node (l, i, j) covers entries [i 2^l, (i + 1) 2^l) x
// [j 2^l, (j + 1) 2^l), clipped to the array.
struct MaxPyramid {
    std::vector<int> w, h;
    std::vector<std::vector<float>> lv;
    MaxPyramid(std::vector<float> base, int W, int H) {
        w.push_back(W);
        h.push_back(H);
        lv.push_back(std::move(base));
        while (w.back() > 1 || h.back() > 1) {
            const int pw = w.back(), ph = h.back(), nw = (pw + 1) / 2, nh = (ph + 1) / 2;
            const std::vector<float>& src = lv.back();
            std::vector<float> dst(size_t(nw) * size_t(nh));
            for (int j = 0; j < nh; ++j)
                for (int i = 0; i < nw; ++i) {
                    float m = src[size_t(2 * j) * pw + size_t(2 * i)];
                    for (int dj = 0; dj < 2; ++dj)
                        for (int di = 0; di < 2; ++di)
                            if (2 * i + di < pw && 2 * j + dj < ph)
                                m = std::max(m, src[size_t(2 * j + dj) * pw + size_t(2 * i + di)]);
                    dst[size_t(j) * nw + size_t(i)] = m;
                }
            w.push_back(nw);
            h.push_back(nh);
            lv.push_back(std::move(dst));
        }
    }
    float at(int l, int i, int j) const {
        return lv[size_t(l)][size_t(j) * w[size_t(l)] + size_t(i)];
    }
    int top() const { return int(lv.size()) - 1; }
};

// The candidates of one source, found through the pyramid. The field tiles: each block is
// visited in the 3 x 3 tile images around the base tile (shift sx, sy in tiles); a ratio is
// capped at 1 and heights differ by at most 1, so nothing farther than one tile can count.
// bound(i0, i1, j0, j1, block max): a lower bound of every candidate of the block (index
// ranges shifted into the image); leaf(i, j, sx, sy): one entry (tile indices) of one image.
// A block is skipped when its bound cannot lower `cur` (the running minimum the leaves update).
template <class Bound, class Leaf>
void visit(const MaxPyramid& p, const double& cur, Bound&& bound, Leaf&& leaf) {
    struct Node {
        int l, i, j, sx, sy;
        double b;
    };
    const int W = p.w[0], H = p.h[0];
    thread_local std::vector<Node> stack;
    stack.clear();
    auto node_bound = [&](int l, int i, int j, int sx, int sy) {
        const int s = 1 << l;
        const int i0 = i * s, i1 = std::min(i0 + s, W) - 1, j0 = j * s,
                  j1 = std::min(j0 + s, H) - 1;
        return bound(i0 + sx * W, i1 + sx * W, j0 + sy * H, j1 + sy * H, p.at(l, i, j));
    };
    const int top = p.top();
    for (int sy : {1, -1, 0})
        for (int sx : {1, -1, 0})
            stack.push_back({top, 0, 0, sx, sy, node_bound(top, 0, 0, sx, sy)});
    while (!stack.empty()) {
        const Node n = stack.back();
        stack.pop_back();
        if (n.b * (1 - 1e-12) >= cur) continue;  // no candidate of the block is below cur
        if (n.l == 0) {
            leaf(n.i, n.j, n.sx, n.sy);
            continue;
        }
        Node kids[4];
        int k = 0;
        const int l = n.l - 1;
        for (int dj = 0; dj < 2; ++dj)
            for (int di = 0; di < 2; ++di) {
                const int ci = 2 * n.i + di, cj = 2 * n.j + dj;
                if (ci < p.w[size_t(l)] && cj < p.h[size_t(l)])
                    kids[k++] = {l, ci, cj, n.sx, n.sy, node_bound(l, ci, cj, n.sx, n.sy)};
            }
        // Largest bound pushed first: the most promising block is searched first.
        for (int q = 0; q < k; ++q) {
            int best = q;
            for (int r = q + 1; r < k; ++r)
                if (kids[r].b > kids[best].b) best = r;
            std::swap(kids[q], kids[best]);
            stack.push_back(kids[q]);
        }
    }
}

// Every entry of every image: the brute force's loop.
template <class Leaf>
void visit_all(int W, int H, Leaf&& leaf) {
    for (int sy = -1; sy <= 1; ++sy)
        for (int sx = -1; sx <= 1; ++sx)
            for (int j = 0; j < H; ++j)
                for (int i = 0; i < W; ++i) leaf(i, j, sx, sy);
}

double sq(double x) { return x * x; }

// |(ax / W, ay / H)|: the uv distance of integer texel offsets (ax, ay >= 0).
struct Metric {
    int W, H;
    double dist(int64_t ax, int64_t ay) const {
        return std::sqrt(sq(double(ax) / W) + sq(double(ay) / H));
    }
    // The smallest |offset| from index c to the range [a0, a1].
    static int64_t gap(int64_t c, int64_t a0, int64_t a1) {
        return std::max<int64_t>({0, a0 - c, c - a1});
    }
};

// Runs per_texel(i, j) for every texel, rows in parallel.
template <class F>
std::vector<float> per_texel(int W, int H, F&& f) {
    std::vector<float> out(size_t(W) * size_t(H));
    tbb::parallel_for(0, H, [&](int j) {
        for (int i = 0; i < W; ++i) out[size_t(j) * W + size_t(i)] = f(i, j);
    });
    return out;
}

std::vector<float> texel_heights(const HeightField& hf) { return hf.texels; }

// ---- Dummer's cones and Ban et al.'s corrected relaxed cones: texel-centre candidates ----

// Ban et al.'s "limiting vertex" test (Conemap.cs.slang, updateMinTan): q = (i, j) at offset
// (ox, oy) from the source; the cell beyond q in each quadrant direction q lies in.
bool limiting(const HeightField& hf, int i, int j, int64_t ox, int64_t oy) {
    const int xs[2] = {ox < 0 ? -1 : 1, ox == 0 ? -1 : 0};
    const int ys[2] = {oy < 0 ? -1 : 1, oy == 0 ? -1 : 0};
    for (int dx : xs) {
        if (dx == 0) continue;
        for (int dy : ys) {
            if (dy == 0) continue;
            const float h00 = hf.wrapped(i, j), h10 = hf.wrapped(i + dx, j);
            const float h01 = hf.wrapped(i, j + dy), h11 = hf.wrapped(i + dx, j + dy);
            if (h00 > h10 || h00 > h01 || h10 > h11 || h01 > h11) return true;
        }
    }
    return false;
}

// The texel-centre candidate of source (ik, jk) and entry (i, j) of image (sx, sy); only
// limiting vertices when `relaxed`. Lowers cur.
struct CentreCandidates {
    const HeightField& hf;
    Metric m;
    bool relaxed;
    int ik, jk;
    double hk;
    double* cur;
    void operator()(int i, int j, int sx, int sy) const {
        const double h = hf.at(i, j);
        if (!(h > hk)) return;
        const int64_t ox = int64_t(i) + int64_t(sx) * m.W - ik;
        const int64_t oy = int64_t(j) + int64_t(sy) * m.H - jk;
        if (relaxed && !limiting(hf, i, j, ox, oy)) return;
        *cur = std::min(*cur, m.dist(std::abs(ox), std::abs(oy)) / (h - hk));
    }
    double bound(int64_t i0, int64_t i1, int64_t j0, int64_t j1, float hmax) const {
        if (!(double(hmax) > hk)) return kInf;
        return m.dist(Metric::gap(ik, i0, i1), Metric::gap(jk, j0, j1)) / (double(hmax) - hk);
    }
};

// The heights a relaxed candidate can have: h where the texel is a limiting vertex for some
// quadrant direction, -1 elsewhere (never above a source), so that plateaus are skipped whole.
std::vector<float> limiting_heights(const HeightField& hf) {
    std::vector<float> out(hf.texels.size());
    tbb::parallel_for(0, hf.height, [&](int j) {
        for (int i = 0; i < hf.width; ++i)
            out[size_t(j) * hf.width + size_t(i)] =
                limiting(hf, i, j, 0, 0) ? hf.at(i, j) : -1.0f;  // offset 0: every direction
    });
    return out;
}

std::vector<float> centre_map(const HeightField& hf, bool relaxed, bool brute) {
    const Metric m{hf.width, hf.height};
    const MaxPyramid pyr(brute     ? std::vector<float>{0.f}
                         : relaxed ? limiting_heights(hf)
                                   : texel_heights(hf),
                         brute ? 1 : m.W, brute ? 1 : m.H);
    return per_texel(m.W, m.H, [&](int i, int j) {
        double cur = 1;
        const CentreCandidates c{hf, m, relaxed, i, j, hf.at(i, j), &cur};
        if (brute) visit_all(m.W, m.H, c);
        else
            visit(
                pyr, cur,
                [&](int64_t i0, int64_t i1, int64_t j0, int64_t j1, float hm) {
                    return c.bound(i0, i1, j0, j1, hm);
                },
                c);
        return round_down(cur);
    });
}

// ---- pxh's bilinear map: per cell, a bound valid for every apex in the cell ----

// Cell (i, j): the bilinear patch between texel centres (i, j) and (i + 1, j + 1), wrapped.
struct Cells {
    int W, H;
    std::vector<float> hi, lo;  // max and min of the four corners
    std::vector<double> grad;   // max |grad h| over the cell (uv units): at a corner
    explicit Cells(const HeightField& hf) : W(hf.width), H(hf.height) {
        const size_t n = size_t(W) * size_t(H);
        hi.resize(n);
        lo.resize(n);
        grad.resize(n);
        tbb::parallel_for(0, H, [&](int j) {
            for (int i = 0; i < W; ++i) {
                const float h00 = hf.wrapped(i, j), h10 = hf.wrapped(i + 1, j);
                const float h01 = hf.wrapped(i, j + 1), h11 = hf.wrapped(i + 1, j + 1);
                const size_t k = size_t(j) * W + size_t(i);
                hi[k] = std::max({h00, h10, h01, h11});
                lo[k] = std::min({h00, h10, h01, h11});
                // |grad h|^2 = gx(fy)^2 + gy(fx)^2, gx affine in fy, gy in fx: convex, so its
                // maximum is at a corner, and it separates.
                const double gx =
                    double(W) * std::max(std::abs(double(h10) - h00), std::abs(double(h11) - h01));
                const double gy =
                    double(H) * std::max(std::abs(double(h01) - h00), std::abs(double(h11) - h10));
                grad[k] = std::sqrt(gx * gx + gy * gy);
            }
        });
    }
    size_t at(int64_t i, int64_t j) const {
        return size_t(wrap_index(j, H)) * W + size_t(wrap_index(i, W));
    }
};

// The candidates of cell Q = (iq, jq): for a cell K (an image) outside Q's 3 x 3 block,
// every x in K and q in Q have |x - q| >= dist(Q, K) and h(x) - h(q) <= hi(K) - lo(Q).
struct CellCandidates {
    const Cells& c;
    Metric m;
    int iq, jq;
    double lo_q;
    double* cur;
    void operator()(int i, int j, int sx, int sy) const {
        const int64_t ox = int64_t(i) + int64_t(sx) * m.W - iq;
        const int64_t oy = int64_t(j) + int64_t(sy) * m.H - jq;
        if (std::abs(ox) <= 1 && std::abs(oy) <= 1) return;  // the near block: the gradient
        const double hk = c.hi[size_t(j) * m.W + size_t(i)];
        if (!(hk > lo_q)) return;
        const int64_t gx = std::max<int64_t>(0, std::abs(ox) - 1);
        const int64_t gy = std::max<int64_t>(0, std::abs(oy) - 1);
        *cur = std::min(*cur, m.dist(gx, gy) / (hk - lo_q));
    }
    double bound(int64_t i0, int64_t i1, int64_t j0, int64_t j1, float hmax) const {
        if (!(double(hmax) > lo_q)) return kInf;
        const int64_t gx = std::max<int64_t>(0, Metric::gap(iq, i0, i1) - 1);
        const int64_t gy = std::max<int64_t>(0, Metric::gap(jq, j0, j1) - 1);
        return m.dist(gx, gy) / (double(hmax) - lo_q);
    }
};

// c_Q: min(1, 1 / (max |grad h| over Q's 3 x 3 block of cells: every segment from Q to a
// cell of the block stays in the block), the far candidates).
double cell_ratio(const Cells& c, const MaxPyramid* pyr, int iq, int jq) {
    double g = 0;
    for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) g = std::max(g, c.grad[c.at(iq + di, jq + dj)]);
    double cur = g > 0 ? std::min(1.0, 1.0 / g) : 1.0;
    const Metric m{c.W, c.H};
    const CellCandidates cc{c, m, iq, jq, double(c.lo[c.at(iq, jq)]), &cur};
    if (!pyr) visit_all(m.W, m.H, cc);
    else
        visit(
            *pyr, cur,
            [&](int64_t i0, int64_t i1, int64_t j0, int64_t j1, float hm) {
                return cc.bound(i0, i1, j0, j1, hm);
            },
            cc);
    return cur;
}

std::vector<float> bilinear_map(const HeightField& hf, bool brute) {
    const Cells c(hf);
    const MaxPyramid pyr(brute ? std::vector<float>{0.f} : c.hi, brute ? 1 : c.W, brute ? 1 : c.H);
    std::vector<double> cell(size_t(c.W) * size_t(c.H));
    tbb::parallel_for(0, c.H, [&](int j) {
        for (int i = 0; i < c.W; ++i)
            cell[size_t(j) * c.W + size_t(i)] = cell_ratio(c, brute ? nullptr : &pyr, i, j);
    });
    // Texel (i, j) is a corner of cells (i - 1 .. i, j - 1 .. j): a linear blend of the four
    // texels around any q of cell Q is then at most c_Q.
    return per_texel(c.W, c.H, [&](int i, int j) {
        double r = cell[c.at(i, j)];
        r = std::min({r, cell[c.at(i - 1, j)], cell[c.at(i, j - 1)], cell[c.at(i - 1, j - 1)]});
        return round_down(r * (1 - 0x1p-20));
    });
}

// ---- The book's relaxed cones ----

// Bilinear height (docs/conventions.md section 1) in double.
double bilinear_h(const HeightField& hf, double u, double v) {
    const double x = u * hf.width - 0.5, y = v * hf.height - 0.5;
    const double fx0 = std::floor(x), fy0 = std::floor(y);
    const double fx = x - fx0, fy = y - fy0;
    const int64_t i0 = int64_t(fx0), j0 = int64_t(fy0);
    const double h00 = hf.wrapped(i0, j0), h10 = hf.wrapped(i0 + 1, j0);
    const double h01 = hf.wrapped(i0, j0 + 1), h11 = hf.wrapped(i0 + 1, j0 + 1);
    const double a = h00 + (h10 - h00) * fx, b = h01 + (h11 - h01) * fx;
    return a + (b - a) * fy;
}

// The book's ratio for source (p, hp) and destination (q, hq) (uv, image-shifted). Its march
// stops at the first point outside the surface; `cur` (the ratio found so far; infinity:
// never) lets it stop early once the ratio along the ray, which only grows beyond q, reaches
// cur: the candidate could not lower the minimum then, and a value >= cur is returned.
double book_ratio(const HeightField& hf, double px, double py, double hp, double qx, double qy,
                  double hq, double cur) {
    double vx = qx - px, vy = qy - py, vz = hq - kBookSourceHeight;
    const double k = hq / -vz;  // scale the direction so that it runs from hq down to h = 0
    vx *= k;
    vy *= k;
    vz = -hq;
    const double sx = vx / kBookSearchSteps, sy = vy / kBookSearchSteps, sz = vz / kBookSearchSteps;
    double rx = qx + sx, ry = qy + sy, rz = hq + sz;
    auto ratio = [&] { return rz <= hp ? 1.0 : std::hypot(rx - px, ry - py) / (rz - hp); };
    for (int i = 1; i < kBookSearchSteps; ++i) {
        if (!(bilinear_h(hf, rx, ry) >= rz)) break;
        rx += sx;
        ry += sy;
        rz += sz;
        if (cur < kInf && ratio() >= cur * (1 + 1e-9)) return ratio();
    }
    return ratio();
}

std::vector<float> book_map(const HeightField& hf, bool brute) {
    const Metric m{hf.width, hf.height};
    const MaxPyramid pyr(brute ? std::vector<float>{0.f} : texel_heights(hf), brute ? 1 : m.W,
                         brute ? 1 : m.H);
    return per_texel(m.W, m.H, [&](int ik, int jk) {
        double cur = 1;
        const double hk = hf.at(ik, jk), px = (ik + 0.5) / m.W, py = (jk + 0.5) / m.H;
        auto leaf = [&](int i, int j, int sx, int sy) {
            const double h = hf.at(i, j);
            // Destinations not above the source give 1 (the ray only descends past them);
            // the brute force computes them all the same.
            if (!brute && !(h > hk)) return;
            const double qx = (i + 0.5) / m.W + sx, qy = (j + 0.5) / m.H + sy;
            cur = std::min(cur, book_ratio(hf, px, py, hk, qx, qy, h, brute ? kInf : cur));
        };
        if (brute) {
            visit_all(m.W, m.H, leaf);
        } else {
            // A destination's own ratio bounds its exit point's from below.
            const CentreCandidates c{hf, m, false, ik, jk, hk, &cur};
            visit(
                pyr, cur,
                [&](int64_t i0, int64_t i1, int64_t j0, int64_t j1, float hm) {
                    return c.bound(i0, i1, j0, j1, hm);
                },
                leaf);
        }
        return round_down(cur);
    });
}

}  // namespace

float round_down(double v) {
    float f = float(v);
    if (double(f) > v) f = std::nextafter(f, 0.0f);
    return f;
}

std::vector<float> dummer(const HeightField& hf) { return centre_map(hf, false, false); }
std::vector<float> dummer_brute(const HeightField& hf) { return centre_map(hf, false, true); }
std::vector<float> relaxed_ban(const HeightField& hf) { return centre_map(hf, true, false); }
std::vector<float> relaxed_ban_brute(const HeightField& hf) { return centre_map(hf, true, true); }

std::vector<float> min3x3(const std::vector<float>& r, int W, int H) {
    return per_texel(W, H, [&](int i, int j) {
        float m = r[size_t(j) * W + size_t(i)];
        for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di)
                m = std::min(m,
                             r[size_t(wrap_index(j + dj, H)) * W + size_t(wrap_index(i + di, W))]);
        return m;
    });
}

std::vector<float> bilinear(const HeightField& hf) { return bilinear_map(hf, false); }
std::vector<float> bilinear_brute(const HeightField& hf) { return bilinear_map(hf, true); }
std::vector<float> relaxed_book(const HeightField& hf) { return book_map(hf, false); }
std::vector<float> relaxed_book_brute(const HeightField& hf) { return book_map(hf, true); }

}  // namespace pxh::cone_maps

// Procedural height fields. Every generator is tileable (periodic on [0,1]^2) and
// deterministic for a given seed; values are evaluated at texel centres.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "harness/core/error.h"
#include "heightfields/heightfields.h"

namespace pxh {
namespace {

constexpr double kTau = 6.283185307179586;

// SplitMix64: a small, portable, reproducible generator (std distributions are not portable).
struct Rng {
    uint64_t state;
    explicit Rng(uint64_t seed) : state(seed * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull) {}
    uint64_t next() {
        uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double uniform() { return double(next() >> 11) * (1.0 / 9007199254740992.0); }
};

template <class F>
void fill(HeightField& out, F f) {
    for (int j = 0; j < out.height; ++j)
        for (int i = 0; i < out.width; ++i)
            out.at(i, j) =
                float(std::clamp(f((i + 0.5) / out.width, (j + 0.5) / out.height), 0.0, 1.0));
}

double wrapped_delta(double a, double b) {
    double d = a - b;
    return d - std::round(d);
}

void gen_flat(HeightField& out, const ParamValues& p) {
    const double level = p.get("level");
    fill(out, [&](double, double) { return level; });
}

void gen_sine(HeightField& out, const ParamValues& p) {
    const double ku = p.get("periods_u"), kv = p.get("periods_v");
    fill(out, [&](double u, double v) {
        return 0.5 + 0.25 * std::sin(kTau * ku * u) + 0.25 * std::sin(kTau * kv * v);
    });
}

void gen_bumps(HeightField& out, const ParamValues& p) {
    Rng rng(uint64_t(p.get("seed")));
    const int n = p.get_int("count");
    const double r = p.get("radius");
    std::vector<double> cu(n), cv(n), amp(n);
    for (int k = 0; k < n; ++k) {
        cu[k] = rng.uniform();
        cv[k] = rng.uniform();
        amp[k] = 0.6 + 0.4 * rng.uniform();
    }
    fill(out, [&](double u, double v) {
        double h = 0;
        for (int k = 0; k < n; ++k) {
            const double du = wrapped_delta(u, cu[k]), dv = wrapped_delta(v, cv[k]);
            const double q = 1 - (du * du + dv * dv) / (r * r);
            if (q > 0) h = std::max(h, amp[k] * std::sqrt(q));
        }
        return h;
    });
}

void gen_bricks(HeightField& out, const ParamValues& p) {
    const int rows = p.get_int("rows"), cols = p.get_int("cols");
    const double mortar = p.get("mortar"), bevel = p.get("bevel");
    Rng rng(uint64_t(p.get("seed")));
    std::vector<double> top(size_t(rows) * cols);
    for (auto& t : top) t = 0.85 + 0.15 * rng.uniform();
    fill(out, [&](double u, double v) {
        const double y = v * rows;
        const int row = int(std::floor(y));
        const double x = u * cols + (row % 2 ? 0.5 : 0.0);
        const int col = int(std::floor(x));
        // Distance to the nearest joint, in units of brick height (1 / rows).
        const double fy = y - row, fx = x - col;
        const double dist = std::min({fy, 1 - fy, (fx < 0.5 ? fx : 1 - fx) * rows / cols});
        const double t = std::clamp((dist - 0.5 * mortar) / std::max(bevel, 1e-9), 0.0, 1.0);
        return t * top[size_t(row % rows) * cols + size_t(col % cols)];
    });
}

void gen_pyramids(HeightField& out, const ParamValues& p) {
    const int n = p.get_int("count");
    fill(out, [&](double u, double v) {
        const double fx = u * n - std::floor(u * n), fy = v * n - std::floor(v * n);
        return 1 - 2 * std::max(std::abs(fx - 0.5), std::abs(fy - 0.5));
    });
}

void gen_terraces(HeightField& out, const ParamValues& p) {
    const int steps = p.get_int("steps");
    const double k = p.get("periods");
    fill(out, [&](double u, double v) {
        const double base = 0.5 + 0.25 * std::sin(kTau * k * u) + 0.25 * std::cos(kTau * k * v);
        return std::min(std::floor(base * steps), double(steps - 1)) / (steps - 1);
    });
}

// Periodic value noise: lattice of period `freq`, quintic interpolation.
// fbm keeps one value lattice of (base_freq 2^o)^2 doubles per octave o: the finest must stay
// within the image side limit (4096^2 doubles = 128 MiB), or a 12-octave sweep at base_freq 256
// asks for terabytes.
constexpr long long kMaxLatticeSide = 4096;
std::string fbm_problem(const ParamValues& p) {
    const long long finest = (long long)p.get_int("base_freq") << (p.get_int("octaves") - 1);
    if (finest <= kMaxLatticeSide) return "";
    return "its finest octave has a " + std::to_string(finest) +
           "^2 lattice (base_freq * 2^(octaves-1)), over the limit of " +
           std::to_string(kMaxLatticeSide) + "; lower base_freq or octaves";
}

struct ValueNoise {
    int freq;
    std::vector<double> lattice;
    ValueNoise(int f, Rng& rng) : freq(f), lattice(size_t(f) * f) {
        for (auto& x : lattice) x = rng.uniform();
    }
    double operator()(double u, double v) const {
        const double x = u * freq, y = v * freq;
        const int64_t i = int64_t(std::floor(x)), j = int64_t(std::floor(y));
        auto fade = [](double t) { return t * t * t * (t * (t * 6 - 15) + 10); };
        const double tx = fade(x - i), ty = fade(y - j);
        auto L = [&](int64_t a, int64_t b) {
            return lattice[size_t(wrap_index(b, freq)) * freq + size_t(wrap_index(a, freq))];
        };
        const double a = L(i, j) + (L(i + 1, j) - L(i, j)) * tx;
        const double b = L(i, j + 1) + (L(i + 1, j + 1) - L(i, j + 1)) * tx;
        return a + (b - a) * ty;
    }
};

void gen_fbm(HeightField& out, const ParamValues& p) {
    Rng rng(uint64_t(p.get("seed")));
    const int octaves = p.get_int("octaves");
    const double gain = p.get("gain");
    std::vector<ValueNoise> layers;
    for (int o = 0; o < octaves; ++o) layers.emplace_back(p.get_int("base_freq") << o, rng);
    std::vector<double> raw(out.texels.size());
    for (int j = 0; j < out.height; ++j)
        for (int i = 0; i < out.width; ++i) {
            const double u = (i + 0.5) / out.width, v = (j + 0.5) / out.height;
            double h = 0, a = 1;
            for (const auto& n : layers) {
                h += a * n(u, v);
                a *= gain;
            }
            raw[size_t(j) * out.width + i] = h;
        }
    const auto [lo, hi] = std::minmax_element(raw.begin(), raw.end());
    const double span = *hi - *lo;
    for (size_t k = 0; k < raw.size(); ++k)
        out.texels[k] = span > 0 ? float((raw[k] - *lo) / span) : 0.5f;
}

void gen_step(HeightField& out, const ParamValues& p) {
    const double lo = p.get("low"), hi = p.get("high");
    for (int j = 0; j < out.height; ++j)
        for (int i = 0; i < out.width; ++i) out.at(i, j) = float(2 * i < out.width ? hi : lo);
}

void gen_spikes(HeightField& out, const ParamValues& p) {
    Rng rng(uint64_t(p.get("seed")));
    const double base = p.get("base");
    std::fill(out.texels.begin(), out.texels.end(), float(base));
    const int n = p.get_int("count");
    for (int k = 0; k < n; ++k) {
        const int i = int(rng.next() % uint64_t(out.width));
        const int j = int(rng.next() % uint64_t(out.height));
        out.at(i, j) = 1.0f;  // one texel wide: narrower than a layer step at grazing views
    }
}

ParamSpec seed_param() { return {"seed", 1.0, 0, 4294967295.0, true, "random seed"}; }

}  // namespace

const std::vector<GeneratorInfo>& all_generators() {
    static const std::vector<GeneratorInfo> gens = {
        {"flat", "constant height", {{"level", 0.5, 0, 1, false, "the height"}}, gen_flat},
        {"sine",
         "smooth waves 0.5 + 0.25 sin(2 pi ku u) + 0.25 sin(2 pi kv v)",
         {{"periods_u", 3.0, 0, 1024, true, "periods across the tile in u"},
          {"periods_v", 2.0, 0, 1024, true, "periods across the tile in v"}},
         gen_sine},
        {"bumps",
         "round domes (hemispheres) at random places, wrapped",
         {{"count", 12.0, 1, 10000, true, "number of domes"},
          {"radius", 0.12, 1e-4, 0.5, false, "dome radius in uv"},
          seed_param()},
         gen_bumps},
        {"bricks",
         "running-bond bricks: plateaus, mortar grooves, near-vertical walls",
         {{"rows", 4.0, 1, 256, true, "brick rows per tile"},
          {"cols", 2.0, 1, 256, true, "bricks per row"},
          {"mortar", 0.1, 0, 0.9, false, "mortar width, fraction of a brick's height"},
          {"bevel", 0.01, 0, 0.5, false, "wall run, fraction of a brick's height"},
          seed_param()},
         gen_bricks},
        {"pyramids",
         "square pyramids: planar slopes meeting at ridges",
         {{"count", 4.0, 1, 1024, true, "pyramids per side"}},
         gen_pyramids},
        {"terraces",
         "smooth waves quantised into flat steps with vertical risers",
         {{"steps", 5.0, 2, 256, true, "number of levels"},
          {"periods", 2.0, 1, 256, true, "wave periods across the tile"}},
         gen_terraces},
        {"fbm",
         "fractal value noise (rough, multi-scale), normalised to [0,1]",
         {{"octaves", 6.0, 1, 12, true, "noise octaves"},
          {"base_freq", 4.0, 1, 256, true, "lattice cells per tile of the first octave"},
          {"gain", 0.5, 0, 1, false, "amplitude factor per octave"},
          seed_param()},
         gen_fbm,
         fbm_problem},
        {"step",
         "a cliff: the left half of the tile high, the right half low (two texel-wide "
         "walls, one at u = 0.5 and one at the wrap)",
         {{"low", 0.0, 0, 1, false, "height of the right half"},
          {"high", 1.0, 0, 1, false, "height of the left half"}},
         gen_step},
        {"spikes",
         "one-texel spikes of height 1 on a flat base",
         {{"count", 24.0, 1, 1e6, true, "number of spikes"},
          {"base", 0.0, 0, 1, false, "height of the base"},
          seed_param()},
         gen_spikes},
    };
    return gens;
}

const GeneratorInfo* find_generator(const std::string& name) {
    for (const auto& g : all_generators())
        if (g.name == name) return &g;
    return nullptr;
}

HeightField generate_heightfield(const GeneratorInfo& g, int width, int height,
                                 const ParamValues& p) {
    HeightField hf(width, height, g.name);
    g.generate(hf, p);
    return hf;
}

}  // namespace pxh

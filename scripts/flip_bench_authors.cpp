// The authors' LDR-FLIP timed on pxh's benchmark pair, for scripts/flip_bench.sh: pxh's own
// driver, compiled by that script against the FLIP.h of a checkout of NVlabs/flip that the user
// names (none of the authors' code is in pxh). It loads the pair as the authors' tool loads an
// 8-bit PNG (bytes / 255, then sRGBToLinearRGB) and times FLIP::evaluate (LDR), with the same
// warm-up, repeats and median as bench/flip_bench.cpp. Without OpenMP it runs on one thread.
//   flip_bench_authors [--repeats N] [--ppd P]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "FLIP.h"
#include "flip_pairs.h"

namespace {

double flip_mean(const flip_pairs::Pair& p, float ppd) {
    FLIP::image<FLIP::color3> r(p.w, p.h), t(p.w, p.h);
    for (int y = 0; y < p.h; ++y)
        for (int x = 0; x < p.w; ++x) {
            const size_t i = 3 * (size_t(y) * size_t(p.w) + size_t(x));
            r.set(x, y, FLIP::color3(&p.reference[i]));
            t.set(x, y, FLIP::color3(&p.test[i]));
        }
    r.sRGBToLinearRGB();
    t.sRGBToLinearRGB();
    FLIP::Parameters par;
    par.PPD = ppd;
    FLIP::image<float> e(p.w, p.h, 0.0f);
    FLIP::evaluate(r, t, false, par, e);
    double sum = 0;
    for (int y = 0; y < p.h; ++y)
        for (int x = 0; x < p.w; ++x) sum += e.get(x, y);
    return sum / (double(p.w) * double(p.h));
}

}  // namespace

int main(int argc, char** argv) {
    int repeats = 9;
    float ppd = 67.02f;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string a = argv[i];
        if (a == "--repeats") repeats = std::max(1, std::atoi(argv[i + 1]));
        else if (a == "--ppd") ppd = float(std::atof(argv[i + 1]));
    }
    const auto p = flip_pairs::bench512();
    double mean = flip_mean(p, ppd);  // warm-up
    std::vector<double> t;
    for (int k = 0; k < repeats; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        mean = flip_mean(p, ppd);
        t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(t.begin(), t.end());
    std::printf("authors flip %dx%d: median %.4f s (min %.4f s, %d repeats, 1 thread), mean %.7f\n",
                p.w, p.h, t[t.size() / 2], t.front(), repeats, mean);
    return 0;
}

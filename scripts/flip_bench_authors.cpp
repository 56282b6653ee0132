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

FLIP::image<FLIP::color3> load(const std::vector<uint8_t>& bytes, int w, int h) {
    FLIP::image<FLIP::color3> im(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            im.set(x, y, FLIP::color3(&bytes[3 * (size_t(y) * size_t(w) + size_t(x))]));
    return im;
}

// The timed work: the sRGB decoding and FLIP::evaluate (LDR), as the tool's "Evaluation time"
// plus its decoding; the bytes' loading and the mean are left out (in pxh's time they are in).
double flip_mean(const FLIP::image<FLIP::color3>& ref, const FLIP::image<FLIP::color3>& test,
                 float ppd, bool timed_only, double* seconds) {
    const auto t0 = std::chrono::steady_clock::now();
    FLIP::image<FLIP::color3> r(ref.getWidth(), ref.getHeight()),
        t(ref.getWidth(), ref.getHeight());
    r.copy(const_cast<FLIP::image<FLIP::color3>&>(ref));
    t.copy(const_cast<FLIP::image<FLIP::color3>&>(test));
    r.sRGBToLinearRGB();
    t.sRGBToLinearRGB();
    FLIP::Parameters par;
    par.PPD = ppd;
    FLIP::image<float> e(r.getWidth(), r.getHeight(), 0.0f);
    FLIP::evaluate(r, t, false, par, e);
    *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (timed_only) return 0;
    double sum = 0;
    for (int y = 0; y < e.getHeight(); ++y)
        for (int x = 0; x < e.getWidth(); ++x) sum += e.get(x, y);
    return sum / (double(e.getWidth()) * double(e.getHeight()));
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
    const auto ref = load(p.reference, p.w, p.h), test = load(p.test, p.w, p.h);
    double s = 0;
    const double mean = flip_mean(ref, test, ppd, false, &s);  // warm-up, and the mean
    std::vector<double> t;
    for (int k = 0; k < repeats; ++k) {
        flip_mean(ref, test, ppd, true, &s);
        t.push_back(s);
    }
    std::sort(t.begin(), t.end());
    std::printf("authors flip %dx%d: median %.4f s (min %.4f s, %d repeats, 1 thread), mean %.7f\n",
                p.w, p.h, t[t.size() / 2], t.front(), repeats, mean);
    return 0;
}

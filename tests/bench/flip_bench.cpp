// pxh_flip_bench: the time of pxh's LDR-FLIP (harness/metrics/flip.h) on the 512 x 512 pair of
// tests/metrics/flip_pairs.h (bench512), on one thread by default: the median of the repeats,
// after one untimed warm-up. scripts/flip_bench.sh runs it beside the authors' implementation
// on the same pair (issue 63: at most 2x their time).
//   pxh_flip_bench [--repeats N] [--threads T] [--ppd P]
// Prints one line: pxh flip 512x512: median S s (min S s, N repeats, T threads), mean M.
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "harness/metrics/flip.h"
#include "tests/metrics/flip_pairs.h"

int main(int argc, char** argv) {
    int repeats = 9, threads = 1;
    double ppd = pxh::kFlipDefaultPpd;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool has_value = i + 1 < argc;
        if (a == "--repeats" && has_value) repeats = std::atoi(argv[++i]);
        else if (a == "--threads" && has_value) threads = std::atoi(argv[++i]);
        else if (a == "--ppd" && has_value) ppd = std::atof(argv[++i]);
        else {
            std::fprintf(stderr, "usage: pxh_flip_bench [--repeats N] [--threads T] [--ppd P]\n");
            return 2;
        }
    }
    if (repeats < 1 || threads < 1 || !(ppd > 0)) {
        std::fprintf(stderr, "pxh_flip_bench: --repeats and --threads >= 1, --ppd > 0\n");
        return 2;
    }
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(threads));
    const auto p = flip_pairs::bench512();
    double mean = pxh::flip_ldr(p.reference, p.test, p.w, p.h, ppd).mean;  // warm-up
    std::vector<double> t;
    for (int k = 0; k < repeats; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        mean = pxh::flip_ldr(p.reference, p.test, p.w, p.h, ppd).mean;
        t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(t.begin(), t.end());
    std::printf("pxh flip %dx%d: median %.4f s (min %.4f s, %d repeats, %d threads), mean %.7f\n",
                p.w, p.h, t[t.size() / 2], t.front(), repeats, threads, mean);
    return 0;
}

// Fuzz target: `pxh compare BASE NEW`'s inputs (pxh::run_compare): the input is BASE's
// results.csv, then a line "===", then NEW's (no such line: the same file as both). Each pair
// is compared twice: as a gate (--fail-on on errors and on a time, whose verdict reads the
// _repeats cells) in Markdown, and with --common and theta bands of its own. Rows matched
// across field sizes or ground truths, duplicate keys, malformed numbers or repeats are refused
// (InputError): expected.
#include <exception>
#include <filesystem>
#include <sstream>
#include <string>

#include "fuzz/fuzz_target.h"
#include "harness/report/compare.h"

PXH_FUZZ_TARGET(compare) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const std::string sep = "\n===\n";
    const size_t at = text.find(sep);
    const std::string base = at == std::string::npos ? text : text.substr(0, at + 1);
    const std::string now = at == std::string::npos ? text : text.substr(at + sep.size());
    namespace fs = std::filesystem;
    const fs::path root = fs::path(pxh::fuzz::scratch_dir()) / "compare";
    fs::create_directories(root / "base");
    fs::create_directories(root / "new");
    pxh::fuzz::write_scratch("compare/base/results.csv",
                             reinterpret_cast<const uint8_t*>(base.data()), base.size());
    pxh::fuzz::write_scratch("compare/new/results.csv",
                             reinterpret_cast<const uint8_t*>(now.data()), now.size());
    for (int pass = 0; pass < 2; ++pass) {
        std::ostringstream out;
        try {
            pxh::CompareOptions opt;
            if (pass == 0) {
                opt.markdown = true;
                opt.fail_on = pxh::parse_fail_on(
                    "err_p95=+5%,err_mean=+0,time=+10%,"
                    "gpu_ms_per_frame=+10%,nonfinite=+0");
            } else {
                opt.common = true;
                opt.band_edges = {0, 45, 90};
            }
            (void)pxh::run_compare((root / "base").string(), (root / "new").string(), opt, out);
        } catch (const std::exception&) {
            // Malformed or incomparable results are refused (InputError): expected.
        }
    }
    return 0;
}

// Fuzz target: thresholds files (TOML [[limit]] tables) through pxh::run_check, as
// `pxh check DIR --thresholds FILE` reads them, against a fixed tiny results folder written
// once by pxh's own results writer (so its columns follow the current results.csv).
#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "fuzz/fuzz_target.h"
#include "harness/report/report.h"
#include "harness/results/results.h"

namespace {

// Four rows: two methods, CPU and GLSL, three angles, one failed row, one NaN metric, so that
// filters, theta ranges, failed rows and non-finite values all have something to match.
std::string results_dir() {
    static const std::string dir = [] {
        const std::filesystem::path d = std::filesystem::path(pxh::fuzz::scratch_dir()) / "results";
        std::filesystem::create_directories(d);
        std::vector<pxh::ResultRow> rows(4);
        const char* methods[] = {"pom", "pom", "parallax", "relief"};
        const double thetas[] = {0, 60, 80, 45};
        for (size_t k = 0; k < rows.size(); ++k) {
            pxh::ResultRow& r = rows[k];
            r.set_text("method", methods[k]);
            r.set_text("params", k < 2 ? "layers=32" : "");
            r.set_text("heightfield", "bricks");
            r.set_text("backend", k == 1 ? "glsl" : "cpu");
            r.set_text("precision", "float");
            r.set_text("texture_format", k == 1 ? "r32f" : "");
            r.set("scale", 0.05);
            r.set("bias", 1.0);
            r.set("theta_deg", thetas[k]);
            r.set("phi_deg", 0);
            r.set("samples", 16);
            r.set("width", 64);
            r.set("height", 64);
            r.set_text("ground_truth", "exact");
            r.set("fetches_mean", 10.0 + double(k));
            r.set("fetches_max", 33);
            r.set("time", k == 2 ? NAN : 40.0);
            r.set_text("time_unit", k == 2 ? "" : "ns/sample");
        }
        rows[3].fail("shader did not compile");
        std::ofstream(d / "results.csv", std::ios::binary) << pxh::results_csv(rows);
        return d.string();
    }();
    return dir;
}

}  // namespace

PXH_FUZZ_TARGET(thresholds) {
    pxh::fuzz::silence_stdout();  // run_check prints its table
    const std::string dir = results_dir();
    const std::string file = pxh::fuzz::write_scratch("thresholds.toml", data, size);
    try {
        (void)pxh::run_check(dir, file);
    } catch (const std::exception&) {
        // A malformed thresholds file is refused (InputError): expected.
    }
    return 0;
}

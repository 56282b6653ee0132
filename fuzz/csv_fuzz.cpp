// Fuzz target: results.csv through pxh::read_csv (RFC 4180 quoting), then every accessor on
// every cell, then `pxh report DIR --no-plots` (pxh::run_report) on the same file: the report is
// the consumer that turns those cells into numbers, bands, budgets and Pareto fronts.
#include <exception>
#include <filesystem>
#include <string>

#include "fuzz/fuzz_target.h"
#include "harness/report/report.h"
#include "harness/results/csv_table.h"

PXH_FUZZ_TARGET(csv) {
    pxh::fuzz::silence_stdout();  // the report prints where it wrote
    const std::filesystem::path dir = std::filesystem::path(pxh::fuzz::scratch_dir()) / "csv";
    std::filesystem::create_directories(dir);
    const std::string path = pxh::fuzz::write_scratch("csv/results.csv", data, size);
    try {
        const pxh::CsvTable t = pxh::read_csv(path);
        volatile double sink = 0;
        for (size_t r = 0; r < t.rows.size(); ++r)
            for (const auto& c : t.columns)
                sink = sink + t.number(r, c) + double(t.get(r, c).size());
        (void)t.index("no such column");
        (void)pxh::run_report(dir.string(), /*plots=*/false);
    } catch (const std::exception&) {
        // Malformed or foreign CSV is refused (InputError): expected.
    }
    return 0;
}

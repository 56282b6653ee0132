// pxh: measures how wrong parallax-mapping methods are against exact ground truth.
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>

#include "harness/error.h"
#include "harness/experiment.h"
#include "harness/provenance.h"
#include "harness/runner.h"
#include "heightfields/heightfields.h"

namespace fs = std::filesystem;
using namespace pxh;

namespace {

void list_methods() {
    for (const auto& m : all_methods()) {
        std::cout << m.name << "  -- " << m.summary << "\n    source: " << m.citation << "\n";
        if (m.exact_on_flat) std::cout << "    exact on flat fields\n";
        for (const auto& p : m.params) std::cout << "    " << describe_param(p) << "\n";
    }
}

void list_heightfields() {
    for (const auto& g : all_generators()) {
        std::cout << g.name << "  -- " << g.summary << "\n";
        for (const auto& p : g.params) std::cout << "    " << describe_param(p) << "\n";
    }
    std::cout << "(any image file: file = \"path\" in a [[heightfields]] entry; PNG, TIFF, EXR, "
                 "PFM, ... through OpenImageIO)\n";
}

// Per method and backend: mean error over all rows, and the worst p95.
void print_summary(const std::vector<ResultRow>& rows) {
    struct Acc {
        double sum_mean = 0, worst_p95 = 0, fetches = 0, ns = 0, shadow = 0;
        int n = 0, failed = 0;
    };
    bool any_shadow = false;
    std::vector<std::string> order;
    std::map<std::string, Acc> acc;
    for (const auto& r : rows) {
        const std::string key = r.method + (r.params.empty() ? "" : " " + r.params) + " [" +
                                r.backend + "/" + r.precision + "]";
        if (!acc.count(key)) order.push_back(key);
        Acc& a = acc[key];
        if (r.status != "ok") { ++a.failed; continue; }
        a.sum_mean += r.err.mean;
        a.worst_p95 = std::max(a.worst_p95, r.err.p95);
        a.fetches += r.fetches_mean;
        a.ns += std::isnan(r.ns_per_sample) ? 0 : r.ns_per_sample;
        if (!std::isnan(r.shadow_err)) { a.shadow += r.shadow_err; any_shadow = true; }
        ++a.n;
    }
    std::cout << std::left << std::setw(44) << "method" << std::right << std::setw(12)
              << "mean err" << std::setw(12) << "worst p95" << std::setw(10) << "fetches"
              << std::setw(10) << "ns/smp" << std::setw(8) << "failed"
              << (any_shadow ? "  shadow err" : "") << "\n";
    std::cout << std::fixed;
    for (const auto& k : order) {
        const Acc& a = acc[k];
        const double n = std::max(a.n, 1);
        std::cout << std::left << std::setw(44) << k << std::right << std::setprecision(3)
                  << std::setw(12) << a.sum_mean / n << std::setw(12) << a.worst_p95
                  << std::setprecision(1) << std::setw(10) << a.fetches / n << std::setw(10)
                  << a.ns / n << std::setw(8) << a.failed;
        if (any_shadow) std::cout << std::setprecision(3) << std::setw(12) << a.shadow / n;
        std::cout << "\n";
    }
    std::cout << "(texel error: distance in texels between the sampled and the truly visible "
                 "point, mean over rows; worst p95: the largest per-row 95th percentile;\n"
                 " ns/smp: single-thread CPU time per sample; shadow err: fraction of samples "
                 "whose hard shadow is wrong)\n";
}

int cmd_run(const std::string& file, std::string out_dir, int threads,
            const std::vector<std::string>& backends, bool quiet) {
    const Experiment ex = load_experiment(file);
    if (out_dir.empty()) out_dir = "results/runs/" + ex.name + "-" + utc_timestamp("%Y%m%d-%H%M%S");
    const int nthreads = threads > 0 ? threads : int(tbb::info::default_concurrency());
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(nthreads));

    // Write into a temporary folder, renamed into place only when complete.
    const fs::path final_dir = fs::path(out_dir);
    const fs::path tmp_dir = final_dir.string() + ".partial-" + std::to_string(getpid());
    fs::create_directories(tmp_dir);
    struct Cleanup {
        fs::path p; bool armed = true;
        ~Cleanup() { if (armed) { std::error_code ec; fs::remove_all(p, ec); } }
    } cleanup{tmp_dir};

    const bool tty = isatty(STDERR_FILENO);
    RunOptions opt;
    opt.backends = backends;
    if (!quiet)
        opt.progress = [tty](const std::string& line) {
            if (tty) std::cerr << "\r\033[K" << line << std::flush;
            else std::cerr << line << "\n";
        };
    const auto t0 = std::chrono::steady_clock::now();
    const auto rows = run_experiment(ex, opt);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!quiet && tty) std::cerr << "\r\033[K";

    write_results_csv(rows, (tmp_dir / "results.csv").string());
    nlohmann::json run = provenance(nthreads);
    run["experiment_file"] = ex.path;
    run["experiment"] = ex.text;
    run["experiment_name"] = ex.name;
    run["rows"] = rows.size();
    size_t failed = 0;
    for (const auto& r : rows) failed += r.status != "ok";
    run["failed_rows"] = failed;
    run["seconds"] = secs;
    {
        std::ofstream f(tmp_dir / "run.json");
        f << run.dump(2) << "\n";
        if (!f) throw InputError((tmp_dir / "run.json").string(), "write failed");
    }
    std::error_code ec;
    if (fs::exists(final_dir)) fs::remove_all(final_dir, ec);
    fs::create_directories(final_dir.parent_path().empty() ? "." : final_dir.parent_path());
    fs::rename(tmp_dir, final_dir);
    cleanup.armed = false;

    if (!quiet) print_summary(rows);
    std::cout << rows.size() << " rows (" << failed << " failed) in " << std::setprecision(1)
              << std::fixed << secs << " s -> " << final_dir.string() << "\n";
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"pxh: measures how far parallax-mapping methods are from the true displaced "
                 "surface, and what they cost"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "pxh 0.1.0");

    auto* run = app.add_subcommand("run", "run an experiment file, write results.csv and run.json");
    std::string file, out_dir;
    int threads = 0;
    bool quiet = false;
    std::vector<std::string> backends;
    run->add_option("experiment", file, "experiment file (TOML)")->required();
    run->add_option("--out", out_dir, "results folder (default results/runs/NAME-DATE)");
    run->add_option("--threads", threads, "worker threads (default: all cores)")
        ->check(CLI::Range(1, 1024));
    run->add_option("--backend", backends, "backends to run, overriding the file (cpu)");
    run->add_flag("--quiet", quiet, "no progress or summary");

    auto* list = app.add_subcommand("list", "list registered methods or height-field generators");
    std::string what;
    list->add_option("what", what, "methods | heightfields")
        ->required()
        ->check(CLI::IsMember({"methods", "heightfields"}));

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    try {
        if (*run) return cmd_run(file, out_dir, threads, backends, quiet);
        if (*list) {
            if (what == "methods") list_methods(); else list_heightfields();
            return 0;
        }
    } catch (const InputError& e) {
        std::cerr << "pxh: error: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "pxh: internal error: " << e.what() << "\n";
        return 1;
    }
    return 0;
}

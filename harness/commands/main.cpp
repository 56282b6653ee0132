// pxh: measures how wrong parallax-mapping methods are against exact ground truth.
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cctype>
#include <cmath>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include "harness/commands/bench.h"
#include "harness/core/error.h"
#include "harness/results/error_maps.h"
#include "harness/experiment/experiment.h"
#include "harness/core/params.h"
#include "harness/results/provenance.h"
#include "harness/report/report.h"
#include "harness/results/run_folder.h"
#include "harness/core/sha256.h"
#include "harness/run/runner.h"
#include "heightfields/heightfields.h"
#include "heightfields/scanned.h"

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
    for (const auto& s : list_scans())
        std::cout << "scan:" << s.name << "  -- " << s.description << "\n    measured, " << s.width
                  << " x " << s.height << (s.periodic ? "" : ", mirrored to " + std::to_string(2 * s.width) +
                                                             " x " + std::to_string(2 * s.height) + " when loaded")
                  << "; use scan = \"" << s.name << "\" (provenance: heightfields/scanned/" << s.name
                  << ".json)\n";
    std::cout << "(any image file: file = \"path\" in a [[heightfields]] entry; PNG, TIFF, EXR, "
                 "PFM, ... through OpenImageIO)\n";
}

// Per method, parameters and backend: mean error over all rows, the worst p95, cost.
void print_summary(const std::vector<ResultRow>& rows) {
    struct Acc {
        double sum_mean = 0, worst_p95 = 0, fetches = 0, ns = 0, ms = 0, shadow = 0;
        int n = 0, n_ns = 0, n_ms = 0, n_shadow = 0, failed = 0;
    };
    std::vector<std::string> order;
    std::map<std::string, Acc> acc;
    for (const auto& r : rows) {
        const std::string key = r.method + (r.params.empty() ? "" : " " + r.params) + " [" +
                                r.backend + "/" +
                                (r.texture_format.empty() ? r.precision : r.texture_format) + "]";
        if (!acc.count(key)) order.push_back(key);
        Acc& a = acc[key];
        if (r.status != "ok") { ++a.failed; continue; }
        a.sum_mean += r.err.mean;
        a.worst_p95 = std::max(a.worst_p95, r.err.p95);
        a.fetches += r.fetches_mean;
        ++a.n;
        if (!std::isnan(r.ns_per_sample)) { a.ns += r.ns_per_sample; ++a.n_ns; }
        if (!std::isnan(r.ms_per_frame)) { a.ms += r.ms_per_frame; ++a.n_ms; }
        if (!std::isnan(r.shadow_err)) { a.shadow += r.shadow_err; ++a.n_shadow; }
    }
    auto cell = [](double sum, int n, int prec) {
        std::ostringstream os;
        if (n == 0) os << "-"; else os << std::fixed << std::setprecision(prec) << sum / n;
        return os.str();
    };
    std::cout << std::left << std::setw(46) << "method [backend/precision or texture]"
              << std::right << std::setw(10) << "mean err" << std::setw(11) << "worst p95"
              << std::setw(9) << "fetches" << std::setw(9) << "ns/smp" << std::setw(10)
              << "ms/frame" << std::setw(8) << "shadow" << std::setw(8) << "failed" << "\n";
    for (const auto& k : order) {
        const Acc& a = acc[k];
        std::cout << std::left << std::setw(46) << k << std::right << std::setw(10)
                  << cell(a.sum_mean, a.n, 3) << std::setw(11) << cell(a.worst_p95, a.n ? 1 : 0, 3)
                  << std::setw(9) << cell(a.fetches, a.n, 1) << std::setw(9)
                  << cell(a.ns, a.n_ns, 1) << std::setw(10) << cell(a.ms, a.n_ms, 2)
                  << std::setw(8) << cell(a.shadow, a.n_shadow, 3) << std::setw(8) << a.failed
                  << "\n";
    }
    std::cout << "mean err: texel distance between the sampled and the truly visible point, "
                 "averaged over rows; worst p95: largest per-row 95th percentile;\n"
                 "ns/smp: single-thread CPU time per sample; ms/frame: GLSL frame time "
                 "(llvmpipe); shadow: fraction of samples with a wrong hard shadow\n";
}

std::string g_command_line;  // as typed (run.json records it)

struct RunArgs {
    std::string file, out_dir, shader_dir;
    int threads = 0;
    std::vector<std::string> backends;
    bool quiet = false, maps = false, force = false;
    size_t max_rows = kDefaultMaxRows;
    std::string max_memory;  // e.g. "8G"; empty = kDefaultMaxMemoryBytes
};

// "123", "512M", "8G", "1.5T" (binary units) -> bytes.
size_t parse_bytes(const std::string& text) {
    size_t used = 0;
    double v = 0;
    try {
        v = std::stod(text, &used);
    } catch (...) {
        used = 0;
    }
    std::string unit = text.substr(used);
    for (auto& c : unit) c = char(std::toupper((unsigned char)c));
    if (!unit.empty() && unit.back() == 'B') unit.pop_back();
    if (unit.size() == 2 && unit[1] == 'I') unit.pop_back();  // GiB, MiB
    const std::map<std::string, double> mult = {{"", 1.0}, {"K", 1024.0}, {"M", 1048576.0},
                                                {"G", 1073741824.0}, {"T", 1099511627776.0}};
    if (used == 0 || !mult.count(unit) || !(v > 0) || !std::isfinite(v * mult.at(unit)) ||
        v * mult.at(unit) > 1e18)
        throw InputError("--max-memory", "'" + text + "' is not a size (e.g. 512M, 8G)");
    return size_t(v * mult.at(unit));
}

// run.json's record of the inputs: every image a height field was read from, with its sha256.
nlohmann::json input_records(const Experiment& ex) {
    nlohmann::json inputs = nlohmann::json::array();
    std::set<std::string> seen;
    inputs.push_back({{"experiment", ex.path}, {"sha256", sha256_hex(ex.text)}});
    for (const auto& h : ex.heightfields)  // hashed once, when the experiment was read
        if (!h.source_path.empty() && seen.insert(h.source_path).second)
            inputs.push_back({{"heightfield", h.name}, {"path", h.source_path}, {"sha256", h.source_sha256}});
    return inputs;
}

int cmd_run(const RunArgs& a) {
    Experiment ex = load_experiment(a.file);
    ex.maps = ex.maps || a.maps;
    // The run's size, estimated before any work: a small file must not take the machine.
    const size_t max_memory = a.max_memory.empty() ? kDefaultMaxMemoryBytes : parse_bytes(a.max_memory);
    const RunEstimate est = estimate_run(ex, a.backends);
    if (est.rows > a.max_rows)
        throw InputError(ex.path, "the run would write " + std::to_string(est.rows) +
                                      " rows, over the limit of " + std::to_string(a.max_rows) +
                                      " (raise it with --max-rows N)");
    if (est.peak_bytes > max_memory)
        throw InputError(ex.path, "the run would need about " + format_bytes(est.peak_bytes) +
                                      " of memory, over the limit of " + format_bytes(max_memory) + " (" +
                                      est.detail + "; raise it with --max-memory SIZE)");
    const std::string out_dir =
        a.out_dir.empty() ? "results/runs/" + ex.name + "-" + utc_timestamp("%Y%m%d-%H%M%S") : a.out_dir;
    const int nthreads = a.threads > 0 ? a.threads : int(tbb::info::default_concurrency());
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(nthreads));
    // llvmpipe's rasteriser threads follow --threads unless LP_NUM_THREADS is set already.
    setenv("LP_NUM_THREADS", std::to_string(nthreads).c_str(), 0);

    // Written into DIR.partial-PID, renamed into place only when complete (before any worker
    // thread exists: the folder's signal clean-up needs every thread to block the signals).
    RunFolder folder(out_dir, a.force);
    const fs::path tmp_dir = folder.partial();

    const bool tty = isatty(STDERR_FILENO);
    RunOptions opt;
    opt.backends = a.backends;
    opt.shader_dir = a.shader_dir;
    if (ex.maps)
        opt.on_view = [&](std::vector<ResultRow>& rows,
                          const std::vector<std::vector<Vec2d>>& errors, size_t first) {
            for (size_t i = 0; i < rows.size(); ++i) {
                if (errors[i].empty()) continue;
                const ResultRow& r = rows[i];
                char stem[512];
                std::snprintf(stem, sizeof stem, "%05zu_%s_%s_t%g_p%g_%s", first + i,
                              r.method.c_str(), r.heightfield.c_str(), r.theta_deg, r.phi_deg,
                              (r.texture_format.empty() ? r.backend + "-" + r.precision
                                                        : r.backend + "-" + r.texture_format)
                                  .c_str());
                std::string safe = stem;
                for (char& ch : safe)
                    if (!std::isalnum((unsigned char)ch) && ch != '_' && ch != '-' && ch != '.') ch = '_';
                const std::string title = r.method + (r.params.empty() ? "" : " " + r.params) +
                                          " | " + r.heightfield + " | theta " +
                                          format_number(r.theta_deg) + " phi " +
                                          format_number(r.phi_deg) + " | " + r.backend;
                rows[i].map = "maps/" + write_error_map(errors[i], ex.samples,
                                                        (tmp_dir / "maps").string(), safe, title);
            }
        };
    if (!a.quiet)
        opt.progress = [tty](const std::string& line) {
            if (tty) std::cerr << "\r\033[K" << line << std::flush;
            else std::cerr << line << "\n";
        };
    const auto t0 = std::chrono::steady_clock::now();
    RunInfo info;
    const auto rows = run_experiment(ex, opt, &info);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!a.quiet && tty) std::cerr << "\r\033[K";

    write_file_synced(tmp_dir / "results.csv", results_csv(rows));
    nlohmann::json run = provenance(nthreads);
    run["command_line"] = g_command_line;
    run["experiment_file"] = ex.path;
    run["experiment"] = ex.text;
    run["experiment_name"] = ex.name;
    run["inputs"] = input_records(ex);
    run["warnings"] = ex.warnings;
    if (!info.gl_renderer.empty()) {
        run["gl_renderer"] = info.gl_renderer;
        run["gl_version"] = info.gl_version;
        const char* lp = std::getenv("LP_NUM_THREADS");
        run["LP_NUM_THREADS"] = lp ? lp : "";
        run["shader_dir"] = a.shader_dir.empty() ? "" : fs::absolute(a.shader_dir).string();
        run["shaders"] = info.shaders;
    }
    size_t failed = 0;
    for (const auto& r : rows) failed += r.status != "ok";
    run["rows"] = rows.size();
    run["failed_rows"] = failed;
    run["seconds"] = secs;
    // Written last: the sha256 of every file above (pxh check and report verify them).
    run["files"] = file_records(tmp_dir);
    write_file_synced(tmp_dir / "run.json", run.dump(2) + "\n");
    folder.commit();

    if (!a.quiet) print_summary(rows);
    std::cout << rows.size() << " rows (" << failed << " failed) in " << std::setprecision(1)
              << std::fixed << secs << " s -> " << folder.final_dir().string() << "\n";
    if (failed) {
        // A failure is never a success: name the failed rows (their metrics are empty).
        size_t shown = 0;
        for (const auto& r : rows) {
            if (r.status == "ok") continue;
            if (++shown > 10) {
                std::cerr << "pxh: ... and " << failed - 10 << " more failed rows (status=failed in results.csv)\n";
                break;
            }
            std::cerr << "pxh: failed row: " << r.method << (r.params.empty() ? "" : " " + r.params)
                      << " | " << r.heightfield << " | theta " << format_number(r.theta_deg)
                      << " phi " << format_number(r.phi_deg) << " | " << r.backend << "/"
                      << (r.texture_format.empty() ? r.precision : r.texture_format) << ": "
                      << one_line(r.error) << "\n";
        }
        return 1;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"pxh: measures how far parallax-mapping methods are from the true displaced "
                 "surface, and what they cost"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "pxh 0.1.0");

    auto* run = app.add_subcommand("run", "run an experiment file, write results.csv and run.json "
                                          "(exit 0: all rows ok; 1: some row failed, results "
                                          "written; 2: bad input, nothing written)");
    RunArgs ra;
    run->add_option("experiment", ra.file, "experiment file (TOML)")->required();
    run->add_option("--out", ra.out_dir,
                    "results folder (default results/runs/NAME-DATE); must not exist, be empty, "
                    "or (with --force) hold earlier pxh results");
    run->add_flag("--force", ra.force,
                  "replace the earlier pxh results in --out (only pxh's own files there)");
    run->add_option("--threads", ra.threads, "worker threads, >= 1 (default: all cores)");
    run->add_option("--backend", ra.backends, "backends to run, overriding the file (cpu, glsl)");
    run->add_option("--shader-dir", ra.shader_dir,
                    "read GLSL from this folder (NAME.frag.glsl, common.glsl) instead of the "
                    "embedded copies; a file missing there is taken from the embedded copies, "
                    "and the shader column says which ran");
    run->add_flag("--quiet", ra.quiet, "no progress or summary (the final one-line count is still printed)");
    run->add_flag("--maps", ra.maps, "write an error map (EXR + false-colour PNG) per row");
    run->add_option("--max-rows", ra.max_rows,
                    "refuse a run estimated to write more rows (default " +
                        std::to_string(kDefaultMaxRows) + ")");
    run->add_option("--max-memory", ra.max_memory,
                    "refuse a run estimated to need more memory, e.g. 512M, 16G (default " +
                        format_bytes(kDefaultMaxMemoryBytes) + ")");

    auto* list = app.add_subcommand("list", "list registered methods, or height fields (generators and imported scans)");
    std::string what;
    list->add_option("what", what, "methods | heightfields")
        ->required()
        ->check(CLI::IsMember({"methods", "heightfields"}));

    auto* bench = app.add_subcommand(
        "bench", "ground-truth throughput: exact tracer vs Embree on the same rays (medians)");
    BenchOptions bo;
    bench->add_option("--sizes", bo.sizes, "height field sizes (default 512 2048)")
        ->check(CLI::Range(1, 16384));
    bench->add_option("--theta", bo.thetas, "view angles in degrees (default 60 85)")
        ->check(CLI::Range(0.0, 89.999));
    bench->add_option("--phi", bo.phi, "azimuth in degrees (default 20)");
    bench->add_option("--field", bo.field, "generator (default fbm)");
    bench->add_option("--samples", bo.samples, "N: N x N rays (default 512)")
        ->check(CLI::Range(1, 8192));
    bench->add_option("--repeats", bo.repeats, "timed repeats (default 5)")->check(CLI::Range(1, 1000));
    bench->add_option("--threads", bo.threads, "threads (default 2)")->check(CLI::Range(1, 1024));
    bench->add_flag("--naive", bo.naive,
                    "also time the per-ray tracers (max-mipmap walk, per-cell DDA) on the same rays");
    bench->add_option("--out", bo.out, "JSON output (default results/runs/bench-DATE.json)");

    auto* report = app.add_subcommand("report", "tables (Markdown, LaTeX, CSV) and plots (PNG, SVG) "
                                                 "from a results folder, into DIR/report/");
    std::string report_dir;
    bool no_plots = false;
    report->add_option("dir", report_dir, "results folder (holding results.csv)")->required();
    report->add_flag("--no-plots", no_plots, "tables only (no matplotlib needed)");
    bool accept_edited = false;
    const char* accept_help =
        "use a results folder whose files differ from what its run recorded in run.json "
        "(e.g. a post-processed results.csv); the output then says NOT VERIFIED";
    report->add_flag("--accept-edited", accept_edited, accept_help);
    ReportOptions ro;
    report->add_option("--bands", ro.bands,
                       "view-angle band edges in degrees, ascending in [0, 90] (default "
                       "0,30,60,75,85,90); bands are [lo, hi), the last one closed")
        ->delimiter(',');
    report->add_option("--budget-metric", ro.budget_metric,
                       "error the budget table ranks by: p95, p99 (texels) or frac_gt_1 "
                       "(fraction of samples more than 1 texel off); default p95");

    auto* check = app.add_subcommand("check", "check a results folder against accuracy limits; "
                                              "exit 1 if any fails");
    std::string check_dir, thresholds;
    check->add_option("dir", check_dir, "results folder (holding results.csv)")->required();
    check->add_option("--thresholds", thresholds, "thresholds file (TOML, [[limit]] tables)")
        ->required();
    check->add_flag("--accept-edited", accept_edited, accept_help);

    auto* import = app.add_subcommand("import", "import the scanned height fields from Debian "
                                                 "packages into heightfields/scanned/");
    ImportOptions io;
    import->add_option("--out", io.out_dir, "output folder (default heightfields/scanned)");
    import->add_option("--cache", io.cache_dir, "package cache (default build/scan-cache)");
    import->add_flag("--check", io.check, "re-import and compare with the committed files (exit 1 "
                                          "if they differ)");

    for (int i = 0; i < argc; ++i) g_command_line += (i ? " " : "") + std::string(argv[i]);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // One line in pxh's own format, like every other error.
        std::cerr << "pxh: error: " << one_line(e.what()) << " (see pxh --help)\n";
        return 2;
    }
    try {
        if (*run) {
            if (ra.threads < 0 || (run->count("--threads") && ra.threads == 0))
                throw InputError("--threads", std::to_string(ra.threads) + " is not a thread count (>= 1)");
            return cmd_run(ra);
        }
        if (*bench) return run_bench(bo);
        if (*report) {
            std::cout << verify_results_folder(report_dir, accept_edited) << "\n";
            ro.plots = !no_plots;
            ro.accept_edited = accept_edited;
            return run_report(report_dir, ro);
        }
        if (*import) return run_import(io);
        if (*check) {
            // A CI gate passes only on the results a run wrote (run.json's sha256 and rows).
            const std::string verified = verify_results_folder(check_dir, accept_edited);
            std::cout << verified << "\n";
            const int rc = run_check(check_dir, thresholds);
            if (verified.rfind("NOT VERIFIED", 0) == 0)
                std::cout << "results NOT VERIFIED: " << check_dir << " differs from its run.json\n";
            return rc;
        }
        if (*list) {
            if (what == "methods") list_methods(); else list_heightfields();
            return 0;
        }
    } catch (const InputError& e) {
        std::cerr << "pxh: error: " << one_line(e.what()) << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "pxh: error: " << one_line(e.what()) << "\n";
        return 1;
    }
    return 0;
}

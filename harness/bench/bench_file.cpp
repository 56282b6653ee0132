// pxh bench's JSON file: its title, the paths taken, and writing it beside, then over, --out
// (never through a link, never over anyone else's file).
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "harness/bench/bench_util.h"
#include "harness/core/error.h"
#include "harness/core/safe_files.h"
#include "harness/results/provenance.h"
#include "harness/truth/embree_truth.h"
#include "harness/truth/ground_truth.h"

namespace pxh {

double bench_median(std::vector<double> v) {
    if (v.empty()) return NAN;
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double bench_spread(const std::vector<double>& seconds_list) {
    if (seconds_list.empty()) return NAN;
    const auto [lo, hi] = std::minmax_element(seconds_list.begin(), seconds_list.end());
    return (*hi - *lo) / bench_median(seconds_list);
}

double bench_seconds(const std::function<void()>& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

namespace {

const char* const kBenchTitle =
    "ground truth throughput: exact (trace_grid: the view's parallel rays in bands over "
    "max-mipmap bounds) vs Embree rtcIntersect16, both on the same sample grid";
const char* const kPerspectiveBenchTitle =
    "ground truth throughput: exact (trace_ray: per-ray max-mipmap walk, trace_naive's hits "
    "bit for bit) vs Embree rtcIntersect16, both on the same perspective rays";

// Whether `path` (a regular file) is a JSON document pxh bench wrote.
bool is_pxh_bench_file(const std::string& path) {
    try {
        std::ifstream f(path, std::ios::binary);
        const auto doc = nlohmann::json::parse(f);
        return doc.is_object() && doc.contains("benchmark") &&
               (doc["benchmark"] == kBenchTitle || doc["benchmark"] == kPerspectiveBenchTitle) &&
               doc.contains("pxh_version") && doc.contains("results");
    } catch (const std::exception&) {
        return false;
    }
}

// The CPU's flags (/proc/cpuinfo's first "flags" line), space-separated.
std::string cpu_flags() {
    std::ifstream f("/proc/cpuinfo");
    std::string line;
    while (std::getline(f, line))
        if (line.rfind("flags", 0) == 0) {
            const auto pos = line.find(':');
            return pos == std::string::npos ? "" : line.substr(pos + 2);
        }
    return "";
}

// The paths both tracers take on this CPU (as capped by PXH_TRACER_PATH), and the CPU's vector
// flags (the whole list under cpu_flags).
}  // namespace

nlohmann::json paths_taken() {
    const char* env = std::getenv("PXH_TRACER_PATH");
    const ExactTracer::RayPath path = ExactTracer::default_path();
    std::string vector_flags;
    std::istringstream flags(cpu_flags());
    for (std::string f; flags >> f;)
        if (f == "sse4_2" || f == "avx" || f == "fma" || f.rfind("avx2", 0) == 0 ||
            f.rfind("avx512", 0) == 0)
            vector_flags += (vector_flags.empty() ? "" : " ") + f;
    const char* per_ray = path == ExactTracer::RayPath::avx512
                              ? "avx512: square walk and DDA, 8 rays to a vector"
                          : path == ExactTracer::RayPath::avx2
                              ? "avx2: square walk 8 rays to a vector (float), DDA 4 (double)"
                              : "scalar: packets, then the max-mipmap walk per ray";
    const char* band =
        path == ExactTracer::RayPath::avx512
            ? "avx512: the band tracer's bounds, its cells by the DDA 8 rays to a vector"
        : path == ExactTracer::RayPath::avx2
            ? "avx2: the band tracer's bounds, its cells by the DDA 4 rays to a vector"
            : "scalar: the band tracer's bounds and walk";
    return {{"exact_per_ray_path", per_ray},
            {"exact_band_path", band},
            {"embree_isa", EmbreeTracer::isa()},
            {"embree_device_config", EmbreeTracer::device_config()},
            {"pxh_tracer_path_env", env ? env : ""},
            {"cpu_best_per_ray_path", ExactTracer::path_name(ExactTracer::cpu_best_path())},
            {"cpu_vector_flags", vector_flags},
            {"cpu_flags", cpu_flags()}};
}

// The JSON document: provenance, the settings and every view's entry.
void write_bench(const BenchOptions& opt, const nlohmann::json& results, size_t rays) {
    // parallel rays (the orthographic grid): the band path; a camera with an eye: per ray
    const bool eye = !camera_entry(opt.camera, "--camera").parallel;
    nlohmann::json doc = provenance(opt.threads);
    doc["benchmark"] = eye ? kPerspectiveBenchTitle : kBenchTitle;
    doc["camera"] = opt.camera;
    if (eye) doc["fov_deg"] = opt.fov;
    doc.update(paths_taken());
    doc["field"] = opt.field;
    doc["scale"] = opt.scale;
    doc["bias"] = opt.bias;
    doc["repeats"] = opt.repeats;
    doc["statistic"] = "median over repeats; ratio from medians measured in the same run";
    doc["results"] = results;
    const std::string& out = opt.out;
    const auto parent = std::filesystem::path(out).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
    replace_own_file(
        out, doc.dump(2) + "\n",
        [](const std::filesystem::path& p) { return is_pxh_bench_file(p); }, out,
        "is no longer a pxh bench file; not replaced");
    std::cout << "ratio = exact / Embree throughput (median of " << opt.repeats << " repeats, "
              << opt.threads << " threads, " << rays << " rays); agreement in texels"
              << (eye ? " over inside pixels" : "")
              << "; spread = (max - min) / median of the repeats' times -> " << out << std::endl;
    std::fflush(stdout);
    if (!std::cout || std::ferror(stdout))
        throw std::runtime_error(
            "cannot write to standard output (a closed pipe?); the results "
            "are complete in " +
            out);
}

void check_bench_out(const std::string& out, bool force) {
    if (out.empty()) throw InputError("--out", "is empty: name the JSON file");
    if (const std::string why = utf8_problem(out); !why.empty())
        throw InputError("--out", "is not UTF-8 (" + why + ")");
    struct stat st;
    if (::lstat(out.c_str(), &st) != 0) {
        if (errno == ENOENT) return;  // a new file: the usual case
        throw InputError(out, std::string("cannot inspect: ") + std::strerror(errno));
    }
    if (S_ISLNK(st.st_mode))
        throw InputError(out,
                         "is a symbolic link: pxh bench writes a file of its own, never "
                         "through a link (name the file itself)");
    if (!S_ISREG(st.st_mode))
        throw InputError(out,
                         "exists and is not a regular file (a device, a folder?): pxh "
                         "bench writes a new file; choose another --out");
    if (!is_pxh_bench_file(out))
        throw InputError(out,
                         "exists and is not a pxh bench file: pxh never overwrites what it "
                         "did not create; choose another --out");
    if (!force)
        throw InputError(out,
                         "holds an earlier pxh bench result: pass --force to replace it, or "
                         "choose another --out");
}

}  // namespace pxh

#include "harness/commands/bench.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>

#include "harness/commands/bench_curved.h"
#include "harness/core/error.h"
#include "harness/core/safe_files.h"
#include "harness/metrics/agreement.h"
#include "harness/results/provenance.h"
#include "harness/scene/base_surface.h"
#include "harness/scene/curved_view.h"
#include "harness/scene/perspective_camera.h"
#include "harness/truth/curved_tracer.h"
#include "harness/truth/embree_truth.h"
#include "harness/truth/ground_truth.h"
#include "harness/truth/travel_limit.h"
#include "heightfields/heightfields.h"
#include "heightfields/scanned.h"

namespace pxh {
namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

PerspectiveParams perspective_params(const BenchOptions& opt, double theta, double distance) {
    PerspectiveParams p;
    p.theta_deg = theta;
    p.phi_deg = opt.phi;
    p.distance = distance;
    p.fov_deg = opt.fov;
    p.samples = opt.samples;
    return p;
}

double seconds(const std::function<void()>& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The repeated timings of one view (seconds), and the last run's results of both tracers.
struct ViewTimings {
    std::vector<double> exact, embree, per_ray, walk, naive;
    Hits hits, em;  // the exact tracer's, Embree's
};

// Both tracers through the Tracer interface on the same view (an orthographic grid view takes
// the exact tracer's band path, any other its per-ray path), and with --naive the two other
// per-ray tracers on the same rays.
ViewTimings time_view(const ExactTracer& exact, const EmbreeTracer& embree, const View& view,
                      const BenchOptions& opt) {
    // Both write into buffers kept from run to run (so neither pays for fresh pages).
    ViewTimings t;
    auto run_exact = [&] { exact.trace(view, t.hits); };
    auto run_embree = [&] { embree.trace(view, t.em); };
    run_exact();  // warm-up
    run_embree();
    auto per_ray = [&](auto&& trace_one) {
        return seconds([&] {
            tbb::parallel_for(tbb::blocked_range<size_t>(0, view.size(), 256), [&](const auto& r) {
                for (size_t k = r.begin(); k < r.end(); ++k) trace_one(view.P[k], view.dir(k));
            });
        });
    };
    for (int rep = 0; rep < opt.repeats; ++rep) {
        // Alternate the order so drift on a shared machine hits both alike.
        if (rep % 2 == 0) {
            t.exact.push_back(seconds(run_exact));
            t.embree.push_back(seconds(run_embree));
        } else {
            t.embree.push_back(seconds(run_embree));
            t.exact.push_back(seconds(run_exact));
        }
        if (opt.naive) {
            t.per_ray.push_back(per_ray([&](Vec2d p, Vec3d v) { return exact.trace(p, v); }));
            t.walk.push_back(per_ray([&](Vec2d p, Vec3d v) { return exact.trace_ray(p, v); }));
            t.naive.push_back(per_ray([&](Vec2d p, Vec3d v) { return exact.trace_naive(p, v); }));
        }
    }
    return t;
}

// The settings of one view: theta, and for a perspective camera D and F.
struct ViewSetting {
    double theta = 0, distance = 0;
    const std::vector<uint8_t>* inside = nullptr;  // perspective: the inside mask
    size_t outside = 0;
};

double spread(const std::vector<double>& seconds_list) {
    // (max - min) / median of the repeats' times: how much the machine moved the timings.
    const auto [lo, hi] = std::minmax_element(seconds_list.begin(), seconds_list.end());
    return (*hi - *lo) / median(seconds_list);
}

// One view's line on stdout and its entry in the JSON (build times in seconds).
nlohmann::json report_view(const BenchOptions& opt, int size, const ViewSetting& vs,
                           const ViewTimings& t, double exact_build, double embree_build) {
    const size_t n = t.hits.uv.size();
    const double rays = double(n);
    // Agreement over the pixels that are measured (a perspective view's inside pixels).
    std::vector<Vec2d> em_uv, exact_uv;
    for (size_t k = 0; k < n; ++k)
        if (!vs.inside || (*vs.inside)[k]) {
            em_uv.push_back(t.em.uv[k]);
            exact_uv.push_back(t.hits.uv[k]);
        }
    const ErrorStats agree = reference_agreement(em_uv, exact_uv, size, size);
    const double exact_mrays = rays / median(t.exact) / 1e6;
    const double embree_mrays = rays / median(t.embree) / 1e6;
    const bool persp = vs.inside != nullptr;
    std::printf("%-6d %-6g", size, vs.theta);
    if (persp) std::printf(" %-6g %8zu", vs.distance, vs.outside);
    std::printf(" %12.2f %12.2f %8.2f", exact_mrays, embree_mrays, exact_mrays / embree_mrays);
    if (opt.naive)
        std::printf(" %12.2f %12.2f %12.2f", rays / median(t.per_ray) / 1e6,
                    rays / median(t.walk) / 1e6, rays / median(t.naive) / 1e6);
    std::printf(" %10.4f %10.4f %10.3f %10.5f %5.2f %5.2f\n", agree.p50, agree.p99, agree.max,
                agree.frac_gt_0_5, spread(t.exact), spread(t.embree));
    std::fflush(stdout);
    nlohmann::json row = {{"size", size},
                          {"camera", opt.camera},
                          {"theta_deg", vs.theta},
                          {"phi_deg", opt.phi},
                          {"rays", n},
                          {"exact_mrays_per_s", exact_mrays},
                          {"embree_mrays_per_s", embree_mrays},
                          {"ratio_exact_over_embree", exact_mrays / embree_mrays},
                          {"exact_seconds", t.exact},
                          {"embree_seconds", t.embree},
                          {"exact_spread", spread(t.exact)},
                          {"embree_spread", spread(t.embree)},
                          {"exact_build_ms", exact_build * 1e3},
                          {"embree_build_ms", embree_build * 1e3},
                          {"agree_p50_texel", agree.p50},
                          {"agree_p99_texel", agree.p99},
                          {"agree_max_texel", agree.max},
                          {"agree_frac_gt_0_5", agree.frac_gt_0_5}};
    if (persp) {  // the rays of outside pixels are traced (the look-at ray) but not compared
        row["distance"] = vs.distance;
        row["fov_deg"] = opt.fov;
        row["samples_outside"] = vs.outside;
    }
    if (opt.naive) {  // measured only with --naive (otherwise left out, never NaN)
        row["per_ray_mipmap_mrays_per_s"] = rays / median(t.per_ray) / 1e6;
        row["trace_ray_mrays_per_s"] = rays / median(t.walk) / 1e6;
        row["naive_mrays_per_s"] = rays / median(t.naive) / 1e6;
        row["trace_ray_seconds"] = t.walk;
        row["per_ray_mipmap_seconds"] = t.per_ray;
        row["naive_seconds"] = t.naive;
    }
    return row;
}

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

// Writes `text` as `out`: a new file beside it, renamed over `out` only when `replace` (an
// earlier pxh bench file, checked again now), else into a name that must still be free.
void write_bench_file(const std::string& out, const std::string& text, bool replace) {
    const std::string tmp = out + ".partial-" + std::to_string(::getpid()) + "-" + random_hex8();
    create_new_file(tmp, text);
    int rc = 0;
    if (replace) {
        if (!is_pxh_bench_file(out)) {
            ::unlink(tmp.c_str());
            throw InputError(out, "is no longer a pxh bench file; not replaced");
        }
        rc = ::rename(tmp.c_str(), out.c_str());
    } else {
        rc = ::renameat2(AT_FDCWD, tmp.c_str(), AT_FDCWD, out.c_str(), RENAME_NOREPLACE);
    }
    if (rc != 0) {
        const std::string why = std::strerror(errno);
        ::unlink(tmp.c_str());
        throw std::runtime_error(out + ": cannot put the results in place: " + why);
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
    nlohmann::json doc = provenance(opt.threads);
    doc["benchmark"] = opt.camera == "perspective" ? kPerspectiveBenchTitle : kBenchTitle;
    doc["camera"] = opt.camera;
    if (opt.camera == "perspective") doc["fov_deg"] = opt.fov;
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
    std::error_code ec;
    write_bench_file(out, doc.dump(2) + "\n", std::filesystem::exists(out, ec));
    std::cout << "ratio = exact / Embree throughput (median of " << opt.repeats << " repeats, "
              << opt.threads << " threads, " << rays << " rays); agreement in texels"
              << (opt.camera == "perspective" ? " over inside pixels" : "")
              << "; spread = (max - min) / median of the repeats' times -> " << out << std::endl;
    std::fflush(stdout);
    if (!std::cout || std::ferror(stdout))
        throw std::runtime_error(
            "cannot write to standard output (a closed pipe?); the results "
            "are complete in " +
            out);
}

}  // namespace

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

// The walks pxh bench times on each view of a curved base: the warm-up and the repeats.
double bench_walks(const BenchOptions& opt) { return 1.0 + std::max(opt.repeats, 0); }

int run_bench(const BenchOptions& options) {
    BenchOptions opt = options;
    if (opt.out.empty()) opt.out = "results/runs/bench-" + utc_timestamp("%Y%m%d-%H%M%S") + ".json";
    check_bench_out(opt.out, opt.force);  // before any measurement
    // A generator at each of --sizes, or a measured field (scan:NAME, as `pxh list
    // heightfields` names it) at its own size (loaded before any measurement).
    const bool scan = opt.field.rfind("scan:", 0) == 0;
    const GeneratorInfo* gen = scan ? nullptr : find_generator(opt.field);
    if (!scan && !gen)
        throw InputError(
            "--field", "unknown generator '" + opt.field + "' (or scan:NAME for a measured field)");
    const HeightField scanned = scan ? load_scan(opt.field.substr(5), "--field") : HeightField{};
    const std::vector<int> sizes = scan ? std::vector<int>{scanned.width} : opt.sizes;
    // Views the ground truths would refuse (the travel limit), before any work.
    for (double theta : opt.thetas)
        if (const std::string why = ray_travel_problem(opt.scale, theta); !why.empty())
            throw InputError("--theta", why);
    if (opt.base != "plane")  // the radius's precision bound (kMaxBaseRadiusCells)
        for (int size : sizes)
            if (const std::string why =
                    base_radius_problem(opt.base, opt.radius, size, scan ? scanned.height : size);
                !why.empty())
                throw InputError("--radius", why);
    const bool persp = opt.camera == "perspective";
    if (persp)  // eyes below the slab top, before any work
        for (double theta : opt.thetas)
            for (double d : opt.distances) {
                const PerspectiveParams p = perspective_params(opt, theta, d);
                if (const std::string why = perspective_problem(p); !why.empty())
                    throw InputError("--camera perspective", why);
                check_eye_above_slab(p, opt.scale, opt.bias, "--distance");
                for (int size : sizes)  // within the exact tracer's reach (kMaxSampleCells)
                    if (const std::string why = reach_problem(0.5 + perspective_reach(p), size,
                                                              scan ? scanned.height : size);
                        !why.empty())
                        throw InputError("--distance", "distance " + format_number(d) +
                                                           " at theta " + format_number(theta) +
                                                           " " + why);
            }
    // The curved walk's work on each view (curved_walk_estimate over the warm-up and the
    // repeats), within kMaxCurvedWalkSteps, before any work.
    if (opt.base != "plane") {
        const std::unique_ptr<BaseSurface> b = make_base(opt.base, opt.radius);
        const size_t n = size_t(opt.samples) * size_t(opt.samples);
        auto check = [&](const Camera& camera, int size, double theta, const std::string& d) {
            const int h = scan ? scanned.height : size;
            const CurvedWalkEstimate e = curved_walk_estimate(*b, opt.scale, opt.bias, size, h,
                                                              camera, n, 0.25, bench_walks(opt));
            if (const std::string why = curved_walk_problem(
                    e,
                    "timed " + format_number(bench_walks(opt)) +
                        " times (a warm-up and --repeats " + std::to_string(opt.repeats) + ")",
                    "lower --theta, --sizes, --samples or --repeats");
                !why.empty())
                throw InputError("--base",
                                 "base " + opt.base + " radius " + format_number(opt.radius) +
                                     " on the " + std::to_string(size) + " x " + std::to_string(h) +
                                     " field at theta " + format_number(theta) + d + ": " + why);
        };
        for (int size : sizes)
            for (double theta : opt.thetas) {
                if (!persp) {
                    check(OrthographicCamera(theta, opt.phi, opt.samples), size, theta, "");
                    continue;
                }
                for (double d : opt.distances)
                    check(PerspectiveCamera(perspective_params(opt, theta, d)), size, theta,
                          " distance " + format_number(d));
            }
    }
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(opt.threads));
    const size_t rays = size_t(opt.samples) * size_t(opt.samples);
    nlohmann::json results = nlohmann::json::array();
    // The paths taken and the CPU, before the table.
    {
        const nlohmann::json p = paths_taken();
        std::printf("cpu: %s; vector flags: %s\n", cpu_model().c_str(),
                    p["cpu_vector_flags"].get<std::string>().c_str());
        const std::string ortho =
            ExactTracer::cpu_has_simd_path()
                ? p["exact_per_ray_path"].get<std::string>() + " up to theta " +
                      format_number(ExactTracer::kGridRaysMaxThetaDeg) + " deg, above it " +
                      p["exact_band_path"].get<std::string>() +
                      " (fields of 2 x 2 cells or more; each view's path: exact_path)"
                : p["exact_band_path"].get<std::string>();
        std::printf("exact: %s; Embree: %s kernels%s\n",
                    persp ? p["exact_per_ray_path"].get<std::string>().c_str() : ortho.c_str(),
                    p["embree_isa"].get<std::string>().c_str(),
                    p["pxh_tracer_path_env"].get<std::string>().empty()
                        ? ""
                        : (" (PXH_TRACER_PATH=" + p["pxh_tracer_path_env"].get<std::string>() + ")")
                              .c_str());
    }
    // Only the columns measured: the per-ray tracers' throughput with --naive alone.
    std::printf("%-6s %-6s", "size", "theta");
    if (persp) std::printf(" %-6s %8s", "D", "outside");
    std::printf(" %12s %12s %8s", "exact Mr/s", "embree Mr/s", "ratio");
    if (opt.naive) std::printf(" %12s %12s %12s", "per-ray Mr/s", "ray Mr/s", "naive Mr/s");
    std::printf(" %10s %10s %10s %10s %5s %5s\n", "agree p50", "agree p99", "agree max", "frac>0.5",
                "sprdX", "sprdE");
    const std::unique_ptr<BaseSurface> base =
        opt.base == "plane" ? nullptr : make_base(opt.base, opt.radius);
    for (int size : sizes) {
        const HeightField hf =
            scan ? scanned
                 : generate_heightfield(*gen, size, size,
                                        resolve_params(gen->params, {}, "bench", gen->name));
        std::unique_ptr<ExactTracer> exact;
        const double exact_build = seconds([&] {
            exact = std::make_unique<ExactTracer>(hf, opt.scale, opt.bias);
            exact->prepare_rays();  // the per-ray path's tables (any view may take it): its build
        });
        std::unique_ptr<EmbreeTracer> embree;
        const double embree_build =
            seconds([&] { embree = std::make_unique<EmbreeTracer>(hf, opt.scale, opt.bias); });
        for (double theta : opt.thetas) {
            if (!persp) {
                const OrthographicCamera camera(theta, opt.phi, opt.samples);
                const View view = camera.view();
                const ViewTimings t = time_view(*exact, *embree, view, opt);
                results.push_back(report_view(opt, size, {theta}, t, exact_build, embree_build));
                const std::string path = ExactTracer::path_name(exact->ray_path());
                results.back()["exact_path"] = exact->grid_takes_rays(view.V[0]) ? path
                                               : exact->simd_path()              ? "band+" + path
                                                                    : std::string("band");
                if (base)
                    time_curved(opt, hf, *base, camera, "theta " + format_number(theta),
                                results.back()["exact_mrays_per_s"], results.back());
                continue;
            }
            for (double d : opt.distances) {
                const PerspectiveCamera camera(perspective_params(opt, theta, d));
                const View view = camera.view();
                if (const std::string why = view_travel_problem(opt.scale, view); !why.empty())
                    throw InputError("--theta", why);
                const std::vector<uint8_t> inside = camera.inside();
                const ViewTimings t = time_view(*exact, *embree, view, opt);
                results.push_back(report_view(opt, size,
                                              {theta, d, &inside, camera.outside_count()}, t,
                                              exact_build, embree_build));
                if (base)
                    time_curved(opt, hf, *base, camera,
                                "theta " + format_number(theta) + " distance " + format_number(d),
                                results.back()["exact_mrays_per_s"], results.back());
            }
        }
    }
    write_bench(opt, results, rays);
    return 0;
}

}  // namespace pxh

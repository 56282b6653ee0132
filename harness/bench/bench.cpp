// pxh bench: the fields, the checks before any measurement, and each field's views timed (the
// flat relief: bench_flat.cpp; a curved base: bench_curved.cpp; the JSON: bench_file.cpp).
#include "harness/bench/bench.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <cstdio>
#include <memory>

#include "harness/bench/bench_curved.h"
#include "harness/bench/bench_flat.h"
#include "harness/bench/bench_util.h"
#include "harness/core/error.h"
#include "harness/core/params.h"
#include "harness/results/provenance.h"
#include "harness/scene/base_surface.h"
#include "harness/scene/perspective_camera.h"
#include "harness/truth/curved_tracer.h"
#include "harness/truth/embree_truth.h"
#include "harness/truth/ground_truth.h"
#include "harness/truth/travel_limit.h"
#include "heightfields/heightfields.h"
#include "heightfields/scanned.h"

namespace pxh {
namespace {

PerspectiveParams perspective_params(const BenchOptions& opt, double theta, double distance) {
    PerspectiveParams p;
    p.theta_deg = theta;
    p.phi_deg = opt.phi;
    p.distance = distance;
    p.fov_deg = opt.fov;
    p.samples = opt.samples;
    return p;
}

// The cameras pxh bench sweeps: the views of each at one theta, checked before any work.
struct BenchCamera {
    const char* name;
    // its views at theta (and the eye's checks: below the slab top, beyond the exact tracer's
    // reach on a `size` x `height` field), throwing InputError
    void (*check)(const BenchOptions& opt, double theta, int size, int height);
    std::vector<BenchView> (*views)(const BenchOptions& opt, double theta);
};

void check_orthographic(const BenchOptions&, double, int, int) {}

std::vector<BenchView> orthographic_views(const BenchOptions& opt, double theta) {
    std::vector<BenchView> v(1);
    v[0].camera = std::make_unique<OrthographicCamera>(theta, opt.phi, opt.samples);
    v[0].theta = theta;
    v[0].at = "theta " + format_number(theta);
    return v;
}

void check_perspective(const BenchOptions& opt, double theta, int size, int height) {
    for (double d : opt.distances) {
        const PerspectiveParams p = perspective_params(opt, theta, d);
        if (const std::string why = perspective_problem(p); !why.empty())
            throw InputError("--camera perspective", why);
        check_eye_above_slab(p, opt.scale, opt.bias, "--distance");
        // within the exact tracer's reach (kMaxSampleCells)
        if (const std::string why = reach_problem(0.5 + perspective_reach(p), size, height);
            !why.empty())
            throw InputError("--distance", "distance " + format_number(d) + " at theta " +
                                               format_number(theta) + " " + why);
    }
}

std::vector<BenchView> perspective_views(const BenchOptions& opt, double theta) {
    std::vector<BenchView> v;
    for (double d : opt.distances) {
        BenchView bv;
        bv.camera = std::make_unique<PerspectiveCamera>(perspective_params(opt, theta, d));
        bv.theta = theta;
        bv.distance = d;
        bv.eye = true;
        bv.at = "theta " + format_number(theta) + " distance " + format_number(d);
        v.push_back(std::move(bv));
    }
    return v;
}

const BenchCamera kBenchCameras[] = {
    {"orthographic", &check_orthographic, &orthographic_views},
    {"perspective", &check_perspective, &perspective_views},
};

// --camera's entry: a camera of the registry (InputError otherwise) that pxh bench sweeps.
const BenchCamera& bench_camera(const std::string& name) {
    camera_entry(name, "--camera");  // an unknown camera: the registry's one line
    std::string known;
    for (const BenchCamera& c : kBenchCameras) {
        if (name == c.name) return c;
        known += std::string(known.empty() ? "" : ", ") + c.name;
    }
    throw InputError("--camera",
                     "pxh bench has no sweep for camera '" + name + "' (it times " + known + ")");
}

// The fields pxh bench times: a generator at each of --sizes, or a measured field (scan:NAME,
// as `pxh list heightfields` names it) at its own size, loaded before any measurement.
struct BenchFields {
    const GeneratorInfo* gen = nullptr;
    HeightField scanned;
    bool scan = false;
    std::vector<int> sizes;
    int height(int size) const { return scan ? scanned.height : size; }
    HeightField make(int size) const {
        return scan ? scanned
                    : generate_heightfield(*gen, size, size,
                                           resolve_params(gen->params, {}, "bench", gen->name));
    }
};

BenchFields bench_fields(const BenchOptions& opt) {
    BenchFields f;
    f.scan = opt.field.rfind("scan:", 0) == 0;
    f.gen = f.scan ? nullptr : find_generator(opt.field);
    if (!f.scan && !f.gen)
        throw InputError(
            "--field", "unknown generator '" + opt.field + "' (or scan:NAME for a measured field)");
    if (f.scan) f.scanned = load_scan(opt.field.substr(5), "--field");
    f.sizes = f.scan ? std::vector<int>{f.scanned.width} : opt.sizes;
    return f;
}

// The curved walk's work on each view (curved_walk_estimate over the warm-up and the repeats)
// within kMaxCurvedWalkSteps, before any work.
void check_curved_walks(const BenchOptions& opt, const BenchFields& f, const BenchCamera& cam) {
    const std::unique_ptr<BaseSurface> b = make_base(opt.base, opt.radius);
    const size_t n = size_t(opt.samples) * size_t(opt.samples);
    const std::string walks = "timed " + format_number(bench_walks(opt)) +
                              " times (a warm-up and --repeats " + std::to_string(opt.repeats) +
                              ")";
    for (int size : f.sizes)
        for (double theta : opt.thetas)
            for (const BenchView& bv : cam.views(opt, theta)) {
                const CurvedWalkEstimate e =
                    curved_walk_estimate(*b, opt.scale, opt.bias, size, f.height(size), *bv.camera,
                                         n, 0.25, bench_walks(opt));
                const std::string why =
                    curved_walk_problem(e, walks, "lower --theta, --sizes, --samples or --repeats");
                const std::string d = bv.eye ? " distance " + format_number(bv.distance) : "";
                if (!why.empty())
                    throw InputError("--base",
                                     "base " + opt.base + " radius " + format_number(opt.radius) +
                                         " on the " + std::to_string(size) + " x " +
                                         std::to_string(f.height(size)) + " field at theta " +
                                         format_number(theta) + d + ": " + why);
            }
}

// Everything the run would refuse, before any measurement.
void check_bench(const BenchOptions& opt, const BenchFields& f, const BenchCamera& cam,
                 bool curved) {
    // views the ground truths would refuse (the travel limit)
    for (double theta : opt.thetas)
        if (const std::string why = ray_travel_problem(opt.scale, theta); !why.empty())
            throw InputError("--theta", why);
    if (curved)  // the radius's precision bound (kMaxBaseRadiusCells)
        for (int size : f.sizes)
            if (const std::string why =
                    base_radius_problem(opt.base, opt.radius, size, f.height(size));
                !why.empty())
                throw InputError("--radius", why);
    for (double theta : opt.thetas)
        for (int size : f.sizes) cam.check(opt, theta, size, f.height(size));
    if (curved) check_curved_walks(opt, f, cam);
}

// The paths taken and the CPU, and the table's header, before the table.
void print_header(const BenchOptions& opt, bool eye) {
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
    const std::string env = p["pxh_tracer_path_env"].get<std::string>();
    std::printf("exact: %s; Embree: %s kernels%s\n",
                eye ? p["exact_per_ray_path"].get<std::string>().c_str() : ortho.c_str(),
                p["embree_isa"].get<std::string>().c_str(),
                env.empty() ? "" : (" (PXH_TRACER_PATH=" + env + ")").c_str());
    print_flat_header(opt, eye);
}

// One field's views: both flat tracers on each, and on a curved base the curved tracers over the
// same camera's rays; their entries appended to `results`.
void bench_field(const BenchOptions& opt, const HeightField& hf, const BenchCamera& cam,
                 const BaseSurface* base, nlohmann::json& results) {
    std::unique_ptr<ExactTracer> exact;
    const double exact_build = bench_seconds([&] {
        exact = std::make_unique<ExactTracer>(hf, opt.scale, opt.bias);
        exact->prepare_rays();  // the per-ray path's tables (any view may take it): its build
    });
    std::unique_ptr<EmbreeTracer> embree;
    const double embree_build =
        bench_seconds([&] { embree = std::make_unique<EmbreeTracer>(hf, opt.scale, opt.bias); });
    for (double theta : opt.thetas)
        for (const BenchView& bv : cam.views(opt, theta)) {
            const View view = bv.camera->view();
            if (bv.eye)
                if (const std::string why = view_travel_problem(opt.scale, view); !why.empty())
                    throw InputError("--theta", why);
            const ViewTimings t = time_view(*exact, *embree, view, opt);
            results.push_back(report_view(opt, hf.width, bv, view, t, exact_build, embree_build));
            if (!bv.eye) {
                const std::string path = ExactTracer::path_name(exact->ray_path());
                results.back()["exact_path"] = exact->grid_takes_rays(view.V[0]) ? path
                                               : exact->simd_path()              ? "band+" + path
                                                                                 : "band";
            }
            if (base)
                time_curved(opt, hf, *base, *bv.camera, bv.at, results.back()["exact_mrays_per_s"],
                            results.back());
        }
}

}  // namespace

std::vector<BenchView> bench_views(const BenchOptions& opt, double theta) {
    return bench_camera(opt.camera).views(opt, theta);
}

// The walks pxh bench times on each view of a curved base: the warm-up and the repeats.
double bench_walks(const BenchOptions& opt) { return 1.0 + std::max(opt.repeats, 0); }

int run_bench(const BenchOptions& options) {
    BenchOptions opt = options;
    if (opt.out.empty()) opt.out = "results/runs/bench-" + utc_timestamp("%Y%m%d-%H%M%S") + ".json";
    check_bench_out(opt.out, opt.force);  // before any measurement
    const BenchCamera& cam = bench_camera(opt.camera);
    const bool eye = !camera_entry(opt.camera, "--camera").parallel;
    const BaseEntry& base_kind = base_entry(opt.base, "--base");
    const BenchFields fields = bench_fields(opt);
    // a curved base: each radius in turn, every one checked before any measurement
    const std::vector<double> radii =
        base_kind.curved ? opt.radii : std::vector<double>{double(NAN)};
    for (double r : radii) {
        opt.radius = r;
        check_bench(opt, fields, cam, base_kind.curved);
    }
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(opt.threads));
    print_header(opt, eye);
    nlohmann::json results = nlohmann::json::array();
    for (double r : radii) {
        opt.radius = r;
        // a curved base: its curved tracers also time the same camera's rays (the plane: none)
        const std::unique_ptr<BaseSurface> base =
            base_kind.curved ? make_base(opt.base, opt.radius) : nullptr;
        for (int size : fields.sizes) bench_field(opt, fields.make(size), cam, base.get(), results);
    }
    write_bench(opt, results, size_t(opt.samples) * size_t(opt.samples));
    return 0;
}

}  // namespace pxh

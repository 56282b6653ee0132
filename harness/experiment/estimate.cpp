// What a run will take, estimated before any work: rows and peak memory (experiment.h).
#include <algorithm>
#include <set>

#include "harness/core/error.h"
#include "harness/experiment/experiment.h"
#include "harness/experiment/view_grid.h"
#include "harness/metrics/sweep.h"
#include "harness/scene/base_surface.h"
#include "harness/truth/exact_tracer.h"

namespace pxh {

RunEstimate estimate_run(const Experiment& ex, const std::vector<std::string>& backends_override) {
    // The model's constants (see experiment.h), measured on this project's machine (peak
    // RSS of pxh run, fbm, samples 4: 62 MiB at 16^2, and 187 MiB once an image is read or
    // written (maps = true), which loads OpenImageIO's module (harness/core/image_codec.h); +52
    // to +55 bytes per texel from 1024^2 to 8192^2, of which 10 are the field and its mipmap;
    // samples 2048, 6 rows per view: 290 bytes per sample, which the terms below overestimate
    // by a third).
    bool images = ex.maps || ex.render || ex.shading;
    for (const HeightfieldSpec& h : ex.heightfields) images = images || h.generator.empty();
    const size_t kBaseBytes = (size_t(64) << 20) + (images ? size_t(128) << 20 : 0);
    constexpr size_t kEmbreeBytesPerTexel = 45;
    // The exact tracer's square tables where the CPU has its AVX-512 path (ray_walk_simd.cpp):
    // 2.33 bytes per texel kept, and two float levels while they are built (peak 10.4; 13
    // counted, a bound).
    const size_t square_bytes_per_texel = ExactTracer::cpu_has_simd_path() ? 13 : 0;
    constexpr size_t kViewBytesPerSample = 16 + 40 + 16 + 8;  // P, exact hits, Embree hits, gap
    constexpr size_t kOutputBytesPerSample = 16 + 4 + 8 + 8;  // uv, fetches, shadows, scoring
    const auto& backends = backends_override.empty() ? ex.backends : backends_override;
    const BackendSettings settings = backend_settings(ex);
    size_t per_method = 0;  // rows per method setting: every backend's variants
    for (const auto& b : backends) per_method += backend_variants(b, settings).size();
    size_t rows_per_view = 0;  // the largest view's (a method may run on some fields only)
    RunEstimate est;
    for (const auto& h : ex.heightfields) {
        size_t methods = 0;
        for (const auto& m : ex.methods) methods += m.runs_on(h.name);
        rows_per_view = std::max(rows_per_view, methods * per_method);
        est.rows += ViewGrid(ex).views_per_field() * methods * per_method;
    }

    const bool levels = std::any_of(ex.methods.begin(), ex.methods.end(),
                                    [](const MethodSpec& m) { return m.lod != LodMode::base; });
    size_t field = 0;  // the largest field's own bytes, its truths' and Embree's
    std::set<std::string> seen;
    for (const auto& spec : ex.heightfields) {
        if (!seen.insert(spec.identity).second) continue;  // scale/bias sweeps: same size
        const FieldSize sz = field_size(spec);
        const size_t texels = sz.width * sz.height;
        // + the texture levels (4/3 of a float per texel) when a setting samples them
        field = std::max(field, texels * (4 + (sz.mask ? 1 : 0) + 6 + square_bytes_per_texel +
                                          kEmbreeBytesPerTexel + (levels ? 6 : 0)));
    }
    const size_t n2 = size_t(ex.samples) * size_t(ex.samples);
    // + a distance sweep's views waiting for the next distance (at most one per theta and
    // setting between a setting and its successor) and a slice's companion at the next distance
    const std::vector<DistanceStep> dist =
        distance_steps(ex.camera_settings, camera_entry(ex.camera, "camera").pair_key());
    size_t waiting = 0;
    for (size_t c = 0; c < dist.size(); ++c) {
        size_t open = 0;
        for (size_t b = 0; b <= c; ++b) open += dist[b].pairs() && dist[b].next > c;
        waiting = std::max(waiting, open * ex.theta_deg.size());
    }
    const size_t views_alive = (ex.sweep_dt_deg > 0 ? 3 : 2) + (waiting ? waiting + 1 : 0);
    // A camera whose rays are not parallel: per sample V (24), J (32), inside (1); every
    // view: lambda (8).
    const size_t camera_bytes = (camera_entry(ex.camera, "camera").parallel ? 0 : 24 + 32 + 1) + 8;
    // A curved base (docs/conventions.md section 12): its view is per sample whatever the camera
    // (P 16, V 24, J 32, inside 1, the world ray 48, base hit 1), its truth's walk twice (uv 16,
    // z 8, point 24, hit 1, and the per-ray record 32), the coverage (2) and per row the method's
    // shown uv for pictures (16).
    bool curved = false;
    for (const HeightfieldSpec& h : ex.heightfields) curved = curved || base_entry(h.base).curved;
    const size_t curved_bytes =
        curved ? 16 + 24 + 32 + 1 + 48 + 1 + 2 * (16 + 8 + 24 + 1 + 32) + 2 + rows_per_view * 16
               : 0;
    // Outputs alive at once: the reference's float and double and the row being scored, and
    // with another backend (the GLSL backend, whose rows may be drawn in its own process) the
    // side lane's rows ahead and the one it draws.
    bool own_process = false;
    for (const std::string& b : backends) own_process = own_process || !backend_entry(b).reference;
    const size_t outputs = 3 + (own_process ? kSideRowsAhead + 1 : 0);
    const size_t view =
        n2 * (kViewBytesPerSample + camera_bytes + curved_bytes + rows_per_view * 16 * views_alive +
              outputs * kOutputBytesPerSample + (ex.maps ? 16 : 0));
    const size_t results = est.rows * kBytesPerRow;
    est.peak_bytes = kBaseBytes + field + view + results;
    est.detail = "process " + format_bytes(kBaseBytes) +
                 " + largest field with its truths and Embree " + format_bytes(field) +
                 " + one view's sample buffers " + format_bytes(view) + " + result rows " +
                 format_bytes(results);
    return est;
}

void check_run_size(const Experiment& ex, const std::vector<std::string>& backends_override,
                    size_t max_rows, size_t max_memory) {
    const RunEstimate est = estimate_run(ex, backends_override);
    if (est.rows > max_rows)
        throw InputError(ex.path, "the run would write " + std::to_string(est.rows) +
                                      " rows, over the limit of " + std::to_string(max_rows) +
                                      " (raise it with --max-rows N)");
    if (est.peak_bytes > max_memory)
        throw InputError(ex.path, "the run would need about " + format_bytes(est.peak_bytes) +
                                      " of memory, over the limit of " + format_bytes(max_memory) +
                                      " (" + est.detail + "; raise it with --max-memory SIZE)");
}

}  // namespace pxh

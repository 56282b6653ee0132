// One flat row per (method, params, height field, s, b, view, backend, precision); reporters
// only consume rows.
#pragma once
#include <cmath>
#include <string>
#include <vector>

#include "harness/metrics/metrics.h"

namespace pxh {

struct ResultRow {
    std::string method, params, heightfield, backend, precision;
    std::string heightfield_id;     // what identifies the field: generator + parameters, or
                                    //   the file (path relative to the experiment) + sha256
    std::string texture_format;     // GLSL rows: r32f | r16 | r8
    std::string shader;             // GLSL rows: "builtin" or the shader file(s) compiled
    double scale = 0, bias = 0, theta_deg = 0, phi_deg = 0;
    int samples = 0, width = 0, height = 0;
    ErrorStats err;
    double fetches_mean = NAN, fetches_max = NAN;
    int fetches_bound = 0;          // the method's declared bound for this view
    double ns_per_sample = NAN;     // CPU: median single-thread time per sample
    double ns_per_sample_min = NAN, ns_per_sample_max = NAN;  // ... fastest and slowest repeat
    double ms_per_frame = NAN;      // GLSL: median wall time of one N x N frame (glFinish)
    double ms_per_frame_min = NAN, ms_per_frame_max = NAN;    // ... fastest and slowest frame
    double cpu_diff_max = NAN;      // GLSL: |uv_glsl - uv_cpu_float| in texels, max
    double cpu_diff_p999 = NAN;     // ... and its 99.9th percentile
    double decision_mismatch = NAN; // GLSL: samples whose fetch count (layer decision) differs
    double double_diff_max = NAN;   // CPU float rows (when double ran too): |uv_f - uv_d|
    double double_diff_p999 = NAN;  //   in texels, max and 99.9th percentile
    double sliding = NAN;           // texels per degree: |mean change of e| / dt
    double shimmering = NAN;        // texels per degree: mean |change of e - mean change| / dt
    double sweep_dt_deg = NAN;      // the dt the two above were measured over
    std::string map;                // error map (PNG) relative to the results folder
    double gt_on_filled = NAN;      // measured fields: fraction of samples whose true hit
                                    //   depends on a filled hole texel
    long long excluded = 0;         // samples left out of err_* (exclude_filled = true)
    double gt_cells_mean = NAN;     // ground-truth cost: cells per ray given to the exact solver
    std::string ground_truth;       // exact | embree: the reference of the err_* columns
    double gt_agree_p50 = NAN;      // |hit_exact - hit_embree| in texels over the samples:
    double gt_agree_p99 = NAN;      //   median, p99, max and fraction > 0.5 texel (the
    double gt_agree_max = NAN;      //   reference's own uncertainty for this field and view)
    double gt_agree_frac_gt_0_5 = NAN;
    double shadow_err = NAN;        // fraction of samples whose hard shadow state is wrong
    double shadow_soft_mae = NAN;   // mean |soft factor - true hard factor|
    std::string status = "ok";      // ok | failed
    std::string error;              // the message when failed
};

// A CSV field, quoted when it holds a comma, a quote or a newline (RFC 4180).
std::string csv_quote(const std::string& s);

// CSV header and rows in a fixed column order (numbers with round-trip precision). A failed
// row (status != ok) has every measured column empty: a failure is never a number.
std::vector<std::string> result_columns();
std::string results_csv(const std::vector<ResultRow>& rows);

}  // namespace pxh

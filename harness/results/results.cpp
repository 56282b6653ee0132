#include "harness/results/results.h"

#include <cstdio>
#include <fstream>
#include <functional>
#include <sstream>


namespace pxh {
namespace {

std::string num(double v) {
    if (std::isnan(v)) return "";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
}

struct Column {
    const char* name;
    std::function<std::string(const ResultRow&)> get;
    bool measured = true;  // false: says what was run (kept on failed rows)
};

const std::vector<Column>& columns() {
    static const std::vector<Column> cols = {
        {"method", [](const ResultRow& r) { return r.method; }, false},
        {"params", [](const ResultRow& r) { return r.params; }, false},
        {"heightfield", [](const ResultRow& r) { return r.heightfield; }, false},
        {"heightfield_id", [](const ResultRow& r) { return r.heightfield_id; }, false},
        {"backend", [](const ResultRow& r) { return r.backend; }, false},
        {"precision", [](const ResultRow& r) { return r.precision; }, false},
        {"texture_format", [](const ResultRow& r) { return r.texture_format; }, false},
        {"shader", [](const ResultRow& r) { return r.shader; }, false},
        {"scale", [](const ResultRow& r) { return num(r.scale); }, false},
        {"bias", [](const ResultRow& r) { return num(r.bias); }, false},
        {"theta_deg", [](const ResultRow& r) { return num(r.theta_deg); }, false},
        {"phi_deg", [](const ResultRow& r) { return num(r.phi_deg); }, false},
        {"samples", [](const ResultRow& r) { return std::to_string(r.samples); }, false},
        {"width", [](const ResultRow& r) { return std::to_string(r.width); }, false},
        {"height", [](const ResultRow& r) { return std::to_string(r.height); }, false},
        {"err_mean", [](const ResultRow& r) { return num(r.err.mean); }},
        {"err_rms", [](const ResultRow& r) { return num(r.err.rms); }},
        {"err_p50", [](const ResultRow& r) { return num(r.err.p50); }},
        {"err_p95", [](const ResultRow& r) { return num(r.err.p95); }},
        {"err_p99", [](const ResultRow& r) { return num(r.err.p99); }},
        {"err_max", [](const ResultRow& r) { return num(r.err.max); }},
        {"frac_gt_0_5", [](const ResultRow& r) { return num(r.err.frac_gt_0_5); }},
        {"frac_gt_1", [](const ResultRow& r) { return num(r.err.frac_gt_1); }},
        {"nonfinite", [](const ResultRow& r) { return std::to_string(r.err.nonfinite); }},
        {"fetches_mean", [](const ResultRow& r) { return num(r.fetches_mean); }},
        {"fetches_max", [](const ResultRow& r) { return num(r.fetches_max); }},
        {"fetches_bound", [](const ResultRow& r) { return std::to_string(r.fetches_bound); }, false},
        {"ns_per_sample", [](const ResultRow& r) { return num(r.ns_per_sample); }},
        {"ns_per_sample_min", [](const ResultRow& r) { return num(r.ns_per_sample_min); }},
        {"ns_per_sample_max", [](const ResultRow& r) { return num(r.ns_per_sample_max); }},
        {"ms_per_frame", [](const ResultRow& r) { return num(r.ms_per_frame); }},
        {"ms_per_frame_min", [](const ResultRow& r) { return num(r.ms_per_frame_min); }},
        {"ms_per_frame_max", [](const ResultRow& r) { return num(r.ms_per_frame_max); }},
        {"cpu_diff_max", [](const ResultRow& r) { return num(r.cpu_diff_max); }},
        {"cpu_diff_p999", [](const ResultRow& r) { return num(r.cpu_diff_p999); }},
        {"decision_mismatch", [](const ResultRow& r) { return num(r.decision_mismatch); }},
        {"double_diff_max", [](const ResultRow& r) { return num(r.double_diff_max); }},
        {"double_diff_p999", [](const ResultRow& r) { return num(r.double_diff_p999); }},
        {"sliding", [](const ResultRow& r) { return num(r.sliding); }},
        {"shimmering", [](const ResultRow& r) { return num(r.shimmering); }},
        {"sweep_dt_deg", [](const ResultRow& r) { return num(r.sweep_dt_deg); }},
        {"map", [](const ResultRow& r) { return r.map; }},
        {"gt_on_filled", [](const ResultRow& r) { return num(r.gt_on_filled); }},
        {"excluded", [](const ResultRow& r) { return std::to_string(r.excluded); }},
        {"gt_cells_mean", [](const ResultRow& r) { return num(r.gt_cells_mean); }},
        {"ground_truth", [](const ResultRow& r) { return r.ground_truth; }, false},
        {"gt_agree_p50", [](const ResultRow& r) { return num(r.gt_agree_p50); }},
        {"gt_agree_p99", [](const ResultRow& r) { return num(r.gt_agree_p99); }},
        {"gt_agree_max", [](const ResultRow& r) { return num(r.gt_agree_max); }},
        {"gt_agree_frac_gt_0_5", [](const ResultRow& r) { return num(r.gt_agree_frac_gt_0_5); }},
        {"shadow_err", [](const ResultRow& r) { return num(r.shadow_err); }},
        {"shadow_soft_mae", [](const ResultRow& r) { return num(r.shadow_soft_mae); }},
        {"status", [](const ResultRow& r) { return r.status; }, false},
        {"error", [](const ResultRow& r) { return r.error; }, false},
    };
    return cols;
}

}  // namespace

std::string csv_quote(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string out = "\"";
    for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
    return out + "\"";
}

std::vector<std::string> result_columns() {
    std::vector<std::string> out;
    for (const auto& c : columns()) out.push_back(c.name);
    return out;
}

std::string results_csv(const std::vector<ResultRow>& rows) {
    std::string out;
    const auto& cols = columns();
    for (size_t c = 0; c < cols.size(); ++c) out += (c ? "," : "") + std::string(cols[c].name);
    out += "\n";
    for (const auto& r : rows) {
        const bool ok = r.status == "ok";
        for (size_t c = 0; c < cols.size(); ++c) {
            if (c) out += ',';
            if (ok || !cols[c].measured) out += csv_quote(cols[c].get(r));
        }
        out += "\n";
    }
    return out;
}

}  // namespace pxh

// ns_per_sample{,_min,_max,_repeats} (CPU), ms_per_frame{,_min,_max,_repeats} and
// gpu_ms_per_frame{,_min,_max} (GLSL; the latter from timer queries, empty without them): empty
// when not timed. The _repeats columns hold every timed repeat, ';'-separated, in order.
#include "harness/metrics/metric.h"
#include "harness/metrics/timing_stats.h"

namespace pxh {

namespace {

void add_timing(const MetricInput& in, ResultRow& row) {
    row.set("ns_per_sample", in.out.ns_per_sample);
    row.set("ns_per_sample_min", in.out.ns_per_sample_min);
    row.set("ns_per_sample_max", in.out.ns_per_sample_max);
    row.set_text("ns_per_sample_repeats", format_repeats(in.out.ns_per_sample_repeats));
    row.set("ms_per_frame", in.out.ms_per_frame);
    row.set("ms_per_frame_min", in.out.ms_per_frame_min);
    row.set("ms_per_frame_max", in.out.ms_per_frame_max);
    row.set_text("ms_per_frame_repeats", format_repeats(in.out.ms_per_frame_repeats));
    row.set("gpu_ms_per_frame", in.out.gpu_ms_per_frame);
    row.set("gpu_ms_per_frame_min", in.out.gpu_ms_per_frame_min);
    row.set("gpu_ms_per_frame_max", in.out.gpu_ms_per_frame_max);
}

}  // namespace

// Its columns are in the table of harness/metrics/columns.cpp.
const Metric& timing_metric() {
    static const Metric m{"timing", add_timing};
    return m;
}

}  // namespace pxh

// The uniform timing columns (time, time_unit, time_min, time_max, time_repeats: the backend's
// own unit, every repeat ';'-separated in order) and each counter's NAME, NAME_min, NAME_max
// (the counters a backend declares in its registry entry): empty when not timed.
#include "harness/metrics/column_groups.h"
#include "harness/metrics/metric.h"
#include "harness/metrics/timing_stats.h"

namespace pxh {

namespace {

void add_timing(const MetricInput& in, ResultRow& row) {
    const Timing& t = in.out.timing;
    row.set("time", t.stats.median);
    row.set_text("time_unit", t.unit);
    row.set("time_min", t.stats.min);
    row.set("time_max", t.stats.max);
    row.set_text("time_repeats", format_repeats(t.repeats));
    for (const Counter& c : in.out.counters) {
        row.set(c.name, c.value.median);
        row.set(c.name + "_min", c.value.min);
        row.set(c.name + "_max", c.value.max);
    }
}

}  // namespace

// Its columns are in the table of harness/metrics/columns.cpp.
const Metric& timing_metric() {
    static const Metric m{"timing", add_timing};
    return m;
}

// The time in the unit the row's backend names; each backend's counters follow time_repeats
// (columns.cpp adds them from the backends' registry entries).
// Declared here, by the code that fills them; harness/metrics/columns.cpp places them in
// results.csv's order.
std::vector<ColumnSpec> timing_columns() {
    using namespace column_decl;
    return {
        ColumnSpec{"time", kNum, kMeasured, "median time of the timed repeats, in time_unit"}
            .in("timing", "time_unit")
            .lead(),
        {"time_unit", kText, kMeasured, "the backend's unit: ns/sample (cpu), ms/frame (glsl)"},
        ColumnSpec{"time_min", kNum, kMeasured, "fastest repeat (time_unit)"}.in("timing",
                                                                                 "time_unit"),
        ColumnSpec{"time_max", kNum, kMeasured, "slowest repeat (time_unit)"}.in("timing",
                                                                                 "time_unit"),
        {"time_repeats", kText, kMeasured,
         "every timed repeat (time_unit), ';'-separated, in the order measured"},
    };
}

}  // namespace pxh

// What `pxh run` prints on the console: the progress line while it runs, the summary after it,
// and the rows that failed.
#pragma once
#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "harness/experiment/shard.h"
#include "harness/results/results.h"

namespace pxh {

// Per method, parameters and backend: mean error over all rows, the worst p95, cost.
void print_summary(const std::vector<ResultRow>& rows);

// After a run: the summary (unless quiet), "N rows (F failed) in S s -> DIR", and the failed
// rows named on stderr (a failure is never a success: their metrics are empty; the first ten
// and a count of the rest). A closed pipe is a std::runtime_error saying the results are
// complete in DIR.
void print_run(const std::vector<ResultRow>& rows, double seconds, const std::filesystem::path& dir,
               bool quiet);

// The progress line on stderr, one call per view: "[3/12 0:07, ~0:21 left] bricks ... theta=45"
// (elapsed, and what is left at the mean pace of the views done so far), rewritten in place on
// a terminal, a line each otherwise.
std::function<void(size_t step, size_t steps, const std::string& what)> progress_printer();
// "shard 1/4: 3 of 12 units, 26.1% of the estimated cost (pxh merge OUT DIR... joins ...)".
void print_slice(const Slice& s, const nlohmann::json& shard_record);

// Clears a terminal's progress line (nothing when stderr is not a terminal).
void end_progress();

}  // namespace pxh

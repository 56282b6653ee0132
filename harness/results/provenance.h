// Provenance recorded with every run (Google Benchmark's context): what ran, where, built how.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

namespace pxh {

// Commit, compiler, library versions, CPU, threads, date, host.
nlohmann::json provenance(int threads);
// "0.1.0 (94f0f14-dirty)": the release and the source tree's git describe (what run.json
// records as pxh_version and pxh --version prints).
std::string pxh_version();
// The CPU's model name (/proc/cpuinfo), or "unknown".
std::string cpu_model();
std::string utc_timestamp(const char* fmt = "%Y-%m-%dT%H:%M:%SZ");

}  // namespace pxh

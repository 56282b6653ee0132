// The run record (harness/run/run_record.h): what run.json says of a run and of a slice, each
// backend's block as the backend wrote it and nothing of it at the top level, the files'
// checksums written last, and the readers' refusals of a record that is not one.
#include "harness/run/run_record.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "harness/core/error.h"
#include "harness/core/sha256.h"
#include "tests/cli_util.h"

namespace pxh {
namespace {

namespace fs = std::filesystem;

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "(none)";
}

Experiment small() {
    return parse_experiment(
        test::ExperimentToml("rec").theta("[0, 60]").field("fbm", 16).method("none").str(),
        "rec.toml");
}

TEST(RunRecord, RecordsTheRunAndEachBackendsOwnBlock) {
    const Experiment ex = small();
    RunInfo info;
    info.backends["cpu"] = {{"facts", nlohmann::json::object()}, {"mine", 1}};
    const nlohmann::json run = run_record(ex, {"pxh run rec.toml", 3}, info);
    EXPECT_EQ(run["command_line"], "pxh run rec.toml");
    EXPECT_EQ(run["threads"], 3);
    EXPECT_EQ(run["experiment"], ex.text);
    EXPECT_EQ(run["experiment_name"], "rec");
    EXPECT_EQ(run["inputs"][0]["sha256"], sha256_hex(ex.text));
    EXPECT_EQ(run["backends"]["cpu"]["mine"], 1);
    for (const char* k : {"gl", "gl_renderer", "shaders", "LP_NUM_THREADS", "files", "rows"})
        EXPECT_FALSE(run.contains(k)) << k;
}

TEST(RunRecord, FinishedRecordCountsRowsAndHashesTheFilesLast) {
    const fs::path dir = fs::temp_directory_path() / ("pxh_rec_" + std::to_string(getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "results.csv") << "a,b\n1,2\n";
    std::vector<ResultRow> rows(3);
    rows[1].fail("broken");
    nlohmann::json run = {{"command_line", "x"}};
    finish_run_record(run, rows, 1.5, dir);
    std::ifstream f(dir / "run.json");
    const nlohmann::json back = nlohmann::json::parse(f);
    EXPECT_EQ(back, run);
    EXPECT_EQ(back["rows"], 3);
    EXPECT_EQ(back["failed_rows"], 1);
    EXPECT_EQ(back["seconds"], 1.5);
    EXPECT_EQ(back["files"]["results.csv"]["sha256"], sha256_hex("a,b\n1,2\n"));
    EXPECT_FALSE(back["files"].contains("run.json"));
    fs::remove_all(dir);
}

TEST(RunRecord, ShardRecordNamesItsUnitsAndSelection) {
    const Experiment ex = small();
    const Slice s = make_slice(ex, {0, 1}, {});
    RunInfo info;
    info.views = {{{0, 0, 0, 0}, 1}, {{0, 0, 0, 1}, 1}};
    const nlohmann::json rec = shard_record(ex, s, {"", {"cpu"}, "", ""}, info);
    EXPECT_EQ(rec["index"], 0);
    EXPECT_EQ(rec["count"], 1);
    EXPECT_EQ(rec["units_total"], s.units.size());
    ASSERT_EQ(rec["units"].size(), 1u);
    EXPECT_EQ(rec["units"][0]["rows"], 2);
    EXPECT_EQ(rec["units"][0]["theta_deg"], nlohmann::json::array({0.0, 60.0}));
    EXPECT_EQ(rec["selection"]["backends"], nlohmann::json::array({"cpu"}));
    EXPECT_EQ(rec["selection"]["samples"], ex.samples);
    // Read back as pxh merge reads a slice's record.
    const nlohmann::json run = {{"shard", rec}};
    EXPECT_EQ(&shard_record_of(run, "s/run.json", "s"), &run["shard"]);
}

TEST(RunRecord, ReadersRefuseWhatIsNotARecord) {
    EXPECT_EQ(error_of([] {
                  parse_run_record("{ not json", "d/run.json");
              }).rfind("d/run.json: unreadable: ", 0),
              0u);
    EXPECT_EQ(error_of([] { parse_run_record("[1, 2]", "d/run.json"); }),
              "d/run.json: unreadable: not a JSON object");
    const nlohmann::json none = {{"rows", 1}};
    EXPECT_EQ(error_of([&] {
                  shard_record_of(none, "d/run.json", "d");
              }).rfind("d: is not a slice: its run.json has no shard record", 0),
              0u);
    const nlohmann::json partial =
        nlohmann::json::parse(R"({"shard": {"index": 0, "units_total": 2}})");
    EXPECT_EQ(error_of([&] { shard_record_of(partial, "d/run.json", "d"); }),
              "d/run.json: shard record without 'count'");
    EXPECT_EQ(error_of([] {
                  check_recordable("out\xff", "pxh run", "");
              }).rfind("--out: is not UTF-8", 0),
              0u);
}

}  // namespace
}  // namespace pxh

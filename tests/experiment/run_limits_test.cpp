// The run's size is estimated before any work and refused past --max-rows / --max-memory, with
// the estimate in the message; nothing is written.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <chrono>

#include "harness/core/error.h"
#include "harness/experiment/experiment.h"
#include "tests/cli_util.h"

namespace {

namespace fs = std::filesystem;

// 12 x 100 x 10 fbm parameter values: 12,000 fields from a 9-line file.
const std::string kHugeSweep =
    pxh::test::ExperimentToml()
        .samples(64)
        .theta("[0, 45]")
        .field("fbm", 64,
               "base_freq = 1\n"
               "octaves = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]\n"
               "seed = { from = 1, to = 100, step = 1 }\n"
               "gain = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95]")
        .method("parallax");

class RunLimits : public pxh::test::CliTest {};

TEST_F(RunLimits, RowsAndMemoryAreBoundedBeforeAnyWork) {
    std::string text = kHugeSweep;
    std::string seeds = "seed = [";
    for (int i = 1; i <= 100; ++i) seeds += std::to_string(i) + (i < 100 ? ", " : "]");
    text.replace(text.find("seed = { from = 1, to = 100, step = 1 }"), 39, seeds);
    const auto exp = write("huge.toml", text);
    const pxh::Experiment ex = pxh::load_experiment(exp);
    const pxh::RunEstimate est = pxh::estimate_run(ex, {});
    EXPECT_EQ(est.rows, 12u * 100 * 10 * 2);  // fields x views x 1 method x cpu float

    const auto t0 = std::chrono::steady_clock::now();
    pxh::test::CliResult r = pxh("run " + exp + " --max-rows 1000 --out " + (dir / "res").string());
    EXPECT_EQ(r.status, 2) << r.err;
    // Counted from the entry's factors while the file is read, before the fields are expanded.
    EXPECT_NE(r.err.find("huge.toml:5: this [[heightfields]] entry would write 24000 rows (12 "
                         "octaves x 10 gain x 100 seed x 1 scale x 1 bias x 2 theta x 1 phi x 1 "
                         "backend variant(s) x 1 method setting (at least)) > --max-rows 1000"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    // The rows alone (1 KiB each) past --max-memory: refused the same way.
    r = pxh("run " + exp + " --max-memory 1M --out " + (dir / "res").string());
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("24000 rows"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("need more than --max-memory 1.0 MiB"), std::string::npos) << r.err;
    // Rows that fit, a run that does not (the process and the fields): the estimate's message.
    r = pxh("run " + exp + " --max-memory 50M --out " + (dir / "res").string());
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("of memory, over the limit of 50.0 MiB"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--max-memory"), std::string::npos) << r.err;
    r = pxh("run " + exp + " --max-memory 12parsecs --out " + (dir / "res").string());
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("is not a size"), std::string::npos) << r.err;
    // Refused from the estimate alone: seconds, not the 12,000 fields.
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(60));
    EXPECT_FALSE(fs::exists(dir / "res"));
}

}  // namespace

namespace {

// Fuzzer findings (fuzz/corpus/experiment/range_to_inf.toml, fbm_huge_lattice.toml): an
// infinite angle range ran as an empty successful run, and a fine fbm lattice asked for
// terabytes. Both are refused when the file is read.
TEST(RunLimitsParse, InfiniteRangesAndHugeLatticesAreRefused) {
    const std::string tail =
        "[[heightfields]]\ngenerator = \"sine\"\nsize = 4\n[[methods]]\nname = \"parallax\"\n";
    for (const std::string to : {"inf", "nan", "1e300"})
        EXPECT_THROW(
            pxh::parse_experiment(
                "[views]\ntheta_deg = { from = 0, to = " + to + ", step = 1 }\n" + tail, "x.toml"),
            pxh::InputError)
            << to;
    EXPECT_EQ(pxh::parse_experiment(
                  "[views]\ntheta_deg = { from = 0, to = 80, step = 10 }\n" + tail, "x.toml")
                  .theta_deg.size(),
              9u);
    const std::string fbm =
        "[views]\ntheta_deg = [0]\n[[heightfields]]\ngenerator = \"fbm\"\nsize = 8\n";
    try {
        pxh::parse_experiment(fbm + "base_freq = 256\noctaves = 12\n[[methods]]\nname = \"none\"\n",
                              "x.toml");
        ADD_FAILURE() << "accepted";
    } catch (const pxh::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("524288^2 lattice"), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).rfind("x.toml:", 0), 0u) << e.what();
    }
    // The largest accepted: base_freq 128, 6 octaves = 4096.
    EXPECT_NO_THROW(pxh::parse_experiment(
        fbm + "base_freq = 128\noctaves = 6\n[[methods]]\nname = \"none\"\n", "x.toml"));
}

}  // namespace

namespace {

// Fuzzer finding (fuzz/corpus/image/png_text_chunk_length_2gb): a 344-byte PNG whose tEXt chunk
// claims 2 GB made libpng allocate 2 GB (through the run-size estimate and the loader) before
// failing. Now refused from the chunk walk, within a small peak memory.
class RunLimitsImages : public pxh::test::CliTest {};

TEST_F(RunLimitsImages, PngChunkLengthsAreCheckedBeforeLibpng) {
    const std::string seed =
        slurp(std::string(PXH_SOURCE_DIR) + "/fuzz/corpus/image/png_text_chunk_length_2gb");
    ASSERT_GT(seed.size(), 100u);
    write("evil.png", seed.substr(1));  // the fuzz input's first byte picks the channel
    const auto exp = write("e.toml",
                           "[views]\ntheta_deg = [0]\n[[heightfields]]\nfile = \"evil.png\"\n"
                           "[[methods]]\nname = \"none\"\n");
    const std::string cmd = std::string(PXH_BINARY) + " run " + exp + " --quiet --out " +
                            (dir / "res").string() + " 2> " + (dir / "err.txt").string();
    const pid_t pid = fork();
    if (pid == 0) {
        execl("/bin/sh", "sh", "-c", cmd.c_str(), (char*)nullptr);
        _exit(127);
    }
    int status = 0;
    struct rusage ru {};
    ASSERT_EQ(wait4(pid, &status, 0, &ru), pid);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 2) << status;
    const std::string err = slurp(dir / "err.txt");
    EXPECT_NE(err.find("PNG chunk 'tEXt'"), std::string::npos) << err;
    EXPECT_LT(ru.ru_maxrss, 600 * 1024) << "peak RSS in KiB";  // was about 2 GB
    EXPECT_FALSE(fs::exists(dir / "res"));
}

}  // namespace

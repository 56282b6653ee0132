// Experiment files through the pxh binary: warnings on stderr, one-line errors, FIFOs, names
// that would escape the output folder, and the memory estimate against a measured run.
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <algorithm>

#include "harness/experiment/experiment.h"
#include "tests/cli_util.h"

extern char** environ;

namespace pxh {
namespace {

namespace fs = std::filesystem;

class ExperimentCli : public test::CliTest {};

size_t count_lines(const std::string& s) { return size_t(std::count(s.begin(), s.end(), '\n')); }

TEST_F(ExperimentCli, WarningsGoToStderrOneLineEach) {
    const std::string exp = write("w.toml", R"(name = "w"
samples = 4
timing_repeats = 0
[views]
theta_deg = [0.5, 0.2]
phi_deg = [-90]
[[heightfields]]
generator = "flat"
size = 8
[[methods]]
name = "none"
)");
    const auto r = pxh("run " + exp + " --out " + (dir / "out").string() + " --quiet");
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("pxh: warning: " + exp + ":5: theta_deg values are all below 1.6"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("pxh: warning: " + exp + ":5: theta_deg is not in increasing order"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("pxh: warning: " + exp +
                         ":6: phi_deg outside [0, 360) normalised: -90 -> 270\n"),
              std::string::npos)
        << r.err;
    size_t warnings = 0;
    std::stringstream ss(r.err);
    for (std::string line; std::getline(ss, line);)
        warnings += line.rfind("pxh: warning: ", 0) == 0;
    EXPECT_EQ(warnings, 3u) << r.err;
    // The rows use the normalised, sorted views.
    const std::string csv = slurp(dir / "out" / "results.csv");
    EXPECT_NE(csv.find(",0.2,270,"), std::string::npos) << csv;
    EXPECT_NE(csv.find(",0.5,270,"), std::string::npos) << csv;
}

TEST_F(ExperimentCli, TomlSyntaxErrorIsOneLine) {
    const std::string exp = write("bad.toml", "samples = fa\n[views]\ntheta_deg = [0]\n");
    const auto r = pxh("run " + exp + " --out " + (dir / "out").string());
    EXPECT_EQ(r.status, 2);
    EXPECT_EQ(count_lines(r.err), 1u) << r.err;
    EXPECT_EQ(r.err.rfind("pxh: error: " + exp + ":1: TOML syntax error: ", 0), 0u) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST_F(ExperimentCli, MissingImageNamesTheExperimentLine) {
    const std::string exp = write("e.toml", R"(samples = 4
[views]
theta_deg = [0]
[[heightfields]]
file = "maps/missing.png"
[[methods]]
name = "none"
)");
    const auto r = pxh("run " + exp + " --out " + (dir / "out").string());
    EXPECT_EQ(r.status, 2);
    EXPECT_EQ(r.err, "pxh: error: " + exp + ":4: heightfield file '" +
                         (dir / "maps/missing.png").string() +
                         "' (paths are relative to the experiment file): no such file\n");
    EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST_F(ExperimentCli, FifoIsRefusedNotRead) {
    const std::string fifo = (dir / "fifo.toml").string();
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    // Before the fix pxh blocks opening the FIFO; timeout ends it with status 124.
    const auto r = pxh_timeout("run " + fifo + " --out " + (dir / "out").string());
    EXPECT_EQ(r.status, 2);
    EXPECT_EQ(r.err, "pxh: error: " + fifo +
                         ": not a regular file (a FIFO, socket "
                         "or device?): an experiment must be a regular file\n");
}

TEST_F(ExperimentCli, ExperimentNameCannotEscapeTheResultsFolder) {
    // Run from a deep folder so that even an escaping name would land inside dir.
    const fs::path cwd = dir / "a" / "b" / "c" / "d";
    fs::create_directories(cwd);
    const std::string exp = write("e.toml", test::ExperimentToml("../../../escaped")
                                                .samples(4)
                                                .theta("[0]")
                                                .field("flat", 8)
                                                .method("none"));
    const auto r = sh("cd " + cwd.string() + " && " + PXH_BINARY + " run " + exp + " --quiet");
    EXPECT_EQ(r.status, 2);
    EXPECT_EQ(r.err, "pxh: error: " + exp +
                         ":1: experiment name '../../../escaped' "
                         "contains '/' or '\\': it names the output folder, so it must "
                         "be a plain file name\n");
    for (const auto& e : fs::recursive_directory_iterator(dir))
        EXPECT_EQ(e.path().filename().string().find("escaped"), std::string::npos) << e.path();
}

// Peak resident memory (bytes) of `pxh ARGS...` run directly (not through a shell).
size_t peak_rss_of(const std::vector<std::string>& args) {
    std::vector<char*> argv;
    std::string bin = PXH_BINARY;
    argv.push_back(bin.data());
    std::vector<std::string> copy = args;
    for (auto& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid;
    if (posix_spawn(&pid, PXH_BINARY, nullptr, nullptr, argv.data(), environ) != 0) return 0;
    int status = 0;
    struct rusage ru {};
    if (wait4(pid, &status, 0, &ru) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return 0;
    return size_t(ru.ru_maxrss) * 1024;  // kilobytes on Linux
}

TEST_F(ExperimentCli, MemoryEstimateBoundsAMeasuredRun) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "ASan's shadow memory inflates the peak RSS this test measures";
#endif
    // A large field dominates: its floats, the exact tracer's mipmap and Embree's copy.
    const std::string exp =
        write("m.toml", test::ExperimentToml().theta("[30]").field("fbm", 2048).method("none"));
    const RunEstimate est = estimate_run(parse_experiment(slurp(exp), exp), {});
    EXPECT_EQ(est.rows, 1u);
    const size_t measured = peak_rss_of({"run", exp, "--out", (dir / "out").string(), "--quiet"});
    ASSERT_GT(measured, 0u);
    // An estimate for refusing runs: at least what the run took, and not wildly more.
    EXPECT_GE(est.peak_bytes, measured) << est.detail;
    EXPECT_LE(double(est.peak_bytes), 1.3 * double(measured))
        << est.detail << "; measured " << measured / (1 << 20) << " MiB";
}

}  // namespace
}  // namespace pxh

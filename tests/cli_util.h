// The pxh binary as a test sees it: a per-test scratch folder, files written into it, and
// `pxh ARGS` run through the shell with its exit status, stdout and stderr.
#pragma once
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace pxh::test {

struct CliResult {
    int status;
    std::string out, err;
};

class CliTest : public ::testing::Test {
  protected:
    std::filesystem::path dir =
        std::filesystem::temp_directory_path() /
        ("pxh_cli_test_" + std::to_string(::getpid()) + "_" +
         ::testing::UnitTest::GetInstance()->current_test_info()->test_suite_name() + "_" +
         ::testing::UnitTest::GetInstance()->current_test_info()->name());
    void SetUp() override {
        std::filesystem::remove_all(dir);
        std::filesystem::create_directories(dir);
    }
    void TearDown() override { std::filesystem::remove_all(dir); }

    static std::string slurp(const std::filesystem::path& p) {
        std::ifstream f(p, std::ios::binary);
        std::stringstream ss;
        ss << f.rdbuf();
        return ss.str();
    }
    std::string write(const std::string& name, const std::string& text) {
        std::ofstream(dir / name, std::ios::binary) << text;
        return (dir / name).string();
    }
    // Runs `pxh ARGS` (ARGS is passed through the shell as written).
    CliResult pxh(const std::string& args) {
        const std::string cmd = std::string(PXH_BINARY) + " " + args + " >" +
                                (dir / "out.txt").string() + " 2>" + (dir / "err.txt").string();
        const int rc = std::system(cmd.c_str());
        return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, slurp(dir / "out.txt"),
                slurp(dir / "err.txt")};
    }
};

// Long enough to be interrupted: many views of a large field (signal and lock tests).
inline constexpr const char* kSlowExperiment = R"(
name = "slow"
samples = 256
timing_repeats = 3
[views]
theta_deg = { from = 0, to = 85, step = 1 }
phi_deg = [0, 10, 20, 30, 40, 50]
[[heightfields]]
generator = "fbm"
size = 512
[[methods]]
name = "relief"
)";

// A thresholds file every small run passes (parallax err_p95 under 1000 texels).
inline constexpr const char* kLooseLimits = R"(
[[limit]]
method = "parallax"
column = "err_p95"
max = 1000
)";

}  // namespace pxh::test

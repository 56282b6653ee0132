// The pxh binary as a test sees it: a scratch folder (per test, or per suite for a suite that
// runs pxh once), files written into it, `pxh ARGS` or any command run through the shell with
// its exit status, stdout and stderr, and the inline experiments many suites write, built by
// ExperimentToml instead of typed again.
#pragma once
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace pxh::test {

struct CliResult {
    int status;
    std::string out, err;
};

// The whole file as bytes ("" when it cannot be read).
inline std::string slurp(const std::filesystem::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

// A file of the source tree, by its path relative to the repository root.
inline std::string source_file(const std::string& rel) {
    return slurp(std::filesystem::path(PXH_SOURCE_DIR) / rel);
}

// S quoted for the shell: as it is, whatever quotes or shell syntax it holds.
inline std::string shell_quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

// Runs CMD through the shell, stdout into OUT and stderr into ERR (the same file: both into it);
// the exit status, -1 when the shell did not exit normally.
inline int shell(const std::string& cmd, const std::filesystem::path& out,
                 const std::filesystem::path& err) {
    const std::string redirect =
        out == err ? " >" + out.string() + " 2>&1" : " >" + out.string() + " 2>" + err.string();
    const int rc = std::system((cmd + redirect).c_str());
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

// Runs CMD through the shell with its output in DIR/out.txt and DIR/err.txt.
inline CliResult shell_in(const std::filesystem::path& dir, const std::string& cmd) {
    const int status = shell(cmd, dir / "out.txt", dir / "err.txt");
    return {status, slurp(dir / "out.txt"), slurp(dir / "err.txt")};
}

// `pxh ARGS` (ARGS passed through the shell as written), its output in DIR/out.txt, DIR/err.txt.
inline CliResult pxh_in(const std::filesystem::path& dir, const std::string& args) {
    return shell_in(dir, std::string(PXH_BINARY) + " " + args);
}

// A scratch folder under the system's temporary folder, named after PREFIX and this process,
// created empty.
inline std::filesystem::path fresh_dir(const std::string& prefix) {
    const auto d = std::filesystem::temp_directory_path() /
                   ("pxh_" + prefix + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}

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

    static std::string slurp(const std::filesystem::path& p) { return test::slurp(p); }
    std::string write(const std::string& name, const std::string& text) {
        std::ofstream(dir / name, std::ios::binary) << text;
        return (dir / name).string();
    }
    // Runs `pxh ARGS` (ARGS is passed through the shell as written).
    CliResult pxh(const std::string& args) { return pxh_in(dir, args); }
    // Runs any shell command, its output in dir/out.txt and dir/err.txt.
    CliResult sh(const std::string& cmd) { return shell_in(dir, cmd); }
    // `timeout SECONDS pxh ARGS`: a hang is exit status 124, not a hung test.
    CliResult pxh_timeout(const std::string& args, int seconds = 20) {
        return sh("timeout " + std::to_string(seconds) + " " + PXH_BINARY + " " + args);
    }
};

// A suite that runs pxh once for all its tests (in SetUpTestSuite, through run_or_record): one
// scratch folder for the suite (Suite::kDirName), removed after it. A failed set-up fails every
// test of the suite (SetUp), instead of a fatal failure in SetUpTestSuite that would make gtest
// skip the tests and ctest count them as skipped.
template <typename Suite>
class SuiteCliTest : public ::testing::Test {
  protected:
    static inline std::filesystem::path dir;
    static inline std::string setup_error;  // why the suite's set-up failed ("" when it did not)
    static void make_dir() {
        dir = fresh_dir(Suite::kDirName);
        setup_error.clear();
    }
    static void TearDownTestSuite() { std::filesystem::remove_all(dir); }
    void SetUp() override { ASSERT_EQ(setup_error, "") << "suite set-up failed"; }

    static std::string write(const std::string& name, const std::string& text) {
        std::ofstream(dir / name, std::ios::binary) << text;
        return (dir / name).string();
    }
    static CliResult pxh(const std::string& args) { return pxh_in(dir, args); }
    static int run(const std::string& args) { return pxh(args).status; }
    // Set-up: `pxh ARGS`, its failure recorded in setup_error.
    static void run_or_record(const std::string& args) {
        const CliResult r = pxh(args);
        if (r.status != 0)
            setup_error += "`pxh " + args + "` exited " + std::to_string(r.status) + ": " + r.err;
    }
    static std::string slurp(const std::filesystem::path& p) { return test::slurp(p); }
    static std::string d(const char* name) { return (dir / name).string(); }
};

// An inline experiment, section by section, for the small runs many suites make:
//   ExperimentToml("tiny").theta("[0, 45, 80]").field("fbm", 16).method("pom", "layers = 8")
// writes name, samples (8 unless set), timing_repeats (0 unless set), the other top-level keys
// in the order set, [views] (theta_deg, then phi_deg if set, then view() keys), one
// [[heightfields]] per field() or scan() and one [[methods]] per method(), in the order called,
// then tail() as it is.
class ExperimentToml {
  public:
    explicit ExperimentToml(const std::string& name = "") {
        if (!name.empty()) set("name", "\"" + name + "\"");
        set("samples", "8");
        set("timing_repeats", "0");
    }
    // A top-level key, VALUE as TOML text (replaces an earlier value of the key, in its place).
    ExperimentToml& set(const std::string& key, const std::string& value) {
        for (auto& kv : top_)
            if (kv.first == key) {
                kv.second = value;
                return *this;
            }
        top_.emplace_back(key, value);
        return *this;
    }
    ExperimentToml& samples(int n) { return set("samples", std::to_string(n)); }
    ExperimentToml& timing_repeats(int n) { return set("timing_repeats", std::to_string(n)); }
    // BACKENDS as TOML list items: backends("\"cpu\", \"glsl\"").
    ExperimentToml& backends(const std::string& items) {
        return set("backends", "[" + items + "]");
    }
    ExperimentToml& theta(const std::string& value) {
        theta_ = value;
        return *this;
    }
    ExperimentToml& phi(const std::string& value) {
        phi_ = value;
        return *this;
    }
    // Another [views] key, VALUE as TOML text, after theta_deg and phi_deg in the order set:
    // view("camera", "\"perspective\"").view("distance", "[1.5, 4]").
    ExperimentToml& view(const std::string& key, const std::string& value) {
        views_ += key + " = " + value + "\n";
        return *this;
    }
    // A generated field; EXTRA: more lines of its section ("scale = 0.06\nbias = 1.0").
    ExperimentToml& field(const std::string& generator, int size, const std::string& extra = "") {
        fields_ += "[[heightfields]]\ngenerator = \"" + generator +
                   "\"\nsize = " + std::to_string(size) + "\n" + lines(extra);
        return *this;
    }
    // A committed scanned field (heightfields/scanned/NAME); EXTRA as for field().
    ExperimentToml& scan(const std::string& name, const std::string& extra = "") {
        fields_ += "[[heightfields]]\nscan = \"" + name + "\"\n" + lines(extra);
        return *this;
    }
    // A method; EXTRA: more lines of its section ("layers = [8, 32]").
    ExperimentToml& method(const std::string& name, const std::string& extra = "") {
        methods_ += "[[methods]]\nname = \"" + name + "\"\n" + lines(extra);
        return *this;
    }
    // Text written after the methods as it is ([render], [[metrics]], ...).
    ExperimentToml& tail(const std::string& text) {
        tail_ += lines(text);
        return *this;
    }
    std::string str() const {
        std::string s;
        for (const auto& kv : top_) s += kv.first + " = " + kv.second + "\n";
        s += "[views]\ntheta_deg = " + theta_ + "\n";
        if (!phi_.empty()) s += "phi_deg = " + phi_ + "\n";
        return s + views_ + fields_ + methods_ + tail_;
    }
    operator std::string() const { return str(); }

  private:
    static std::string lines(const std::string& text) {
        return text.empty() || text.back() == '\n' ? text : text + "\n";
    }
    std::vector<std::pair<std::string, std::string>> top_;
    std::string theta_ = "[0, 45, 80]", phi_, views_, fields_, methods_, tail_;
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

// The small run of the folder tests: three views of one small fbm field, parallax and pom.
inline ExperimentToml tiny_experiment() {
    return ExperimentToml("tiny").samples(16).field("fbm", 16).method("parallax").method("pom");
}

}  // namespace pxh::test

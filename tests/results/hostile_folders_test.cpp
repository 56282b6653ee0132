// Hostile folders and inputs through the pxh binary: a leftover partial folder is never adopted
// or certified, --force removes only pxh's own files, everything is created without following
// links, every signal that ends a run cleans up, and bad arguments are refused before any work.
// (The parser's sweep limits and checks: tests/experiment/parse_limits_test.cpp; the safe-file
// helpers: tests/core/safe_files_test.cpp.)
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <functional>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>

#include "harness/core/error.h"
#include "harness/core/safe_files.h"
#include "harness/experiment/experiment.h"
#include "tests/cli_util.h"

namespace {

namespace fs = std::filesystem;
using pxh::test::CliResult;

const std::string kTiny =
    pxh::test::tiny_experiment().tail("[render]\nheightfields = [\"fbm\"]\ntheta_deg = [45]");

class HostileFolders : public pxh::test::CliTest {
  protected:
    // Names in `dir` (not recursive), sorted.
    std::set<std::string> names() {
        std::set<std::string> out;
        for (const auto& e : fs::directory_iterator(dir)) out.insert(e.path().filename().string());
        return out;
    }
    // Anything an unfinished run leaves beside its folder: partial/replaced folders, the lock.
    std::vector<std::string> leftovers() {
        std::vector<std::string> out;
        for (const auto& n : names())
            if (n.find(".partial-") != std::string::npos ||
                n.find(".replaced-") != std::string::npos ||
                n.find(".pxh-lock") != std::string::npos)
                out.push_back(n);
        return out;
    }
    // Runs PXH with argv in a child whose set-up (signals, limits, descriptors) `prepare` does
    // after fork; returns the wait status, stderr in err.txt.
    int spawn(const std::vector<std::string>& args, const std::function<void()>& prepare,
              pid_t* child = nullptr, bool wait_for_it = true) {
        const std::string err = (dir / "err.txt").string();
        const pid_t pid = fork();
        if (pid == 0) {
            const int fd = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            ::dup2(fd, 2);
            const int null = ::open("/dev/null", O_WRONLY);
            ::dup2(null, 1);
            prepare();
            std::vector<char*> argv{const_cast<char*>(PXH_BINARY)};
            for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
            argv.push_back(nullptr);
            execv(PXH_BINARY, argv.data());
            _exit(127);
        }
        if (child) *child = pid;
        int status = 0;
        if (wait_for_it) waitpid(pid, &status, 0);
        return status;
    }
    // `pxh ARGS` under a file-size limit of BYTES, SIGXFSZ at its default (which ends a process
    // silently): pxh ignores the signal, so the write fails and is named (exit 1). Its stderr.
    std::string under_file_size_limit(const std::vector<std::string>& args, rlim_t bytes) {
        const int status = spawn(args, [bytes] {
            signal(SIGXFSZ, SIG_DFL);
            const rlimit lim{bytes, bytes};
            setrlimit(RLIMIT_FSIZE, &lim);
        });
        const std::string err = slurp(dir / "err.txt");
        EXPECT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
        EXPECT_EQ(WEXITSTATUS(status), 1) << err;
        EXPECT_NE(err.find("write failed: File too large"), std::string::npos) << err;
        return err;
    }
};

// A leftover DIR.partial-PID of the very pid the run gets (made by the child itself before it
// becomes pxh), holding a foreign file and a link, is neither adopted nor touched; pxh check
// never certifies such a folder, even one holding a complete run's files.
TEST_F(HostileFolders, LeftoverPartialOfTheSamePidIsNotAdopted) {
    const auto exp = write("tiny.toml", kTiny);
    const fs::path out = dir / "res";
    write("secret.txt", "do not touch");
    std::string premade;
    const int status = spawn({"run", exp, "--quiet", "--out", out.string()}, [&] {
        const fs::path p = out.string() + ".partial-" + std::to_string(getpid());
        fs::create_directory(p);
        std::ofstream(p / "foreign.txt") << "stale";
        fs::create_symlink(dir / "secret.txt", p / "results.csv");
        fs::create_symlink(dir / "secret.txt", p / "run.json");
    });
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << slurp(dir / "err.txt");
    // The leftover as it was: the same three entries, the link still pointing at the file.
    std::vector<fs::path> pre;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().filename().string().rfind("res.partial-", 0) == 0) pre.push_back(e.path());
    ASSERT_EQ(pre.size(), 1u);
    std::set<std::string> inside;
    for (const auto& e : fs::directory_iterator(pre[0])) inside.insert(e.path().filename());
    EXPECT_EQ(inside, (std::set<std::string>{"foreign.txt", "results.csv", "run.json"}));
    EXPECT_TRUE(fs::is_symlink(pre[0] / "results.csv"));
    EXPECT_EQ(slurp(dir / "secret.txt"), "do not touch");
    EXPECT_EQ(slurp(pre[0] / "foreign.txt"), "stale");
    // The run's folder holds only what the run wrote.
    EXPECT_FALSE(fs::exists(out / "foreign.txt"));
    EXPECT_FALSE(fs::is_symlink(out / "results.csv"));
    const auto limits = write("limits.toml", pxh::test::kLooseLimits);
    CliResult r = pxh("check " + out.string() + " --thresholds " + limits);
    EXPECT_EQ(r.status, 0) << r.err;

    // A leftover holding a complete run's files verifies byte for byte, and is still refused.
    const fs::path left = dir / "old.partial-4242-0a1b2c3d";
    fs::copy(out, left, fs::copy_options::recursive);
    for (const std::string extra : {"", " --accept-edited"}) {
        r = pxh("check " + left.string() + " --thresholds " + limits + extra);
        EXPECT_EQ(r.status, 2) << r.out;
        EXPECT_NE(r.err.find("partial folder of a pxh run that did not finish"), std::string::npos)
            << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
    r = pxh("check " + (dir / "old.replaced-4242-0a1b2c3d").string() + " --thresholds " + limits);
    EXPECT_EQ(r.status, 2);  // no such folder
    fs::rename(left, dir / "old.replaced-4242-0a1b2c3d");
    r = pxh("check " + (dir / "old.replaced-4242-0a1b2c3d").string() + " --thresholds " + limits);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("interrupted --force run"), std::string::npos) << r.err;
}

// --force removes only what run.json records pxh wrote (byte for byte) and report/: a file of
// the user's in pictures/, a recorded picture changed since, or a link in maps/ stops it.
TEST_F(HostileFolders, ForceRemovesOnlyPxhsOwnFiles) {
    const auto exp = write("tiny.toml", kTiny);
    const std::string out = (dir / "res").string();
    CliResult r = pxh("run " + exp + " --quiet --maps --out " + out);
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string run_json = slurp(dir / "res" / "run.json");
    const auto run = nlohmann::json::parse(run_json);
    std::string picture;
    for (const auto& [rel, rec] : run["files"].items())
        if (rel.rfind("pictures/", 0) == 0) picture = rel;
    ASSERT_FALSE(picture.empty()) << run["files"].dump();
    r = pxh("report " + out + " --no-plots");  // report/ and its manifest.txt
    ASSERT_EQ(r.status, 0) << r.err;
    ASSERT_TRUE(fs::is_regular_file(dir / "res/report/manifest.txt"));
    write("secret.txt", "mine");
    struct Case {
        std::string name;
        std::function<void()> make, undo;
        std::string expect;
    };
    const std::string saved = slurp(dir / "res" / picture);
    const std::vector<Case> cases = {
        {"a file of the user's in pictures/", [&] { write("res/pictures/mine.png", "mine"); },
         [&] { fs::remove(dir / "res/pictures/mine.png"); },
         "'pictures/mine.png', which pxh did not write there"},
        {"a folder of the user's in maps/",
         [&] {
             fs::create_directories(dir / "res/maps/sub");
             write("res/maps/sub/x.txt", "x");
         },
         [&] { fs::remove_all(dir / "res/maps/sub"); }, "'maps/sub/x.txt'"},
        {"a recorded picture changed", [&] { write("res/" + picture, "edited"); },
         [&] { write("res/" + picture, saved); }, "has changed since pxh wrote it"},
        {"a link in maps/",
         [&] { fs::create_symlink(dir / "secret.txt", dir / "res/maps/link.png"); },
         [&] { fs::remove(dir / "res/maps/link.png"); }, "a symbolic link pxh did not write"},
        {"a file of the user's in report/", [&] { write("res/report/notes.txt", "mine"); },
         [&] { fs::remove(dir / "res/report/notes.txt"); },
         "'report/notes.txt', which pxh report did not write there"},
    };
    for (const auto& c : cases) {
        c.make();
        r = pxh("run " + exp + " --quiet --force --out " + out);
        EXPECT_EQ(r.status, 2) << c.name;
        EXPECT_NE(r.err.find(c.expect), std::string::npos) << c.name << ": " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_EQ(slurp(dir / "res" / "run.json"), run_json) << c.name;
        EXPECT_TRUE(leftovers().empty()) << c.name;
        c.undo();
    }
    EXPECT_EQ(slurp(dir / "secret.txt"), "mine");
    r = pxh("run " + exp + " --quiet --force --out " + out);
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(leftovers().empty());
    EXPECT_EQ(names(),
              (std::set<std::string>{"err.txt", "out.txt", "res", "secret.txt", "tiny.toml"}));
}

// Every signal that ends a process by default (but SIGKILL and the faults) removes the partial
// folder and the lock, and exits 128 + signal.
TEST_F(HostileFolders, EverySignalCleansUp) {
    const auto exp = write("slow.toml", pxh::test::kSlowExperiment);
    for (int sig : {SIGUSR1, SIGALRM, SIGQUIT, SIGUSR2, SIGXCPU}) {
        const fs::path out = dir / ("res" + std::to_string(sig));
        pid_t pid = 0;
        spawn(
            {"run", exp, "--quiet", "--out", out.string()}, [] {}, &pid, false);
        const auto t0 = std::chrono::steady_clock::now();
        while (leftovers().size() < 2 &&
               std::chrono::steady_clock::now() - t0 < std::chrono::seconds(30))
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        ASSERT_EQ(leftovers().size(), 2u) << "the run never started";  // partial folder + lock
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        kill(pid, sig);
        int status = 0;
        waitpid(pid, &status, 0);
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 128 + sig)
            << strsignal(sig) << ": " << status;
        EXPECT_FALSE(fs::exists(out)) << sig;
        EXPECT_TRUE(leftovers().empty()) << strsignal(sig) << ": " << leftovers()[0];
        EXPECT_NE(slurp(dir / "err.txt").find("interrupted (signal " + std::to_string(sig)),
                  std::string::npos)
            << slurp(dir / "err.txt");
    }
}

// A file-size limit with SIGXFSZ at its default (which ends a process silently): pxh ignores
// it, so the write fails, is named, and nothing is left.
TEST_F(HostileFolders, FileSizeLimitFailsTheWriteCleanly) {
    const auto exp = write("tiny.toml", kTiny);
    const fs::path out = dir / "res";
    const std::string err =
        under_file_size_limit({"run", exp, "--quiet", "--out", out.string()}, 1024);
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_TRUE(leftovers().empty());
}

// `pxh run ... | head -c 20` with the reader gone: the results are complete (and verify), the
// lost output is an error, and nothing is left beside the folder.
TEST_F(HostileFolders, ClosedPipeIsReportedNotFatal) {
    const auto exp = write("tiny.toml", kTiny);
    const fs::path out = dir / "res";
    int fds[2];
    ASSERT_EQ(pipe(fds), 0);
    close(fds[0]);  // no reader: every write to the pipe fails
    const int status = spawn({"run", exp, "--out", out.string()}, [&] {
        signal(SIGPIPE, SIG_DFL);
        dup2(fds[1], 1);
    });
    close(fds[1]);
    const std::string err = slurp(dir / "err.txt");
    ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
    EXPECT_EQ(WEXITSTATUS(status), 1) << err;
    EXPECT_NE(err.find("cannot write to standard output"), std::string::npos) << err;
    EXPECT_TRUE(leftovers().empty());
    const auto limits = write("limits.toml", pxh::test::kLooseLimits);
    EXPECT_EQ(pxh("check " + out.string() + " --thresholds " + limits).status, 0);
    // Through the shell, its output cut short by a pipe that closes early.
    const std::string cmd = std::string(PXH_BINARY) + " run " + exp + " --out " +
                            (dir / "res2").string() + " 2>&1 | head -c 20 > /dev/null";
    std::system(cmd.c_str());
    EXPECT_TRUE(leftovers().empty());
    EXPECT_TRUE(fs::exists(dir / "res2" / "run.json"));
}

// pxh bench --out: a new file of its own, never through a link or over anyone's file; a
// device is refused before any measurement; a write error is named.
TEST_F(HostileFolders, BenchOutIsANewFileOfItsOwn) {
    const std::string bench = "bench --sizes 16 --theta 30 --samples 8 --repeats 1 --threads 1";
    write("mine.json", "{\"mine\": 1}");
    fs::create_symlink(dir / "mine.json", dir / "link.json");
    struct Case {
        std::string out, expect;
    };
    for (const Case& c : std::vector<Case>{
             {"/dev/full", "exists and is not a regular file"},
             {(dir / "link.json").string(), "is a symbolic link"},
             {(dir / "mine.json").string(), "is not a pxh bench file"},
             {"''", "--out: is empty"},
         }) {
        const CliResult r = pxh(bench + " --out " + c.out + " --force");
        EXPECT_EQ(r.status, 2) << c.out;
        EXPECT_NE(r.err.find(c.expect), std::string::npos) << c.out << ": " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_EQ(r.out, "") << "measured before refusing: " << r.out;
    }
    EXPECT_EQ(slurp(dir / "mine.json"), "{\"mine\": 1}");
    const std::string out = (dir / "b.json").string();
    CliResult r = pxh(bench + " --out " + out);
    ASSERT_EQ(r.status, 0) << r.err;
    const auto doc = nlohmann::json::parse(slurp(out));
    EXPECT_EQ(doc["results"].size(), 1u);
    r = pxh(bench + " --out " + out);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("pass --force"), std::string::npos) << r.err;
    EXPECT_EQ(pxh(bench + " --out " + out + " --force").status, 0);
    // A file-size limit: the write fails, is named, and no file is left.
    under_file_size_limit({"bench", "--sizes", "16", "--theta", "30", "--samples", "8", "--repeats",
                           "1", "--threads", "1", "--out", (dir / "big.json").string()},
                          512);
    for (const auto& n : names()) EXPECT_EQ(n.find("big.json"), std::string::npos) << n;
}

// Command-line values refused with one line before any work: --out '', --max-rows -1, a
// non-UTF-8 --out, a non-UTF-8 experiment (its line named).
TEST_F(HostileFolders, BadArgumentsAndTextAreRefusedBeforeWork) {
    const auto exp = write("tiny.toml", kTiny);
    std::string latin1 = kTiny;
    latin1.insert(latin1.find("[views]"), "# caf\xe9 au lait\n");
    const auto bad = write("latin1.toml", latin1);
    std::string named = kTiny;
    named.replace(named.find("\"tiny\""), 6, "\"t\xffny\"");
    const auto bad_name = write("badname.toml", named);
    struct Case {
        std::string args, expect;
    };
    for (const Case& c : std::vector<Case>{
             {"run " + exp + " --quiet --out ''", "--out: is empty"},
             {"run " + exp + " --quiet --max-rows -1 --out " + (dir / "r").string(),
              "--max-rows: -1 is not a row count"},
             {"run " + exp + " --quiet --out " + (dir / "r\xe9").string(), "--out: is not UTF-8"},
             {"run " + exp + " --quiet --backend foo --out " + (dir / "r").string(),
              "--backend: unknown backend 'foo'"},
             {"run " + bad + " --quiet --out " + (dir / "r").string(),
              bad + ":4: column 6: byte 0xE9 is not UTF-8"},
             {"run " + bad_name + " --quiet --out " + (dir / "r").string(),
              bad_name + ":1: column 10: byte 0xFF is not UTF-8"},
         }) {
        const CliResult r = pxh(c.args);
        EXPECT_EQ(r.status, 2) << c.args;
        EXPECT_NE(r.err.find(c.expect), std::string::npos) << c.args << ": " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
    EXPECT_EQ(names(), (std::set<std::string>{"badname.toml", "err.txt", "latin1.toml", "out.txt",
                                              "tiny.toml"}));
}

// A parameter combination the parser lets through but that gives no answer at a view (march
// mix_negated with layers_min = 2 layers_max: 0 layers head-on): that row fails, naming why;
// the other view's row is measured.
TEST_F(HostileFolders, RowWithEveryNonFiniteSampleFails) {
    const auto exp =
        write("neg.toml", pxh::test::ExperimentToml().theta("[0, 45]").field("fbm", 16).method(
                              "march", "count = \"mix_negated\"\nlayers_min = 16\nlayers_max = 8"));
    const CliResult r = pxh("run " + exp + " --quiet --out " + (dir / "res").string());
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("theta 0 phi 0 | cpu/float: every sample (64) gave a non-finite uv"),
              std::string::npos)
        << r.err;
    const std::string csv = slurp(dir / "res" / "results.csv");
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3);
    EXPECT_NE(csv.find(",failed,"), std::string::npos);
    EXPECT_NE(csv.find(",ok,"), std::string::npos);
}

}  // namespace

// Results folders through the pxh binary: pxh never deletes what it did not create, a run is
// written whole or not at all (signals, write errors, concurrent runs), and check/report only
// accept the files a run wrote (run.json's row count and sha256).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <nlohmann/json.hpp>
#include <thread>

#include "harness/core/sha256.h"
#include "harness/results/csv_table.h"
#include "tests/cli_util.h"

namespace {

namespace fs = std::filesystem;
using pxh::test::CliResult;

const std::string kTiny = pxh::test::tiny_experiment();

class RunFolder : public pxh::test::CliTest {
  protected:
    std::vector<std::string> partials() {
        std::vector<std::string> out;
        for (const auto& e : fs::recursive_directory_iterator(dir))
            if (e.path().filename().string().find(".partial-") != std::string::npos)
                out.push_back(e.path().string());
        return out;
    }
    std::string run_tiny(const std::string& out, const std::string& extra = "") {
        const auto exp = write("tiny.toml", kTiny);
        const CliResult r = pxh("run " + exp + " --quiet --out '" + out + "' " + extra);
        EXPECT_EQ(r.status, 0) << r.err;
        return out;
    }
};

TEST_F(RunFolder, CurrentFolderAndParentsAreRefused) {
    const auto exp = write("e.toml", kTiny);
    write("keep.txt", "mine");
    for (const std::string& out :
         std::vector<std::string>{".", "..", "./", dir.string(), "../" + dir.filename().string()}) {
        const std::string cmd = "cd '" + dir.string() + "' && " + PXH_BINARY +
                                " run e.toml --quiet --out '" + out + "' > out.txt 2> err.txt";
        const int rc = std::system(cmd.c_str());
        EXPECT_EQ(WEXITSTATUS(rc), 2) << out;
        const std::string err = slurp(dir / "err.txt");
        EXPECT_NE(err.find("is the current folder or one of its parents"), std::string::npos)
            << err;
        EXPECT_EQ(slurp(dir / "keep.txt"), "mine");
        EXPECT_EQ(slurp(exp), kTiny);
    }
    EXPECT_TRUE(partials().empty());
}

TEST_F(RunFolder, ForeignFolderIsNeverTouched) {
    const auto exp = write("e.toml", kTiny);
    fs::create_directories(dir / "precious");
    write("precious/important.txt", "data");
    for (const std::string& extra : {std::string(), std::string("--force")}) {
        const CliResult r =
            pxh("run " + exp + " --quiet --out " + (dir / "precious").string() + " " + extra);
        EXPECT_EQ(r.status, 2) << extra;
        EXPECT_NE(r.err.find("not a pxh results folder"), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_EQ(slurp(dir / "precious" / "important.txt"), "data");
    }
    // A file where the folder should be.
    write("afile", "x");
    EXPECT_EQ(pxh("run " + exp + " --quiet --out " + (dir / "afile").string()).status, 2);
    EXPECT_EQ(slurp(dir / "afile"), "x");
    EXPECT_TRUE(partials().empty());
}

TEST_F(RunFolder, EarlierResultsNeedForceAndOnlyPxhFilesAreReplaced) {
    const std::string out = run_tiny((dir / "res").string());
    const std::string first = slurp(fs::path(out) / "run.json");
    const auto exp = write("tiny.toml", kTiny);
    CliResult r = pxh("run " + exp + " --quiet --out " + out);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("pass --force"), std::string::npos) << r.err;
    EXPECT_EQ(slurp(fs::path(out) / "run.json"), first);
    // A file the user put into the results folder stops --force.
    write("res/notes.txt", "my notes");
    r = pxh("run " + exp + " --quiet --force --out " + out);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("'notes.txt'"), std::string::npos) << r.err;
    EXPECT_EQ(slurp(dir / "res" / "notes.txt"), "my notes");
    fs::remove(dir / "res" / "notes.txt");
    r = pxh("run " + exp + " --quiet --force --out " + out);
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(slurp(fs::path(out) / "run.json"), first);
    // Nothing left beside it: no partial, no replaced folder, no lock file.
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"err.txt", "out.txt", "res", "tiny.toml"}));
    // An empty folder is fine.
    fs::create_directories(dir / "empty");
    EXPECT_EQ(pxh("run " + exp + " --quiet --out " + (dir / "empty").string()).status, 0);
    EXPECT_TRUE(fs::exists(dir / "empty" / "results.csv"));
}

// SIGINT and SIGTERM leave nothing; SIGKILL leaves only a partial folder, which the next run
// into the same parent names.
TEST_F(RunFolder, SignalsLeaveNoCompleteLookingFolder) {
    const auto exp = write("slow.toml", pxh::test::kSlowExperiment);
    for (int sig : {SIGINT, SIGTERM, SIGKILL}) {
        const fs::path out = dir / ("res" + std::to_string(sig));
        const pid_t pid = fork();
        if (pid == 0) {
            execl(PXH_BINARY, PXH_BINARY, "run", exp.c_str(), "--quiet", "--out", out.c_str(),
                  (char*)nullptr);
            _exit(127);
        }
        // Wait until the run is under way (its partial folder exists), then a little more.
        const auto t0 = std::chrono::steady_clock::now();
        while (partials().empty() &&
               std::chrono::steady_clock::now() - t0 < std::chrono::seconds(30))
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        ASSERT_FALSE(partials().empty()) << "the run never started";
        std::this_thread::sleep_for(std::chrono::milliseconds(500));
        kill(pid, sig);
        int status = 0;
        waitpid(pid, &status, 0);
        EXPECT_FALSE(fs::exists(out)) << sig;
        if (sig == SIGKILL) {
            ASSERT_EQ(partials().size(), 1u);
            EXPECT_FALSE(fs::exists(fs::path(partials()[0]) / "run.json"));
        } else {
            EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 128 + sig) << status;
            EXPECT_TRUE(partials().empty()) << sig;
        }
    }
    const std::string stale = partials()[0];
    const auto tiny = write("tiny.toml", kTiny);
    const CliResult r = pxh("run " + tiny + " --quiet --out " + (dir / "next").string());
    EXPECT_EQ(r.status, 0);
    EXPECT_NE(r.err.find("pxh: warning: " + stale + " is left from an interrupted run"),
              std::string::npos)
        << r.err;
    EXPECT_TRUE(fs::exists(stale)) << "pxh deleted a folder it did not create in this run";
}

// A write error (here a file-size limit) fails the run: no complete-looking folder.
TEST_F(RunFolder, WriteErrorsFailTheRun) {
    const auto exp = write("tiny.toml", kTiny);
    // 4 blocks of 512 bytes: results.csv (~3 KB) cannot be written whole. SIGXFSZ keeps its
    // default action (ending the process): pxh itself ignores it, so the write fails.
    const std::string cmd = "sh -c \"trap - XFSZ; ulimit -f 4; exec " + std::string(PXH_BINARY) +
                            " run " + exp + " --quiet --out " + (dir / "res3").string() + "\" > " +
                            (dir / "o.txt").string() + " 2> " + (dir / "e.txt").string();
    const int rc = std::system(cmd.c_str());
    EXPECT_EQ(WEXITSTATUS(rc), 1) << slurp(dir / "e.txt");
    EXPECT_NE(slurp(dir / "e.txt").find("write failed"), std::string::npos) << slurp(dir / "e.txt");
    EXPECT_FALSE(fs::exists(dir / "res3"));
    EXPECT_FALSE(fs::exists(dir / ".res3.pxh-lock"));
    for (const auto& p : partials()) EXPECT_EQ(p.find("res3"), std::string::npos) << p;
}

// Two runs into the same folder at once: exactly one succeeds, the other says why.
TEST_F(RunFolder, ConcurrentRunsIntoOneFolder) {
    const auto exp = write("slow.toml", kTiny);
    const std::string out = (dir / "res").string();
    const std::string cmd = std::string(PXH_BINARY) + " run " + exp + " --quiet --out " + out;
    const std::string both = "(" + cmd + " > o1.txt 2> e1.txt; echo $? > rc1) & (" + cmd +
                             " > o2.txt 2> e2.txt; echo $? > rc2) & wait";
    ASSERT_EQ(std::system(("cd '" + dir.string() + "' && { " + both + "; }").c_str()), 0);
    const int rc1 = std::stoi(slurp(dir / "rc1")), rc2 = std::stoi(slurp(dir / "rc2"));
    EXPECT_EQ(std::min(rc1, rc2), 0);
    EXPECT_EQ(std::max(rc1, rc2), 2);
    const std::string err = slurp(dir / (rc1 ? "e1.txt" : "e2.txt"));
    EXPECT_TRUE(err.find("another pxh run is writing") != std::string::npos ||
                err.find("holds earlier pxh results") != std::string::npos)
        << err;
}

// run.json records rows and sha256; check and report refuse anything else.
TEST_F(RunFolder, CheckAndReportVerifyTheFolder) {
    const std::string out = run_tiny((dir / "res").string(), "--maps");
    const auto limits = write("limits.toml", pxh::test::kLooseLimits);
    const auto run = nlohmann::json::parse(slurp(fs::path(out) / "run.json"));
    EXPECT_EQ(run["rows"], 6);
    EXPECT_EQ(run["files"]["results.csv"]["sha256"], pxh::sha256_file(out + "/results.csv"));
    EXPECT_EQ(run["files"].size(), 1u + 2 * 6);  // results.csv + an EXR and a PNG per row
    CliResult r = pxh("check " + out + " --thresholds " + limits);
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("verified: "), std::string::npos) << r.out;

    const std::string csv = slurp(fs::path(out) / "results.csv");
    std::vector<std::string> lines;
    for (size_t a = 0, b; a < csv.size(); a = b + 1)
        lines.push_back(csv.substr(a, (b = csv.find('\n', a)) - a));
    auto join = [](const std::vector<std::string>& ls) {
        std::string s;
        for (const auto& l : ls) s += l + "\n";
        return s;
    };
    struct Case {
        std::string name, csv, expect;
    };
    std::vector<std::string> cut(lines.begin(), lines.begin() + 3), removed = lines, added = lines;
    removed.erase(removed.begin() + 3);
    added.push_back(lines[2]);
    std::string edited = csv;
    const size_t comma = edited.find(",0.", edited.find('\n'));
    edited[comma + 3] = edited[comma + 3] == '9' ? '1' : '9';
    const std::vector<Case> cases = {
        {"cut at a row boundary", join(cut), "2 rows, run.json records 6: rows are missing"},
        {"a row removed from the middle", join(removed), "5 rows, run.json records 6"},
        {"a row added", join(added), "7 rows, run.json records 6: rows were added"},
        {"one value edited", edited, "values differ from what the run wrote"},
    };
    for (const auto& c : cases) {
        write("res/results.csv", c.csv);
        for (const std::string& cmd :
             {"check " + out + " --thresholds " + limits, "report --no-plots " + out}) {
            r = pxh(cmd);
            EXPECT_EQ(r.status, 2) << c.name << ": " << cmd;
            EXPECT_NE(r.err.find(c.expect), std::string::npos) << c.name << ": " << r.err;
            EXPECT_NE(r.err.find("results.csv"), std::string::npos) << r.err;
            EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        }
        // Accepted on request, and then said to be unverified.
        r = pxh("check " + out + " --thresholds " + limits + " --accept-edited");
        EXPECT_EQ(r.status, 0) << c.name << r.err;
        EXPECT_NE(r.out.find("NOT VERIFIED"), std::string::npos) << r.out;
    }
    write("res/results.csv", csv);
    // A map file altered, then run.json missing.
    const std::string png = run["files"].items().begin().key();
    write("res/" + png, "not the map");
    r = pxh("check " + out + " --thresholds " + limits);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find(png + ": differs from what the run wrote"), std::string::npos) << r.err;
    fs::remove(fs::path(out) / png);
    r = pxh("check " + out + " --thresholds " + limits);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find(png + ": missing (run.json records it)"), std::string::npos) << r.err;
    fs::remove(fs::path(out) / "run.json");
    r = pxh("check " + out + " --thresholds " + limits);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("run.json: missing"), std::string::npos) << r.err;
}

TEST_F(RunFolder, RunJsonRecordsProvenance) {
    const std::string out = run_tiny((dir / "res").string());
    const auto run = nlohmann::json::parse(slurp(fs::path(out) / "run.json"));
    EXPECT_NE(run["command_line"].get<std::string>().find("--out " + out), std::string::npos);
    EXPECT_EQ(run["pxh_version"].get<std::string>().rfind("0.1.0 (", 0), 0u) << run["pxh_version"];
    EXPECT_NE(run["compile_flags"].get<std::string>().find("-ffp-contract=off"), std::string::npos);
    EXPECT_EQ(run["inputs"][0]["sha256"], pxh::sha256_file((dir / "tiny.toml").string()));
}

TEST_F(RunFolder, ThreadsZeroIsOnePxhError) {
    const auto exp = write("tiny.toml", kTiny);
    for (const std::string t : {"0", "-3", "abc"}) {
        const CliResult r =
            pxh("run " + exp + " --threads " + t + " --out " + (dir / "r").string());
        EXPECT_EQ(r.status, 2) << t;
        EXPECT_EQ(r.err.rfind("pxh: error: ", 0), 0u) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
}

}  // namespace

// Sharded runs: the partition (every unit in exactly one slice, deterministic, within LPT's
// bound of the best partition found by brute force), and pxh run --shard I/N + pxh merge
// through the binary: the merged folder equals the unsharded run cell by cell (timing columns
// aside) and file by file, and merge refuses what is not one whole run.
#include "harness/experiment/shard.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <random>

#include "harness/core/error.h"
#include "harness/experiment/experiment.h"
#include "harness/results/csv_table.h"
#include "harness/scene/scene.h"
#include "harness/scene/view.h"
#include "tests/cli_util.h"

namespace {

namespace fs = std::filesystem;
using namespace pxh;

const std::string kSource = PXH_SOURCE_DIR;

// ---- the partition ----

TEST(ShardPartition, ParsesIOverNAndRefusesTheRest) {
    EXPECT_EQ(parse_shard("0/1").count, 1u);
    EXPECT_EQ(parse_shard("3/8").index, 3u);
    EXPECT_EQ(parse_shard("3/8").count, 8u);
    for (const char* bad : {"", "3", "8/8", "9/8", "0/0", "-1/4", "1/-4", "a/4", "1/4x", " 1/4",
                            "1//4", "1/4/5", "99999999999/4"}) {
        try {
            parse_shard(bad);
            ADD_FAILURE() << "accepted '" << bad << "'";
        } catch (const InputError& e) {
            EXPECT_EQ(std::string(e.what()).rfind("--shard: '", 0), 0u) << e.what();
        }
    }
}

std::vector<WorkUnit> units_of(const std::vector<double>& costs) {
    std::vector<WorkUnit> u;
    for (size_t i = 0; i < costs.size(); ++i) u.push_back({i, 0, 0, 1, costs[i]});
    return u;
}

// The smallest possible largest slice, by trying every assignment.
double best_makespan(const std::vector<double>& c, size_t n) {
    std::vector<size_t> a(c.size(), 0);
    double best = INFINITY;
    while (true) {
        std::vector<double> load(n, 0);
        for (size_t i = 0; i < c.size(); ++i) load[a[i]] += c[i];
        best = std::min(best, *std::max_element(load.begin(), load.end()));
        size_t k = 0;
        while (k < a.size() && ++a[k] == n) a[k++] = 0;
        if (k == a.size()) return best;
    }
}

TEST(ShardPartition, EveryUnitInExactlyOneSliceWithinLptBoundOfTheBest) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> cost(1, 100);
    for (int trial = 0; trial < 40; ++trial) {
        std::vector<double> c(2 + size_t(trial) % 7);
        for (auto& x : c) x = trial % 5 == 0 ? 10 : cost(rng);  // some with equal costs (ties)
        const auto units = units_of(c);
        for (size_t n = 1; n <= std::min<size_t>(c.size(), 4); ++n) {
            std::vector<int> owner(c.size(), -1);
            double largest = 0;
            for (size_t i = 0; i < n; ++i) {
                const auto mine = shard_units(units, {i, n});
                EXPECT_TRUE(std::is_sorted(mine.begin(), mine.end()));
                EXPECT_EQ(mine, shard_units(units, {i, n}));  // deterministic
                EXPECT_FALSE(mine.empty()) << "slice " << i << "/" << n << " has nothing";
                double load = 0;
                for (size_t u : mine) {
                    EXPECT_EQ(owner[u], -1) << "unit " << u << " in two slices";
                    owner[u] = int(i);
                    load += c[u];
                }
                largest = std::max(largest, load);
            }
            for (size_t u = 0; u < c.size(); ++u) EXPECT_GE(owner[u], 0) << "unit " << u;
            // Graham's bound for longest-processing-time first: (4/3 - 1/(3n)) x the best.
            const double best = best_makespan(c, n);
            EXPECT_LE(largest, (4.0 / 3.0 - 1.0 / (3.0 * double(n))) * best + 1e-9)
                << "trial " << trial << " n " << n;
        }
    }
    // Equal costs: a round of slices 0, 1, 2, 0, 1, 2 ... by index.
    const auto equal = units_of({5, 5, 5, 5, 5, 5, 5});
    EXPECT_EQ(shard_units(equal, {0, 3}), (std::vector<size_t>{0, 3, 6}));
    EXPECT_EQ(shard_units(equal, {2, 3}), (std::vector<size_t>{2, 5}));
    try {
        shard_units(equal, {0, 8});
        ADD_FAILURE() << "8 slices of 7 units accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("7 units of work"), std::string::npos) << e.what();
    }
}

const char* kUnits = R"(
name = "units"
samples = 8
backends = ["cpu"]
timing_repeats = 2
[views]
theta_deg = [0, 45, 80]
phi_deg = [0, 90]
[[heightfields]]
name = "small"
generator = "fbm"
size = 32
[[heightfields]]
name = "large"
generator = "fbm"
size = 64
[[methods]]
name = "pom"
layers = 8
)";

TEST(ShardPartition, UnitsAreWholeSweepsInRunOrderCostingWhatTheyRun) {
    const Experiment ex = parse_experiment(kUnits, "units.toml");
    const auto u = work_units(ex, {});
    ASSERT_EQ(u.size(), 4u);  // 2 fields x 2 azimuths
    for (size_t i = 0; i < u.size(); ++i) {
        EXPECT_EQ(u[i].field, i / 2);
        EXPECT_EQ(u[i].phi, i % 2);
        EXPECT_EQ(u[i].theta_begin, 0u);
        EXPECT_EQ(u[i].theta_end, 3u);
    }
    // By the model: 8^2 samples x per view (2 + s tan(theta) x side + bound x (1 + repeats))
    // + the set-up, 64 per texel.
    const auto bound = [&](double theta, int side) {
        const Scene<double> sc{0.05, 1.0, view_vector(theta, 0), side, side};
        return double(ex.methods[0].method->max_fetches(ex.methods[0].params, sc));
    };
    double want = 32.0 * 32 * 64;
    for (double t : {0.0, 45.0, 80.0})
        want += 64 * (2 + 0.05 * std::tan(t * std::numbers::pi / 180) * 32 + bound(t, 32) * 3);
    EXPECT_NEAR(u[0].cost, want, 1e-9 * want);
    EXPECT_GT(u[2].cost, u[0].cost);  // the larger field costs more
    // The GLSL backend adds its rows (timed frames).
    EXPECT_GT(work_units(ex, {"cpu", "glsl"})[0].cost, u[0].cost);

    // With sweep_dt_deg every view pairs with its own companion: a unit per view.
    std::string text = kUnits;
    text.replace(text.find("[views]"), 7, "sweep_dt_deg = 1\n[views]");
    const auto v = work_units(parse_experiment(text, "units.toml"), {});
    ASSERT_EQ(v.size(), 12u);
    EXPECT_EQ(v[4].theta_begin, 1u);
    EXPECT_EQ(v[4].theta_end, 2u);
    EXPECT_EQ(v[4].phi, 1u);
}

// ---- pxh run --shard and pxh merge ----

class ShardMerge : public test::CliTest {
  protected:
    // Runs `pxh run EXP ARGS --shard i/n` for every i, then merges; returns merge's result.
    test::CliResult shard_and_merge(const std::string& exp, const std::string& args, size_t n,
                                    const std::string& name) {
        std::string dirs;
        for (size_t i = 0; i < n; ++i) {
            const std::string d = (dir / (name + "_" + std::to_string(i))).string();
            const auto r = pxh("run " + exp + " " + args + " --quiet --out " + d + " --shard " +
                               std::to_string(i) + "/" + std::to_string(n));
            EXPECT_EQ(r.status, 0) << r.err;
            EXPECT_NE(r.out.find("shard " + std::to_string(i) + "/" + std::to_string(n) + ": "),
                      std::string::npos)
                << r.out;
            dirs = d + " " + dirs;  // merge takes them in any order
        }
        return pxh("merge " + (dir / name).string() + " " + dirs);
    }

    // An EXR's header records when it was written (capDate): that part blanked.
    static std::string without_date(std::string s) {
        const std::string tag("capDate\0string\0\x13\0\0\0", 19);
        const size_t at = s.find(tag);
        if (at != std::string::npos && at + tag.size() + 19 <= s.size())
            s.replace(at + tag.size(), 19, 19, '#');
        return s;
    }

    // Cell by cell, timing columns aside; then every other file byte by byte (EXR dates aside).
    void expect_same_run(const fs::path& a, const fs::path& b) {
        const CsvTable x = read_csv((a / "results.csv").string());
        const CsvTable y = read_csv((b / "results.csv").string());
        ASSERT_EQ(x.columns, y.columns);
        ASSERT_EQ(x.rows.size(), y.rows.size());
        ASSERT_GT(x.rows.size(), 0u);
        size_t compared = 0;
        for (size_t c = 0; c < x.columns.size(); ++c) {
            const std::string& col = x.columns[c];
            bool timing = false;
            for (const char* t : {"time", "gpu_ms", "precompute_ms"})
                timing = timing || (col.rfind(t, 0) == 0 && col != "time_unit");
            if (timing) continue;
            for (size_t r = 0; r < x.rows.size(); ++r) {
                ASSERT_EQ(x.rows[r][c], y.rows[r][c]) << "row " << r + 2 << " column " << col;
                ++compared;
            }
        }
        EXPECT_GT(compared, x.rows.size() * 20);
        std::vector<std::string> fa, fb;
        for (const auto& e : fs::recursive_directory_iterator(a))
            if (e.is_regular_file()) fa.push_back(e.path().lexically_relative(a).string());
        for (const auto& e : fs::recursive_directory_iterator(b))
            if (e.is_regular_file()) fb.push_back(e.path().lexically_relative(b).string());
        std::sort(fa.begin(), fa.end());
        std::sort(fb.begin(), fb.end());
        EXPECT_EQ(fa, fb);
        for (const auto& f : fa) {
            if (f == "results.csv" || f == "run.json") continue;
            EXPECT_EQ(without_date(slurp(a / f)), without_date(slurp(b / f))) << f;
        }
    }

    // The whole run against its merge over each slice count of `counts`; the last count's merge
    // is also reported and compared, and its run.json records the slices.
    void expect_reproduces(const std::string& exp, const std::string& args,
                           const std::vector<size_t>& counts) {
        const auto full =
            pxh("run " + exp + " " + args + " --quiet --out " + (dir / "full").string());
        ASSERT_EQ(full.status, 0) << full.err;
        const size_t last = counts.back();
        for (size_t n : counts) {
            const std::string name = "merged" + std::to_string(n);
            const auto m = shard_and_merge(exp, args, n, name);
            ASSERT_EQ(m.status, 0) << m.out << m.err;
            EXPECT_NE(m.out.find("merged " + std::to_string(n) + " slices"), std::string::npos);
            EXPECT_NE(m.out.find("verified: " + (dir / name / "results.csv").string()),
                      std::string::npos)
                << m.out;
            expect_same_run(dir / "full", dir / name);
            if (n != last) continue;
            // The merged folder is a run to check, report and compare.
            EXPECT_EQ(pxh("report " + (dir / name).string() + " --no-plots").status, 0);
            const auto cmp = pxh("compare " + (dir / "full").string() + " " +
                                 (dir / name).string() + " --fail-on err_p95=+0,err_mean=+0");
            EXPECT_EQ(cmp.status, 0) << cmp.out << cmp.err;
        }
        const auto rec =
            nlohmann::json::parse(slurp(dir / ("merged" + std::to_string(last)) / "run.json"));
        EXPECT_EQ(rec["merged"]["count"], last);
        EXPECT_EQ(rec["merged"]["slices"].size(), last);
        EXPECT_EQ(rec["rows"], nlohmann::json::parse(slurp(dir / "full" / "run.json"))["rows"]);
    }
};

// One slice (the degenerate merge) and seven; the engines' experiment over three.
TEST_F(ShardMerge, DefaultExperimentOver1And7Shards) {
    expect_reproduces(kSource + "/results/experiments/default.toml", "--samples 8", {1, 7});
}

TEST_F(ShardMerge, EnginesExperimentOver3Shards) {
    expect_reproduces(kSource + "/results/experiments/engines.toml",
                      "--samples 8 --only 'theta_deg=0|45|85'", {3});
}

// A perspective distance sweep: its pairs span units (one per distance), so a slice traces the
// next distance of its own units as a companion view; the merged run is the whole one.
TEST_F(ShardMerge, DistanceSweepPairsAcrossSlicesReproduceTheRun) {
    const std::string exp =
        write("dist.toml",
              "name = \"dist\"\nsamples = 8\ntiming_repeats = 0\nbackends = [\"cpu\"]\n[views]\n"
              "theta_deg = [45, 70]\nphi_deg = [0, 30]\ncamera = \"perspective\"\n"
              "distance = [1, 2, 3, 4]\n[[heightfields]]\nname = \"f\"\ngenerator = \"fbm\"\n"
              "width = 16\nheight = 16\n[[methods]]\nname = \"pom\"\nlayers = 8\n");
    expect_reproduces(exp, "", {1, 3, 7});
    const CsvTable t = read_csv((dir / "full" / "results.csv").string());
    size_t paired = 0;
    for (size_t r = 0; r < t.rows.size(); ++r) paired += std::isfinite(t.number(r, "sliding_dist"));
    EXPECT_EQ(paired, t.rows.size() * 3 / 4);  // every distance but the last
}

const std::string kTiny = test::ExperimentToml("tiny")
                              .set("sweep_dt_deg", "0.5")
                              .theta("[0, 40, 80]")
                              .phi("[0, 45]")
                              .field("fbm", 16)
                              .method("pom", "layers = 8");

TEST_F(ShardMerge, ViewUnitsWithSweepPairsAndMapsReproduceTheRun) {
    const std::string exp = write("tiny.toml", kTiny);
    ASSERT_EQ(pxh("run " + exp + " --maps --quiet --out " + (dir / "full").string()).status, 0);
    const auto m = shard_and_merge(exp, "--maps", 5, "merged");
    ASSERT_EQ(m.status, 0) << m.err;
    expect_same_run(dir / "full", dir / "merged");  // maps named by the whole run's row index
    EXPECT_TRUE(fs::exists(dir / "merged" / "maps"));
}

// Three slices of kTiny, run once for the whole suite (each pxh process takes a second or two
// on a loaded 2-core machine).
class ShardRefusals : public test::CliTest {
  protected:
    static inline fs::path shared;
    static inline std::string exp;
    static void SetUpTestSuite() {
        shared = test::fresh_dir("shard_refusals");
        exp = (shared / "tiny.toml").string();
        std::ofstream(exp) << kTiny;
        for (int i = 0; i < 3; ++i) {
            const std::string args =
                "run " + exp + " --quiet --out " + s(i) + " --shard " + std::to_string(i) + "/3";
            const test::CliResult r = test::pxh_in(shared, args);
            ASSERT_EQ(r.status, 0) << args << ": " << r.err;
        }
    }
    static void TearDownTestSuite() { fs::remove_all(shared); }
    static std::string s(int i) { return (shared / ("s" + std::to_string(i))).string(); }
    std::string mine(int i) const { return (dir / ("s" + std::to_string(i))).string(); }
    // Exit 2, one line naming `what`, and no OUT.
    void expect_refused(const std::string& dirs, const std::string& what) {
        const auto r = pxh("merge " + (dir / "out").string() + " " + dirs);
        EXPECT_EQ(r.status, 2) << r.out << r.err;
        EXPECT_NE(r.err.find(what), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_FALSE(fs::exists(dir / "out"));
    }
    // A copy of slice i (named `name`) whose run.json `edit` changes (run.json is not in its
    // own integrity record: the copy still verifies).
    template <class F>
    std::string edited(int i, const std::string& name, F edit) {
        const fs::path d = dir / name;
        fs::copy(s(i), d, fs::copy_options::recursive);
        auto j = nlohmann::json::parse(slurp(d / "run.json"));
        edit(j);
        std::ofstream(d / "run.json") << j.dump(2);
        return d.string();
    }
    std::string with_build(int i, const std::string& key, const std::string& value) {
        return edited(i, "edited" + key,
                      [&](nlohmann::json& j) { j["shard"]["build"][key] = value; });
    }
};

TEST_F(ShardRefusals, MissingShardIsNamed) {
    expect_refused(s(0) + " " + s(2), "shard 1/3 missing");
    expect_refused(s(1), "shard 0/3 missing; shard 2/3 missing");
}

TEST_F(ShardRefusals, DuplicatedAndOverlappingSlices) {
    expect_refused(s(0) + " " + s(1) + " " + s(2) + " " + s(1),
                   s(1) + ": overlaps " + s(1) + ": both are shard 1/3");
    // The same shard run twice (another folder).
    ASSERT_EQ(pxh("run " + exp + " --quiet --out " + mine(9) + " --shard 1/3").status, 0);
    expect_refused(s(0) + " " + s(1) + " " + s(2) + " " + mine(9), "both are shard 1/3");
    // Another partition of the same run.
    ASSERT_EQ(pxh("run " + exp + " --quiet --out " + mine(8) + " --shard 1/4").status, 0);
    expect_refused(s(0) + " " + mine(8) + " " + s(2), mine(8) + ": is cut another way: shard 1/4");
}

TEST_F(ShardRefusals, ForeignSlices) {
    // Another experiment (one theta more).
    std::string other = kTiny;
    other.replace(other.find("[0, 40, 80]"), 11, "[0, 40, 60, 80]");
    const std::string exp2 = write("other.toml", other);
    ASSERT_EQ(pxh("run " + exp2 + " --quiet --out " + mine(7) + " --shard 1/3").status, 0);
    expect_refused(s(0) + " " + mine(7) + " " + s(2),
                   mine(7) + ": is a slice of another experiment: " + exp2);
    // The same experiment with another selection (--samples).
    ASSERT_EQ(pxh("run " + exp + " --samples 4 --quiet --out " + mine(6) + " --shard 1/3").status,
              0);
    expect_refused(s(0) + " " + mine(6) + " " + s(2),
                   mine(6) + ": is a slice of another selection of the experiment: samples 4");
    // Another pxh version, another build of it.
    expect_refused(s(0) + " " + with_build(1, "pxh_version", "0.0.9 (abc)") + " " + s(2),
                   "was run by another pxh version: 0.0.9 (abc) where " + s(0));
    expect_refused(s(0) + " " + with_build(1, "binary_sha256", "00ff") + " " + s(2),
                   "was run by another build of pxh: binary_sha256 00ff where " + s(0));
    // GLSL rows drawn by another GL driver (the glsl backend's block of run.json says which).
    const std::string gl = edited(1, "gl", [](nlohmann::json& j) {
        j["backends"]["glsl"]["facts"]["gl_renderer"] = "llvmpipe (LLVM 99, 512 bits)";
    });
    expect_refused(s(0) + " " + gl + " " + s(2), gl + ": ran its glsl rows on another setup: ");
    // Not a slice at all: an unsharded run.
    ASSERT_EQ(pxh("run " + exp + " --quiet --out " + mine(5)).status, 0);
    expect_refused(s(0) + " " + mine(5), mine(5) + ": is not a slice");
}

TEST_F(ShardRefusals, UnitsCoveredTwiceOrRowsNotOfTheirUnit) {
    // Slice 0's units again, claiming to be shard 1/3.
    const std::string twin = edited(0, "twin", [](nlohmann::json& j) { j["shard"]["index"] = 1; });
    expect_refused(s(0) + " " + twin + " " + s(2), ": both ran unit ");
    // A unit recorded under another field's name: its rows are not that unit's.
    const std::string renamed = edited(
        1, "renamed", [](nlohmann::json& j) { j["shard"]["units"][0]["heightfield"] = "bricks"; });
    expect_refused(s(0) + " " + renamed + " " + s(2), "row is not of unit ");
}

TEST_F(ShardRefusals, EditedSliceIsRefusedAsCheckRefusesIt) {
    const fs::path copy = dir / "edited";
    fs::copy(s(1), copy, fs::copy_options::recursive);
    const fs::path csv = copy / "results.csv";
    std::string text = slurp(csv);
    text.pop_back();
    text += "9\n";  // one digit more in the last cell
    std::ofstream(csv, std::ios::binary) << text;
    expect_refused(s(0) + " " + copy.string() + " " + s(2),
                   csv.string() + ": values differ from what the run wrote");
    const auto check = pxh("report " + copy.string() + " --no-plots");
    EXPECT_EQ(check.status, 2);
}

TEST_F(ShardRefusals, MoreSlicesThanUnitsAndBadShardAreRefusedByRun) {
    // 2 azimuths x 3 views, a unit per view with sweep_dt_deg: 6 units.
    auto r = pxh("run " + exp + " --quiet --out " + mine(4) + " --shard 0/7");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("--shard: 0/7: the run has 6 units of work"), std::string::npos) << r.err;
    r = pxh("run " + exp + " --quiet --out " + mine(4) + " --shard 3/3");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("--shard: '3/3' has I >= N"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(mine(4)));
    // A merge that succeeds writes OUT; merging into a slice is refused.
    const auto ok = pxh("merge " + (dir / "out").string() + " " + s(0) + " " + s(1) + " " + s(2));
    EXPECT_EQ(ok.status, 0) << ok.err;
    const auto into = pxh("merge " + s(0) + " " + s(0) + " " + s(1) + " " + s(2) + " --force");
    EXPECT_EQ(into.status, 2);
    EXPECT_NE(into.err.find("is one of the slices"), std::string::npos) << into.err;
}

// Issue 51's messages: each a line naming what is wrong, exit 2, nothing written.
TEST_F(ShardRefusals, EmptyPathsFifosAndNestedFoldersAreNamed) {
    const std::string all = s(0) + " " + s(1) + " " + s(2);
    // An empty OUT or slice path (before: a filesystem error, exit 1).
    auto r = pxh("merge '' " + all);
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_EQ(r.err, "pxh: error: merge: the output folder OUT is an empty path\n");
    expect_refused(s(0) + " '' " + s(2), "pxh: error: merge: a slice's folder is an empty path");
    // A FIFO given as a slice (before: "no such results folder").
    const std::string fifo = (dir / "fifo").string();
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    expect_refused(s(0) + " " + fifo + " " + s(2),
                   "pxh: error: " + fifo +
                       ": is not a folder (a FIFO, socket or device?), not a slice's results "
                       "folder");
    // OUT inside a slice (before: accepted, writing into slice 0's folder), or holding one.
    const auto nested = pxh("merge " + s(0) + "/merged " + all);
    EXPECT_EQ(nested.status, 2) << nested.err;
    EXPECT_EQ(nested.err, "pxh: error: " + s(0) + "/merged: lies inside the slice " + s(0) +
                              ": merge into a folder outside every slice\n");
    EXPECT_FALSE(fs::exists(s(0) + "/merged"));
    const fs::path parent = dir / "parent";
    fs::create_directories(parent);
    fs::copy(s(1), parent / "s1", fs::copy_options::recursive);
    const auto holds = pxh("merge " + parent.string() + " " + s(0) + " " +
                           (parent / "s1").string() + " " + s(2) + " --force");
    EXPECT_EQ(holds.status, 2) << holds.err;
    EXPECT_NE(holds.err.find(": holds the slice "), std::string::npos) << holds.err;
    EXPECT_TRUE(fs::exists(parent / "s1" / "results.csv"));
}

TEST_F(ShardRefusals, EditedSliceIsNotOfferedAnOptionMergeLacks) {
    const fs::path copy = dir / "edited";
    fs::copy(s(1), copy, fs::copy_options::recursive);
    std::string text = slurp(copy / "results.csv");
    text.pop_back();
    text += "9\n";  // one digit more in the last cell
    std::ofstream(copy / "results.csv", std::ios::binary) << text;
    const auto r =
        pxh("merge " + (dir / "out").string() + " " + s(0) + " " + copy.string() + " " + s(2));
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_EQ(r.err.find("--accept-edited"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("pxh merge joins only intact slices: run that slice again"),
              std::string::npos)
        << r.err;
    // merge has no such option indeed.
    EXPECT_EQ(pxh("merge " + (dir / "out").string() + " " + s(0) + " --accept-edited").status, 2);
}

TEST_F(ShardRefusals, EmptyShardIsRefusedNotRunUnsharded) {
    const auto r = pxh("run " + exp + " --quiet --out " + mine(3) + " --shard ''");
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_EQ(r.err,
              "pxh: error: --shard: '' is not I/N (I/N with 0 <= I < N, e.g. "
              "$SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT)\n");
    EXPECT_FALSE(fs::exists(mine(3)));
}

// Slices whose inputs changed between them, the TOML unchanged (issue 59, item 4): a height-field
// file edited, a plug-in shader or a compiled shader under another sha256; and slices traced on
// another tracer path (item 7): run.json records the path, merge refuses a mix.
TEST_F(ShardRefusals, ChangedInputsAndTracerPathsAreRefused) {
    // a 4 x 4 plain PGM height field, then the same file edited (one texel)
    const auto pgm = [&](int corner) {
        std::ofstream(dir / "h.pgm")
            << "P2\n4 4\n255\n"
            << corner << " 10 20 30\n40 50 60 70\n80 90 100 110\n120 130 140 150\n";
    };
    pgm(0);
    const std::string e = write("file.toml",
                                "name = \"file\"\nsamples = 4\ntiming_repeats = 0\nbackends = "
                                "[\"cpu\"]\n[views]\ntheta_deg = [0, 40]\nphi_deg = [0, 45]\n"
                                "[[heightfields]]\nname = \"h\"\nfile = \"h.pgm\"\n"
                                "[[methods]]\nname = \"parallax\"\n");
    const auto slice = [&](int i, const std::string& env, int name) {
        const std::string d = mine(name);
        const auto r =
            test::shell_in(dir, env + std::string(PXH_BINARY) + " run " + e + " --quiet --out " +
                                    d + " --shard " + std::to_string(i) + "/2");
        EXPECT_EQ(r.status, 0) << r.err;
        return d;
    };
    const std::string a = slice(0, "", 20);
    // run.json records the tracers' paths
    const auto rec = nlohmann::json::parse(slurp(fs::path(a) / "run.json"));
    ASSERT_TRUE(rec.contains("tracers")) << rec.dump();
    for (const char* k : {"exact_path", "embree_isa", "pxh_tracer_path_env"})
        EXPECT_TRUE(rec["tracers"].contains(k)) << k;
    EXPECT_EQ(rec["tracers"]["pxh_tracer_path_env"], "");
    const std::string b = slice(1, "", 21);
    pgm(255);  // the field's file edited, the TOML unchanged
    const std::string b2 = slice(1, "", 22);
    const auto ok = pxh("merge " + (dir / "ok").string() + " " + a + " " + b);
    EXPECT_EQ(ok.status, 0) << ok.err;
    expect_refused(a + " " + b2, b2 + ": ran with another height-field file ");
    pgm(0);
    // the exact tracer's path capped to scalar: another path, refused
    const std::string scalar = slice(1, "PXH_TRACER_PATH=scalar ", 23);
    EXPECT_EQ(nlohmann::json::parse(slurp(fs::path(scalar) / "run.json"))["tracers"]["exact_path"],
              "scalar");
    expect_refused(a + " " + scalar, scalar + ": ran its ground truths on another tracer path: ");
    // a plug-in shader edited between slices (its sha256 in run.json), and a compiled source
    const std::string plug = (dir / "plug").string(), plug2 = (dir / "plug2").string();
    for (const auto& [d, sha] : {std::pair{plug, "aa11"}, std::pair{plug2, "bb22"}}) {
        fs::copy(d == plug ? a : b, d, fs::copy_options::recursive);
        auto j = nlohmann::json::parse(slurp(fs::path(d) / "run.json"));
        j["plugin_shaders"] = nlohmann::json::array(
            {{{"method", "mine"}, {"path", "mine.glsl"}, {"sha256", sha}, {"source", ""}}});
        j["backends"]["cpu"]["sources"]["mine.glsl"] = sha;
        std::ofstream(fs::path(d) / "run.json") << j.dump(2);
    }
    expect_refused(plug + " " + plug2, plug2 + ": ran with another plug-in shader mine.glsl");
    auto j = nlohmann::json::parse(slurp(fs::path(plug2) / "run.json"));
    j["plugin_shaders"][0]["sha256"] = "aa11";
    std::ofstream(fs::path(plug2) / "run.json") << j.dump(2);
    expect_refused(plug + " " + plug2, plug2 + ": compiled another cpu source mine.glsl");
}

}  // namespace

// DIR/report/ is pxh report's own: it writes nothing through a symbolic link, replaces and
// removes only what it wrote before (report/manifest.txt), leaves no truncated file when the
// disk is full, refuses picture paths that leave the results folder, and its plotter draws any
// field or method name (no traceback).
#include <sys/stat.h>
#include <unistd.h>

#include "tests/cli_util.h"

namespace fs = std::filesystem;

namespace {

class ReportFiles : public pxh::test::CliTest {
  protected:
    // A small run (CPU only, a few rows); with_render: pictures of one field (a strip and a
    // montage).
    std::string make_run(const std::string& field_name = "", bool with_render = false) {
        pxh::test::ExperimentToml exp("tiny");
        exp.backends("\"cpu\"").timing_repeats(1).theta("[0, 45, 70]");
        exp.field("bricks", 32, field_name.empty() ? "" : "name = \"" + field_name + "\"");
        for (const char* m : {"parallax", "parallax_limited", "steep", "relief", "pom"})
            exp.method(m);
        if (with_render)
            exp.tail("[render]\nheightfields = [\"" + (field_name.empty() ? "bricks" : field_name) +
                     "\"]\ntheta_deg = [45]\nstrip_method = \"pom\"");
        const std::string file = write("exp.toml", exp);
        const std::string res = (dir / "res").string();
        const auto r = pxh("run " + file + " --quiet --out " + res);
        EXPECT_EQ(r.status, 0) << r.out << r.err;
        return res;
    }
    static std::string manifest(const fs::path& rep) { return slurp(rep / "manifest.txt"); }
};

TEST_F(ReportFiles, LinkedSummaryIsNotReplaced) {
    const std::string res = make_run();
    const fs::path rep = fs::path(res) / "report";
    fs::create_directories(rep);
    write("mine.md", "the user's own notes\n");
    fs::create_symlink(dir / "mine.md", rep / "summary.md");
    const auto r = pxh("report --no-plots " + res);
    EXPECT_EQ(r.status, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("summary.md: exists and pxh report did not write it"), std::string::npos)
        << r.err;
    EXPECT_EQ(slurp(dir / "mine.md"), "the user's own notes\n");
    EXPECT_TRUE(fs::is_symlink(rep / "summary.md"));
    // no temporary file left behind
    for (const auto& e : fs::directory_iterator(rep))
        EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
}

TEST_F(ReportFiles, LinkedReportFolderIsRefused) {
    const std::string res = make_run();
    fs::create_directories(dir / "elsewhere");
    fs::create_directory_symlink(dir / "elsewhere", fs::path(res) / "report");
    const auto r = pxh("report --no-plots " + res);
    EXPECT_EQ(r.status, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("report: is a symbolic link"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::is_empty(dir / "elsewhere"));
    // A linked manifest is refused too (it would be read and appended to).
    fs::remove(fs::path(res) / "report");
    fs::create_directories(fs::path(res) / "report");
    write("list.txt", "summary.md\n");
    fs::create_symlink(dir / "list.txt", fs::path(res) / "report" / "manifest.txt");
    const auto m = pxh("report --no-plots " + res);
    EXPECT_EQ(m.status, 2) << m.out << m.err;
    EXPECT_NE(m.err.find("manifest.txt: is not a regular file"), std::string::npos) << m.err;
    EXPECT_EQ(slurp(dir / "list.txt"), "summary.md\n");
}

// A re-run removes exactly what the last report wrote: with --no-plots the earlier figures and
// figures.json go; the user's files in report/ and report/data/ stay, and so does a file the
// manifest names but that the user turned into a link.
TEST_F(ReportFiles, RerunRemovesOnlyItsOwnFiles) {
    const std::string res = make_run();
    const fs::path rep = fs::path(res) / "report";
    auto r = pxh("report " + res);
    ASSERT_EQ(r.status, 0) << r.out << r.err;
    ASSERT_TRUE(fs::exists(rep / "cost_vs_error.png"));
    ASSERT_TRUE(fs::exists(rep / "figures.json"));
    const std::string m = manifest(rep);
    for (const char* f : {"\nsummary.csv\n", "\ndata/\n", "\ndata/vs_theta.csv\n",
                          "\ncost_vs_error.png\n", "\nfigures.json\n"})
        EXPECT_NE(m.find(f), std::string::npos) << f << " not in " << m;
    std::ofstream(rep / "notes.txt") << "mine";
    std::ofstream(rep / "data" / "mine.csv") << "a,b\n";
    write("target.txt", "keep me");
    fs::remove(rep / "sweep.md");
    if (fs::exists(rep / "budget.tex")) fs::remove(rep / "budget.tex");
    fs::create_symlink(dir / "target.txt", rep / "budget.tex");  // the user's link, our name
    r = pxh("report --no-plots " + res);
    EXPECT_EQ(r.status, 2) << r.out << r.err;  // budget.tex is now someone else's: stop there
    EXPECT_NE(r.err.find("budget.tex: exists and pxh report did not write it"), std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("budget.tex: not the file pxh report wrote there"), std::string::npos)
        << r.err;
    EXPECT_EQ(slurp(dir / "target.txt"), "keep me");
    fs::remove(rep / "budget.tex");
    r = pxh("report --no-plots " + res);
    ASSERT_EQ(r.status, 0) << r.out << r.err;
    EXPECT_EQ(slurp(rep / "notes.txt"), "mine");
    EXPECT_EQ(slurp(rep / "data" / "mine.csv"), "a,b\n");
    EXPECT_TRUE(fs::exists(rep / "summary.csv"));
    EXPECT_TRUE(fs::exists(rep / "budget.tex"));
    for (const auto& e : fs::directory_iterator(rep)) {
        const std::string n = e.path().filename().string();
        EXPECT_NE(e.path().extension(), ".png") << n;
        EXPECT_NE(e.path().extension(), ".pdf") << n;
        EXPECT_NE(n, "figures.json");
        EXPECT_EQ(n.find(".tmp-"), std::string::npos) << n;
    }
    EXPECT_EQ(manifest(rep).find(".png"), std::string::npos);
}

// The plot script's figures reach the report folder only through pxh report (a staging folder
// of its own, taken in after the script ends): a user's file of a figure's name stops the
// report (exit 2, the file untouched), no staging folder or half a figure set is left, and a
// staging folder that a killed report left behind (listed "NAME/**") goes with the next run.
TEST_F(ReportFiles, FiguresTakenInOnlyOverNothing) {
    const std::string res = make_run();
    const fs::path rep = fs::path(res) / "report";
    fs::create_directories(rep);
    std::ofstream(rep / "cost_vs_error.png") << "the user's picture";
    auto r = pxh("report --formats png " + res);
    EXPECT_EQ(r.status, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("cost_vs_error.png: exists and pxh report did not write it"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(slurp(rep / "cost_vs_error.png"), "the user's picture");
    for (const auto& e : fs::directory_iterator(rep)) {
        EXPECT_EQ(e.path().filename().string().rfind(".staging", 0), std::string::npos) << e.path();
        if (e.path().filename() != "cost_vs_error.png") {  // the user's
            EXPECT_NE(e.path().extension(), ".png") << "half the figures taken in: " << e.path();
        }
    }
    EXPECT_TRUE(fs::exists(rep / "summary.md"));  // the tables are written
    fs::remove(rep / "cost_vs_error.png");
    // A staging folder left by a report killed while drawing: in the manifest, with files.
    fs::create_directories(rep / ".staging-0badf00d" / "sub");
    std::ofstream(rep / ".staging-0badf00d" / "half.png") << "half";
    std::ofstream(rep / ".staging-0badf00d" / "sub" / "x.png") << "x";
    std::ofstream(rep / "manifest.txt", std::ios::app) << ".staging-0badf00d/**\n";
    r = pxh("report --formats png " + res);
    ASSERT_EQ(r.status, 0) << r.out << r.err;
    EXPECT_FALSE(fs::exists(rep / ".staging-0badf00d"));
    EXPECT_TRUE(fs::is_regular_file(rep / "cost_vs_error.png"));
    EXPECT_NE(r.out.find("wrote " + (rep / "cost_vs_error.png").string()), std::string::npos)
        << r.out;
    const std::string m = manifest(rep);
    EXPECT_NE(m.find("\ncost_vs_error.png\n"), std::string::npos) << m;
    EXPECT_NE(m.find("\nfigures.json\n"), std::string::npos) << m;
    for (const auto& e : fs::directory_iterator(rep))
        EXPECT_EQ(e.path().filename().string().rfind(".staging", 0), std::string::npos) << e.path();
}

// A full disk (here a file-size limit: the same failed write) leaves no 0-byte or truncated
// file: the failure is reported (the first file over the limit: the figures' data, written
// first), non-zero exit, nothing written after it, and no name holds a part file.
TEST_F(ReportFiles, FullDiskLeavesNoTruncatedFile) {
    const std::string res = make_run();
    const fs::path rep = fs::path(res) / "report";
    // 1 block: the manifest's first line fits, data/vs_theta.csv does not. SIGXFSZ ignored by the
    // shell is ignored by pxh too (pxh report ignores it itself as well).
    const std::string cmd = "sh -c \"trap '' XFSZ; ulimit -f 1; exec " + std::string(PXH_BINARY) +
                            " report --no-plots " + res + "\" >" + (dir / "out.txt").string() +
                            " 2>" + (dir / "err.txt").string();
    const int rc = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(rc));
    EXPECT_NE(WEXITSTATUS(rc), 0);
    const std::string err = slurp(dir / "err.txt");
    EXPECT_NE(err.find("data/vs_theta.csv: cannot write: File too large"), std::string::npos)
        << err;
    EXPECT_FALSE(fs::exists(rep / "data" / "vs_theta.csv"));
    EXPECT_FALSE(fs::exists(rep / "summary.csv"));  // the report stopped at the first failure
    for (const auto& e : fs::recursive_directory_iterator(rep)) {
        EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
        if (e.is_regular_file() && e.path().filename() != "manifest.txt") {
            EXPECT_GT(fs::file_size(e.path()), 0u) << e.path();
        }
    }
}

TEST_F(ReportFiles, PicturePathsOutsideTheFolderRefused) {
    const std::string res = make_run("", true);
    const std::string csv = slurp(fs::path(res) / "results.csv");
    const size_t at = csv.find("pictures/");
    ASSERT_NE(at, std::string::npos) << "no picture in the run";
    const size_t end = csv.find(',', at);
    const std::string first = csv.substr(at, end - at);
    // ../ out of the folder
    std::string edited = csv;
    edited.replace(at, end - at, "../../../../etc/hostname");
    write("res/results.csv", edited);
    auto r = pxh("report --no-plots --accept-edited " + res);
    EXPECT_EQ(r.status, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("results.csv:"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("leaves the results folder"), std::string::npos) << r.err;
    // a picture that is a link to a file elsewhere
    write("res/results.csv", csv);
    write("secret.png", "not a picture");
    fs::remove(fs::path(res) / first);
    fs::create_symlink(dir / "secret.png", fs::path(res) / first);
    r = pxh("report --no-plots --accept-edited " + res);
    EXPECT_EQ(r.status, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("passes through a symbolic link"), std::string::npos) << r.err;
}

// The plotter draws a field named outside Latin-1 (its GIF's bitmap font is Latin-1 only)
// without a traceback, and its strip's GIF is written.
TEST_F(ReportFiles, NonLatin1FieldNameDraws) {
    const std::string res = make_run("砂岩_field", true);
    const auto r = pxh("report " + res);
    EXPECT_EQ(r.status, 0) << r.out << r.err;
    EXPECT_EQ(r.err.find("Traceback"), std::string::npos) << r.err;
    bool gif = false;
    for (const auto& e : fs::directory_iterator(fs::path(res) / "report"))
        gif |= e.path().extension() == ".gif";
    EXPECT_TRUE(gif);
}

}  // namespace

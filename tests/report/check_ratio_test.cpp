// `pxh check` limits on a ratio to a baseline row of the same run (`ratio_to`): on a results
// folder built for it, with times chosen so each limit passes or fails as its numbers say; the
// baseline is the row of the same field, view and backend (and variant); a failed baseline fails
// the row; a missing or ambiguous baseline is bad input (FILE:LINE, exit 2).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "tests/cli_util.h"

namespace {

// parallax and pom (two settings) on one field at theta 0 and 60, CPU and GLSL. CPU pom
// layers=16 costs 3x and 5x parallax; GLSL pom layers=16 2x and 4x. pom layers=64 at theta 60
// on the CPU failed. Written as pxh wrote results.csv before the backends named their own
// timing (ns_per_sample on CPU rows, ms_per_frame on GLSL rows): a limit on time reads them.
const char* kResults =
    "method,params,heightfield,scale,bias,theta_deg,phi_deg,samples,backend,precision,"
    "texture_format,ground_truth,ns_per_sample,ms_per_frame,status,error\n"
    "parallax,,fbm,0.05,1,0,0,32,cpu,float,,exact,10,,ok,\n"
    "parallax,,fbm,0.05,1,60,0,32,cpu,float,,exact,10,,ok,\n"
    "pom,layers=16,fbm,0.05,1,0,0,32,cpu,float,,exact,30,,ok,\n"
    "pom,layers=16,fbm,0.05,1,60,0,32,cpu,float,,exact,50,,ok,\n"
    "pom,layers=64,fbm,0.05,1,0,0,32,cpu,float,,exact,90,,ok,\n"
    "pom,layers=64,fbm,0.05,1,60,0,32,cpu,float,,exact,,,failed,out of time\n"
    "parallax,,fbm,0.05,1,0,0,32,glsl,float,r32f,exact,,0.5,ok,\n"
    "parallax,,fbm,0.05,1,60,0,32,glsl,float,r32f,exact,,0.5,ok,\n"
    "pom,layers=16,fbm,0.05,1,0,0,32,glsl,float,r32f,exact,,1,ok,\n"
    "pom,layers=16,fbm,0.05,1,60,0,32,glsl,float,r32f,exact,,2,ok,\n";

class CheckRatio : public pxh::test::CliTest {
  protected:
    void SetUp() override {
        CliTest::SetUp();
        std::filesystem::create_directories(dir / "run");
        write("run/results.csv", kResults);
    }
    pxh::test::CliResult check(const std::string& limits) {
        return pxh("check " + (dir / "run").string() + " --accept-edited --thresholds " +
                   write("t.toml", limits));
    }
};

TEST_F(CheckRatio, PassesAndFailsAsTheNumbersSay) {
    // CPU pom layers=16: 3x and 5x parallax. max 5 passes (worst 5), max 4.5 fails at theta 60.
    auto r = check(
        "[[limit]]\nmethod = \"pom\"\nparams = \"layers=16\"\nbackend = \"cpu\"\n"
        "column = \"time\"\nratio_to = { method = \"parallax\" }\nmax = 5\nmin = 3\n"
        "[[limit]]\nmethod = \"pom\"\nparams = \"layers=16\"\nbackend = \"cpu\"\n"
        "column = \"time\"\nratio_to = { method = \"parallax\" }\nmax = 4.5\n"
        "[[limit]]\nmethod = \"pom\"\nparams = \"layers=16\"\nbackend = \"cpu\"\n"
        "column = \"time\"\nratio_to = { method = \"parallax\" }\nmin = 3.5\n"
        // GLSL divides by GLSL's parallax (2x, 4x), never by the CPU's (which would be 0.1-0.2).
        "[[limit]]\nmethod = \"pom\"\nparams = \"layers=16\"\nbackend = \"glsl\"\n"
        "column = \"time\"\nratio_to = { method = \"parallax\" }\nmin = 2\nmax = 4\n");
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    std::vector<std::string> lines;
    std::stringstream ss(r.out);
    for (std::string l; std::getline(ss, l);) lines.push_back(l);
    auto line_of = [&](const std::string& start) {
        for (const auto& l : lines)
            if (l.rfind(start, 0) == 0) return l;
        return std::string();
    };
    EXPECT_NE(line_of("1 ").find("(/ parallax)"), std::string::npos) << r.out;
    EXPECT_NE(line_of("1 ").find(">= 3 x parallax, <= 5 x parallax"), std::string::npos) << r.out;
    EXPECT_NE(line_of("1 ").find("pass"), std::string::npos) << r.out;
    EXPECT_NE(line_of("2 ").find("5 "), std::string::npos) << r.out;
    EXPECT_NE(line_of("2 ").find("FAIL"), std::string::npos) << r.out;
    EXPECT_NE(line_of("3 ").find("FAIL"), std::string::npos) << r.out;
    EXPECT_NE(line_of("4 ").find("pass"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("  worst: pom layers=16 [cpu/float] on fbm s=0.05 b=1 theta=60 phi=0: "
                         "5 x parallax"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("  worst: pom layers=16 [cpu/float] on fbm s=0.05 b=1 theta=0 phi=0: "
                         "3 x parallax"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("2 passed, 2 failed"), std::string::npos) << r.out;
}

TEST_F(CheckRatio, BaselineByParamsAndFailedRows) {
    // pom layers=64 / pom layers=16 at theta 0: 3 (passes max 3); at theta 60 the row failed.
    auto r = check(
        "[[limit]]\nmethod = \"pom\"\nparams = \"layers = 64\"\nbackend = \"cpu\"\n"
        "column = \"time\"\nratio_to = { method = \"pom\", params = \"layers=16\" }\n"
        "max = 3\ntheta_max = 30\n"
        "[[limit]]\nmethod = \"pom\"\nparams = \"layers = 64\"\nbackend = \"cpu\"\n"
        "column = \"time\"\nratio_to = { method = \"pom\", params = \"layers=16\" }\n"
        "max = 3\n"
        // Its failed row as a baseline: the rows divided by it fail too.
        "[[limit]]\nmethod = \"pom\"\nparams = \"layers=16\"\nbackend = \"cpu\"\ntheta_min = 30\n"
        "column = \"time\"\nratio_to = { method = \"pom\", params = \"layers=64\" }\n"
        "max = 100\n");
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    EXPECT_NE(r.out.find("1 matching rows failed: out of time"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("1 matching rows failed: its baseline pom layers=64 [cpu/float] on fbm "
                         "s=0.05 b=1 theta=60 phi=0 failed: out of time"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("1 passed, 2 failed"), std::string::npos) << r.out;
}

TEST_F(CheckRatio, BadBaselinesAreExit2) {
    const std::string head = "[[limit]]\nmethod = \"pom\"\ncolumn = \"time\"\nmax = 9\n";
    // No row of the baseline method at all.
    auto r = check(head + "ratio_to = { method = \"relief\" }\n");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("t.toml:5: ratio_to: no row of results.csv is relief"), std::string::npos)
        << r.err;
    // pom divided by pom without params: two settings share each field and view.
    r = check(head + "backend = \"cpu\"\nratio_to = { method = \"pom\" }\n");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("ratio_to: 2 rows of pom share the field, view and backend of pom "
                         "layers=16 [cpu/float] on fbm s=0.05 b=1 theta=0 phi=0 (name the "
                         "baseline's params)"),
              std::string::npos)
        << r.err;
    // GLSL pom layers=16 has no GLSL pom layers=64 to divide by.
    r = check(head +
              "backend = \"glsl\"\nratio_to = { method = \"pom\", params = \"layers=64\" }\n");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("has no baseline row (pom layers=64 on the same field, view and "
                         "backend)"),
              std::string::npos)
        << r.err;
    for (const char* bad :
         {"ratio_to = \"parallax\"\n", "ratio_to = { methd = \"parallax\" }\n",
          "ratio_to = { params = \"layers=16\" }\n", "ratio_to = { method = 3 }\n"}) {
        r = check(head + bad);
        EXPECT_EQ(r.status, 2) << bad;
        EXPECT_NE(r.err.find("t.toml:5: "), std::string::npos) << bad << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 2) << bad << r.err;
    }
}

}  // namespace

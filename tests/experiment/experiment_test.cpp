// Experiment files: what parses, and every bad input named with file and line.
#include "harness/experiment/experiment.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "harness/core/error.h"
#include "harness/core/sha256.h"
#include "harness/truth/exact_tracer.h"
#include "heightfields/heightfields.h"
#include "tests/cli_util.h"

namespace pxh {
namespace {

const char* kGood = R"(
name = "t"
samples = 16
[views]
theta_deg = { from = 0, to = 80, step = 20 }
phi_deg = [0, 90]
[[heightfields]]
generator = "bricks"
size = 32
rows = [2, 4]
scale = [0.02, 0.05]
bias = 1.0
[[methods]]
name = "pom"
layers = [8, 16, 32]
[[methods]]
name = "relief"
layers_min = 8
layers_max = 32
)";

TEST(Experiment, ParsesAndExpandsSweeps) {
    const Experiment ex = parse_experiment(kGood, "good.toml");
    EXPECT_EQ(ex.name, "t");
    EXPECT_EQ(ex.samples, 16);
    EXPECT_EQ(ex.theta_deg, (std::vector<double>{0, 20, 40, 60, 80}));
    EXPECT_EQ(ex.phi_deg, (std::vector<double>{0, 90}));
    ASSERT_EQ(ex.heightfields.size(), 4u);  // rows x scale
    EXPECT_EQ(ex.heightfields[0].name, "bricks[rows=2;cols=2;mortar=0.1;bevel=0.01;seed=1]");
    EXPECT_DOUBLE_EQ(ex.heightfields[1].scale, 0.05);
    ASSERT_EQ(ex.methods.size(), 4u);  // 3 pom + 1 relief
    EXPECT_EQ(ex.methods[2].params.canonical(), "layers=32;layers_min=off;layers_max=off");
    EXPECT_EQ(ex.methods[3].params.canonical(),
              "layers=adaptive;layers_min=8;layers_max=32;binary_steps=5");
    EXPECT_TRUE(ex.warnings.empty());
    // One entry swept over scale keeps its name; the identity says what the field is.
    EXPECT_EQ(ex.heightfields[0].name, ex.heightfields[1].name);
    EXPECT_EQ(ex.heightfields[0].identity,
              "generator:bricks 32x32 [rows=2;cols=2;mortar=0.1;bevel=0.01;seed=1]");
}

std::string error_of(const std::string& text) {
    try {
        parse_experiment(text, "bad.toml");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
    const auto pos = s.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    return s.replace(pos, from.size(), to);
}

TEST(Experiment, BadInputsNameFileLineAndProblem) {
    struct Case {
        std::string from, to, expect;
    };
    const Case cases[] = {
        {"samples = 16", "samples = 0", "bad.toml:3: 'samples' = 0 is outside [1, 8192]"},
        {"samples = 16", "sample = 16",
         "bad.toml:3: unknown key 'sample' (did you mean 'samples'?) in the experiment"},
        {"name = \"pom\"", "name = \"pomm\"", "bad.toml:14: unknown method 'pomm'"},
        {"layers = [8, 16, 32]", "layer = 8",
         "bad.toml:15: unknown parameter 'layer' (did you mean 'layers'?) for method 'pom'"},
        {"layers = [8, 16, 32]", "layers = 0", "parameter 'layers' = 0 is outside [1, 4096]"},
        {"generator = \"bricks\"", "generator = \"brick\"",
         "bad.toml:8: unknown generator 'brick'"},
        {"rows = [2, 4]", "rowz = 2",
         "unknown key 'rowz' (did you mean 'rows'?) in [[heightfields]]"},
        {"to = 80, step = 20", "to = 90, step = 30", "theta_deg = 90 is impossible"},
        {"theta_deg = { from = 0, to = 80, step = 20 }", "theta_deg = [-5]",
         "theta_deg = -5 is impossible"},
        {"scale = [0.02, 0.05]", "scale = 0", "bad.toml:11: scale must be > 0"},
        {"bias = 1.0", "bias = 1.5", "bad.toml:12: bias must lie in [0, 1]"},
        {"layers_max = 32", "layers_max = 32\nlayers = 4", "give either 'layers'"},
        {"samples = 16", "samples = [", "TOML syntax error"},
        {"samples = 16", "samples = 16\nground_truth = \"embre\"", "unknown ground_truth 'embre'"},
        {"samples = 16", "samples = 16\nbackends = [\"gpu\"]", "unknown backend 'gpu'"},
        {"samples = 16", "samples = 16\ntexture_format = \"r4\"", "unknown texture_format 'r4'"},
    };
    for (const auto& c : cases) {
        const std::string err = error_of(replace(kGood, c.from, c.to));
        EXPECT_NE(err.find(c.expect), std::string::npos)
            << "got: " << err << "\nwanted: " << c.expect;
    }
    EXPECT_NE(error_of("[views]\ntheta_deg=[0]\n").find("no [[heightfields]]"), std::string::npos);
    EXPECT_NE(error_of("samples = 4\n").find("missing [views]"), std::string::npos);
}

TEST(Experiment, MissingFileIsNamed) {
    try {
        load_experiment("/nonexistent/x.toml");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "/nonexistent/x.toml: no such file");
    }
}

}  // namespace
}  // namespace pxh

// ---- Everything below: the trust / hostile-input fixes (names, params, warnings, limits). ----

namespace pxh {
namespace {

namespace fs = std::filesystem;

// A scratch folder per test holding an experiment file and its images.
class ExperimentFiles : public test::CliTest {
  protected:
    // A W x H image whose texels depend on `seed` (different seeds: different bytes).
    std::string image(const std::string& rel, int seed, int w = 16, int h = 16) {
        HeightField hf(w, h);
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) hf.at(i, j) = float((i * 7 + j * 3 + seed) % 17) / 16.0f;
        fs::create_directories((dir / rel).parent_path());
        save_heightfield_file(hf, (dir / rel).string());
        return (dir / rel).string();
    }
    std::string exp_path() const { return (dir / "e.toml").string(); }
    Experiment parse(const std::string& body) {
        return parse_experiment(
            "[views]\ntheta_deg = [0, 30]\n" + body + "[[methods]]\nname = \"parallax\"\n",
            exp_path());
    }
    // The InputError message of parse(body), "" if it parses.
    std::string error_of(const std::string& body) {
        try {
            parse(body);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    }
};

bool has(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

// Lines of the [[heightfields]] headers in parse()'s text: line 3 is the first entry.
TEST_F(ExperimentFiles, SameFileStemInTwoFoldersIsRefusedNamingBothEntries) {
    image("maps/rock16.png", 1);
    image("maps/other/rock16.png", 2);
    const std::string err = error_of(
        "[[heightfields]]\nfile = \"maps/rock16.png\"\n"
        "[[heightfields]]\nfile = \"maps/other/rock16.png\"\n");
    EXPECT_TRUE(
        has(err, exp_path() + ":5: heightfield name 'rock16' is given to two different fields"))
        << err;
    EXPECT_TRUE(has(err, "file:maps/rock16.png channel:0 (" + exp_path() + ":3)")) << err;
    EXPECT_TRUE(has(err, "file:maps/other/rock16.png channel:0 (" + exp_path() + ":5)")) << err;
    EXPECT_TRUE(has(err, "name = \"...\"")) << err;
    // Named apart, both run.
    const Experiment ex = parse(
        "[[heightfields]]\nfile = \"maps/rock16.png\"\n"
        "[[heightfields]]\nfile = \"maps/other/rock16.png\"\nname = \"rock16b\"\n");
    ASSERT_EQ(ex.heightfields.size(), 2u);
    EXPECT_EQ(ex.heightfields[1].name, "rock16b");
}

TEST_F(ExperimentFiles, SameStemDifferentFormatsAndSameExplicitNameAreRefused) {
    image("rock.png", 1);
    image("rock.exr", 1);
    EXPECT_TRUE(has(error_of("[[heightfields]]\nfile = \"rock.png\"\n"
                             "[[heightfields]]\nfile = \"rock.exr\"\n"),
                    "heightfield name 'rock' is given to two different fields"));
    // The same explicit name on two different generators.
    EXPECT_TRUE(has(error_of("[[heightfields]]\ngenerator = \"sine\"\nname = \"a\"\n"
                             "[[heightfields]]\ngenerator = \"bumps\"\nname = \"a\"\n"),
                    exp_path() + ":6: heightfield name 'a' is given to two different fields: "
                                 "generator:sine 256x256"));
}

TEST_F(ExperimentFiles, GeneratorSeedsCollideUnlessSweptInOneEntry) {
    const std::string err = error_of(
        "[[heightfields]]\ngenerator = \"fbm\"\nseed = 1\n"
        "[[heightfields]]\ngenerator = \"fbm\"\nseed = 2\n");
    EXPECT_TRUE(has(err, "heightfield name 'fbm' is given to two different fields")) << err;
    EXPECT_TRUE(has(err, "seed=1] (" + exp_path() + ":3)")) << err;
    EXPECT_TRUE(has(err, "seed=2] (" + exp_path() + ":6)")) << err;
    // One entry swept over its seed: the names carry the parameters.
    const Experiment ex = parse("[[heightfields]]\ngenerator = \"fbm\"\nseed = [1, 2]\n");
    ASSERT_EQ(ex.heightfields.size(), 2u);
    EXPECT_NE(ex.heightfields[0].name, ex.heightfields[1].name);
}

TEST_F(ExperimentFiles, ExactDuplicatesAreRefusedScaleSweepsAreNot) {
    // The same field at the same scale and bias, under the same or another name.
    EXPECT_TRUE(has(error_of("[[heightfields]]\ngenerator = \"sine\"\n"
                             "[[heightfields]]\ngenerator = \"sine\"\n"),
                    exp_path() + ":5: duplicate height field: generator:sine 256x256"));
    EXPECT_TRUE(has(error_of("[[heightfields]]\ngenerator = \"sine\"\n"
                             "[[heightfields]]\ngenerator = \"sine\"\nname = \"sine2\"\n"),
                    "is also the entry at " + exp_path() + ":3 (as 'sine')"));
    EXPECT_TRUE(has(error_of("[[heightfields]]\ngenerator = \"sine\"\nscale = [0.05, 0.05]\n"),
                    "this entry lists generator:sine"));
    // The same field at two scales, as two entries or one list: one name, told apart by the
    // scale column.
    const Experiment ex = parse(
        "[[heightfields]]\ngenerator = \"sine\"\nscale = 0.02\n"
        "[[heightfields]]\ngenerator = \"sine\"\nscale = [0.05, 0.1]\n");
    ASSERT_EQ(ex.heightfields.size(), 3u);
    for (const auto& h : ex.heightfields) EXPECT_EQ(h.name, "sine");
}

TEST_F(ExperimentFiles, IdentityNamesGeneratorFileBytesAndScan) {
    const std::string png = image("maps/a.png", 3);
    const Experiment ex = parse(
        "[[heightfields]]\ngenerator = \"bumps\"\nwidth = 64\nheight = 32\n"
        "[[heightfields]]\nfile = \"./maps/../maps/a.png\"\nchannel = 0\n"
        "[[heightfields]]\nscan = \"jacksboro\"\n");
    ASSERT_EQ(ex.heightfields.size(), 3u);
    EXPECT_EQ(ex.heightfields[0].identity.rfind("generator:bumps 64x32 [", 0), 0u);
    const std::string first = ex.heightfields[1].identity;
    EXPECT_EQ(first, "file:maps/a.png channel:0 sha256:" + sha256_file(png));
    EXPECT_EQ(ex.heightfields[2].identity,
              "scan:jacksboro sha256:" +
                  sha256_file(std::string(PXH_SOURCE_DIR) + "/heightfields/scanned/jacksboro.png"));
    // Other bytes under the same path: another identity.
    image("maps/a.png", 4);
    EXPECT_NE(parse("[[heightfields]]\nfile = \"maps/a.png\"\n").heightfields[0].identity, first);
    EXPECT_TRUE(has(error_of("[[heightfields]]\nscan = \"../../etc/passwd\"\n"),
                    exp_path() + ":4: unknown scan '../../etc/passwd'"));
}

TEST_F(ExperimentFiles, MissingOrBadImageNamesExperimentLineAndRelativePaths) {
    const std::string missing = (dir / "maps/missing.png").string();
    EXPECT_EQ(error_of("[[heightfields]]\nfile = \"maps/missing.png\"\n"),
              exp_path() + ":3: heightfield file '" + missing +
                  "' (paths are relative to the experiment file): no such file");
    // Not an image: parses (it is a file), fails when loaded, with the same prefix.
    std::ofstream(dir / "notes.png") << "not an image\n";
    const Experiment ex = parse("[[heightfields]]\nfile = \"notes.png\"\n");
    try {
        make_heightfield(ex.heightfields[0]);
        FAIL() << "loaded a text file";
    } catch (const InputError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(
            msg.rfind(exp_path() + ":3: heightfield file '" + (dir / "notes.png").string() +
                          "' (paths are relative to the experiment file): not a readable image",
                      0),
            0u)
            << msg;
        EXPECT_FALSE(has(msg, "\n"));
    }
}

TEST_F(ExperimentFiles, GeneratorsObeyTheImageLimit) {
    const std::string err = error_of("[[heightfields]]\ngenerator = \"flat\"\nsize = 16384\n");
    EXPECT_TRUE(has(err, exp_path() + ":3: generated field 16384 x 16384 has more than " +
                             std::to_string(kMaxImageTexels) + " texels"))
        << err;
    // Exactly the limit parses (nothing is generated here).
    EXPECT_EQ(error_of("[[heightfields]]\ngenerator = \"flat\"\nwidth = 16384\nheight = 4096\n"),
              "");
    EXPECT_TRUE(has(error_of("[[heightfields]]\ngenerator = \"flat\"\nwidth = 16385\n"),
                    "'width' = 16385 is outside [1, 16384]"));
}

TEST_F(ExperimentFiles, NamesThatWouldEscapeTheOutputFolderAreRefused) {
    auto err = [&](const std::string& head) {
        try {
            parse_experiment(head +
                                 "\n[views]\ntheta_deg = [0]\n[[heightfields]]\ngenerator = "
                                 "\"flat\"\n[[methods]]\nname = \"none\"\n",
                             exp_path());
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_TRUE(has(err("\nname = \"../../../escaped\""),
                    exp_path() + ":2: experiment name '../../../escaped' contains '/'"));
    EXPECT_TRUE(has(err("name = \"..\""), exp_path() + ":1: experiment name '..' starts with '.'"));
    EXPECT_TRUE(has(err("name = \"a\\\\b\""), "contains '/' or '\\'"));
    EXPECT_TRUE(has(err("name = \"\""), "experiment name '' is empty"));
    EXPECT_TRUE(
        has(err("name = \"a\\nb\""), "experiment name 'a\\nb' contains control characters"));
    EXPECT_EQ(err("name = \"ok-name_1.2\""), "");
    // Height field names go into map file names.
    EXPECT_TRUE(has(error_of("[[heightfields]]\ngenerator = \"flat\"\nname = \"x/y\"\n"),
                    exp_path() + ":5: heightfield name 'x/y' contains '/'"));
    // Without a name the file's stem is used, made safe.
    std::ofstream(dir / ".hidden.toml") << "";
    EXPECT_EQ(parse_experiment("[views]\ntheta_deg = [0]\n[[heightfields]]\ngenerator = \"flat\"\n"
                               "[[methods]]\nname = \"none\"\n",
                               (dir / ".hidden.toml").string())
                  .name,
              "_hidden");
}

TEST_F(ExperimentFiles, OnlyRegularFilesAreRead) {
    const std::string fifo = (dir / "fifo.toml").string();
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    // Reading the FIFO would block until a writer comes: a helper plays that writer (opens
    // and closes at once, so a reader sees an empty file) so that a regression fails here
    // instead of hanging the suite. Opening without a reader fails (O_NONBLOCK): it retries.
    std::atomic<bool> done{false};
    std::thread writer([&] {
        for (int k = 0; k < 200 && !done; ++k) {
            const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
            if (fd >= 0) {
                ::close(fd);
                return;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
    });
    std::string err;
    try {
        load_experiment(fifo);
    } catch (const InputError& e) {
        err = e.what();
    }
    done = true;
    writer.join();
    EXPECT_EQ(err, fifo +
                       ": not a regular file (a FIFO, socket or device?): an experiment must be "
                       "a regular file");
    // A symlink to a regular file is followed.
    std::ofstream(dir / "real.toml") << "[views]\ntheta_deg = [0]\n[[heightfields]]\ngenerator = "
                                        "\"flat\"\n[[methods]]\nname = \"none\"\n";
    fs::create_symlink(dir / "real.toml", dir / "link.toml");
    EXPECT_EQ(load_experiment((dir / "link.toml").string()).name, "link");
}

// ---- params: the resolved set ----

std::vector<std::string> names_in(const std::string& canonical) {
    std::vector<std::string> out;
    std::stringstream ss(canonical);
    std::string item;
    while (std::getline(ss, item, ';')) out.push_back(item.substr(0, item.find('=')));
    return out;
}

TEST(Params, EveryRegisteredMethodListsEveryDeclaredParameter) {
    ASSERT_FALSE(all_methods().empty());
    for (const auto& m : all_methods()) {
        const std::string c = resolve_method_params(m, {}, "x").canonical();
        std::vector<std::string> declared;
        for (const auto& p : m.params) declared.push_back(p.name);
        EXPECT_EQ(names_in(c), declared) << m.name << ": " << c;
        EXPECT_FALSE(has(c, "=unset")) << m.name << ": " << c;
    }
}

TEST(Params, OneCanonicalSpellingPerSetting) {
    const MethodInfo& pom = *find_method("pom");
    const MethodInfo& relief = *find_method("relief");
    auto canon = [](const MethodInfo& m, const std::map<std::string, double>& given) {
        return resolve_method_params(m, given, "x").canonical();
    };
    // The default is fixed 32 layers, the same setting as layers = 32 written out.
    EXPECT_EQ(canon(pom, {}), "layers=32;layers_min=off;layers_max=off");
    EXPECT_EQ(canon(pom, {{"layers", 32}}), canon(pom, {}));
    EXPECT_EQ(canon(relief, {}), "layers=32;layers_min=off;layers_max=off;binary_steps=5");
    // parallax_clamped's m defaults to the scene's scale s.
    EXPECT_EQ(canon(*find_method("parallax_clamped"), {}), "max_offset=scale");
    EXPECT_EQ(canon(*find_method("parallax_clamped"), {{"max_offset", 0.02}}), "max_offset=0.02");
    // Adaptive: the bound not given is filled in, and layers says "adaptive".
    EXPECT_EQ(canon(pom, {{"layers_max", 64}}), "layers=adaptive;layers_min=8;layers_max=64");
    EXPECT_EQ(canon(pom, {{"layers_min", 8}, {"layers_max", 32}}), canon(pom, {{"layers_min", 8}}));
    // The filled set configures the same search: 33 fetches straight down for fixed 32, and
    // for adaptive 8..64 at theta = 0 (|V.z| = 1: n = layers_min = 8) 9.
    const Scene<double> down{};
    EXPECT_EQ(pom.max_fetches(resolve_method_params(pom, {}, "x"), down), 33);
    EXPECT_EQ(pom.max_fetches(resolve_method_params(pom, {{"layers_max", 64}}, "x"), down), 9);
    // Still refused: both modes at once.
    EXPECT_THROW(resolve_method_params(pom, {{"layers", 16}, {"layers_min", 8}}, "x"), InputError);
}

TEST(Params, UnsetParametersKeepDeclarationOrder) {
    ParamValues p;
    p.declare_unset("a", "auto");
    p.declare_unset("b", "off");
    p.set("c", 3);
    EXPECT_EQ(p.canonical(), "a=auto;b=off;c=3");
    p.set("b", 2.5);
    EXPECT_EQ(p.canonical(), "a=auto;b=2.5;c=3");
    ASSERT_EQ(p.items().size(), 2u);
    EXPECT_EQ(p.items()[0].first, "b");  // items(): values only, declaration order
    EXPECT_EQ(p.items()[1].first, "c");
}

// ---- warnings (parse_experiment collects, load_experiment prints) ----

Experiment with_views(const std::string& views, const std::string& field = "generator = \"flat\"") {
    return parse_experiment(
        "[views]\n" + views + "\n[[heightfields]]\n" + field + "\n[[methods]]\nname = \"none\"\n",
        "w.toml");
}

TEST(Warnings, RadiansLookingTheta) {
    const Experiment ex = with_views("theta_deg = [0, 0.5, 1.2]");
    ASSERT_EQ(ex.warnings.size(), 1u);
    EXPECT_EQ(ex.warnings[0],
              "w.toml:2: theta_deg values are all below 1.6 and not all whole "
              "numbers: they look like radians, but theta_deg is in degrees");
    EXPECT_TRUE(with_views("theta_deg = [0, 1]").warnings.empty());     // whole degrees
    EXPECT_TRUE(with_views("theta_deg = [0.5, 30]").warnings.empty());  // not all small
}

TEST(Warnings, PhiNormalisedAndDeduplicated) {
    const Experiment ex = with_views("theta_deg = [10]\nphi_deg = [-90, 360, 10, 0, 730]");
    EXPECT_EQ(ex.phi_deg, (std::vector<double>{270, 0, 10}));
    ASSERT_EQ(ex.warnings.size(), 2u);
    EXPECT_EQ(ex.warnings[0],
              "w.toml:3: phi_deg outside [0, 360) normalised: -90 -> 270, 360 -> 0, "
              "730 -> 10");
    EXPECT_EQ(ex.warnings[1],
              "w.toml:3: phi_deg repeats an azimuth (2 duplicate(s) dropped): each "
              "view is measured once");
}

TEST(Warnings, ThetaSortedAndDeduplicated) {
    Experiment ex = with_views("theta_deg = [60, 30, 60, 0]");
    EXPECT_EQ(ex.theta_deg, (std::vector<double>{0, 30, 60}));
    ASSERT_EQ(ex.warnings.size(), 1u);
    EXPECT_EQ(ex.warnings[0],
              "w.toml:2: theta_deg is not in increasing order (sorted, 1 "
              "duplicate(s) dropped): views are measured in increasing theta, each once");
    ex = with_views("theta_deg = [0, 30, 30]");
    EXPECT_EQ(ex.theta_deg, (std::vector<double>{0, 30}));
    ASSERT_EQ(ex.warnings.size(), 1u);
    EXPECT_TRUE(has(ex.warnings[0], "theta_deg repeats values (1 duplicate(s) dropped)"));
}

TEST(Warnings, ScaleWhoseErrorsSaturate) {
    // s = 5: s tan(theta) = 0.5 at theta = atan(0.1) = 5.7 degrees.
    Experiment ex = with_views("theta_deg = [0, 30]", "generator = \"flat\"\nscale = [0.05, 5]");
    ASSERT_EQ(ex.warnings.size(), 1u);
    EXPECT_TRUE(has(ex.warnings[0],
                    "w.toml:5: scale = 5: the parallax offset s*tan(theta) reaches "
                    "half a tile at theta = 5.7 deg"))
        << ex.warnings[0];
    // One warning per scale value, naming every entry's line.
    ex = with_views("theta_deg = [0, 30]",
                    "generator = \"flat\"\nscale = 5\n[[heightfields]]\n"
                    "generator = \"sine\"\nscale = [1, 5]");
    ASSERT_EQ(ex.warnings.size(), 2u);
    EXPECT_EQ(ex.warnings[0].rfind("w.toml:8: scale = 1: ", 0), 0u) << ex.warnings[0];
    EXPECT_EQ(ex.warnings[1].rfind("w.toml:5: scale = 5 (also on lines 8): ", 0), 0u)
        << ex.warnings[1];
    // The same scale only straight down, or grazing views with an ordinary scale: no warning.
    EXPECT_TRUE(
        with_views("theta_deg = [0, 5]", "generator = \"flat\"\nscale = 5").warnings.empty());
    EXPECT_TRUE(
        with_views("theta_deg = [0, 89.9]", "generator = \"flat\"\nscale = 0.05").warnings.empty());
    // s = 0.5 reaches half a tile at exactly 45 degrees.
    EXPECT_EQ(with_views("theta_deg = [45]", "generator = \"flat\"\nscale = 0.5").warnings.size(),
              1u);
    EXPECT_TRUE(
        with_views("theta_deg = [44]", "generator = \"flat\"\nscale = 0.5").warnings.empty());
}

// ---- one line ----

TEST(OneLine, ControlCharactersAreEscaped) {
    EXPECT_EQ(one_line("a\nb\tc\rd\x01"
                       "e\x7f"),
              "a\\nb\\tc\\rd\\x01e\\x7f");
    EXPECT_EQ(one_line("plain ü"), "plain ü");  // UTF-8 passes
    EXPECT_STREQ(InputError("f:1", "x\ny").what(), "f:1: x\\ny");
}

TEST(OneLine, TomlSyntaxErrorQuotingTheInput) {
    try {
        parse_experiment("samples = fa\n[views]\ntheta_deg = [0]\n", "bad.toml");
        FAIL();
    } catch (const InputError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
        EXPECT_EQ(msg.rfind("bad.toml:1: TOML syntax error: ", 0), 0u) << msg;
        EXPECT_TRUE(has(msg, "fa\\n")) << msg;  // the quoted newline, escaped
    }
}

// ---- estimate ----

TEST(Estimate, RowsCountEveryCombination) {
    const Experiment ex = parse_experiment(R"(
samples = 16
backends = ["cpu", "glsl"]
precision = ["float", "double"]
texture_format = ["r32f", "r16", "r8"]
[views]
theta_deg = [0, 30, 60, 80]
phi_deg = [0, 45, 90]
[[heightfields]]
generator = "sine"
scale = [0.02, 0.05]
[[heightfields]]
generator = "bumps"
size = 64
[[methods]]
name = "pom"
layers = [8, 16]
[[methods]]
name = "parallax"
)",
                                           "e.toml");
    // 3 fields x 4 theta x 3 phi x 3 settings x (2 precisions + 3 formats)
    EXPECT_EQ(estimate_run(ex, {}).rows, 3u * 4 * 3 * 3 * 5);
    EXPECT_EQ(estimate_run(ex, {"cpu"}).rows, 3u * 4 * 3 * 3 * 2);
    EXPECT_EQ(estimate_run(ex, {"glsl"}).rows, 3u * 4 * 3 * 3 * 3);
}

TEST(Estimate, MemoryGrowsWithTheLargestFieldAndTheSamples) {
    auto est = [](int size, int samples, const std::string& more = "") {
        return estimate_run(
            parse_experiment("samples = " + std::to_string(samples) +
                                 "\n[views]\ntheta_deg = [0]\n[[heightfields]]\ngenerator = "
                                 "\"flat\"\nsize = 16\n[[heightfields]]\ngenerator = \"sine\"\n"
                                 "size = " +
                                 std::to_string(size) + "\n" + more +
                                 "[[methods]]\nname = \"none\"\n",
                             "e.toml"),
            {});
    };
    // Fields are built one at a time: a second small field adds nothing; 4x the texels of
    // the largest adds 3 x 4096^2 x 55 bytes (field, mipmap, Embree), and 13 more per texel
    // where the CPU has the exact tracer's AVX-512 path (its square tables while built).
    const size_t per_texel = 55 + (ExactTracer::cpu_has_simd_path() ? 13 : 0);
    const RunEstimate a = est(4096, 8), b = est(8192, 8);
    EXPECT_EQ(b.peak_bytes - a.peak_bytes, 3ull * 4096 * 4096 * per_texel);
    EXPECT_TRUE(has(a.detail, "largest field with its truths and Embree " +
                                  format_bytes(4096ull * 4096 * per_texel)))
        << a.detail;
    // Samples: per sample 80 (the view) + 8 (its lambda) + 2 x 16 (one row's errors, this view
    // and the last) + 3 x 36 (method outputs).
    const RunEstimate c = est(4096, 1024);
    EXPECT_EQ(c.peak_bytes - a.peak_bytes, (1024ull * 1024 - 64) * (80 + 8 + 32 + 108));
}

// A scan counts as tiled when loaded: the geoid is 1440 x 1440 (periodic in x, continued over
// the poles), a mirrored scan 2W x 2H; 56 bytes per texel (field, mask, mipmap, Embree), 13
// more where the CPU has the exact tracer's AVX-512 path.
TEST(Estimate, ScansCountAsTiled) {
    const size_t per_texel = 56 + (ExactTracer::cpu_has_simd_path() ? 13 : 0);
    auto field_mib = [](const std::string& scan) {
        const RunEstimate e = estimate_run(
            parse_experiment("samples = 8\n[views]\ntheta_deg = [0]\n[[heightfields]]\nscan = \"" +
                                 scan + "\"\n[[methods]]\nname = \"none\"\n",
                             "e.toml"),
            {});
        return e.detail;
    };
    EXPECT_TRUE(has(field_mib("egm96"), "largest field with its truths and Embree " +
                                            format_bytes(1440ull * 1440 * per_texel)))
        << field_mib("egm96");
    EXPECT_TRUE(has(field_mib("olinda"), "largest field with its truths and Embree " +
                                             format_bytes(222ull * 222 * per_texel)))
        << field_mib("olinda");
}

}  // namespace
}  // namespace pxh

// Bilinear sampling (docs/conventions.md section 1), generators, and image loading.
#include "harness/scene/heightfield.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "harness/core/error.h"
#include "heightfields/heightfields.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

namespace fs = std::filesystem;

// 2 x 2 field: row j = 0 is (0.0, 1.0), row j = 1 is (0.5, 0.25).
HeightField two_by_two() {
    HeightField hf(2, 2);
    hf.at(0, 0) = 0.0f;
    hf.at(1, 0) = 1.0f;
    hf.at(0, 1) = 0.5f;
    hf.at(1, 1) = 0.25f;
    return hf;
}

TEST(HeightSampler, TexelCentresReturnTexels) {
    const HeightField hf = two_by_two();
    HeightSampler<double> hs(hf, 1, 0);
    EXPECT_DOUBLE_EQ(hs.height({0.25, 0.25}), 0.0);
    EXPECT_DOUBLE_EQ(hs.height({0.75, 0.25}), 1.0);
    EXPECT_DOUBLE_EQ(hs.height({0.25, 0.75}), 0.5);
    EXPECT_DOUBLE_EQ(hs.height({0.75, 0.75}), 0.25);
    EXPECT_EQ(hs.fetches, 4);
}

TEST(HeightSampler, BilinearHandComputed) {
    const HeightField hf = two_by_two();
    HeightSampler<double> hs(hf, 1, 0);
    // Midway between the four centres: the mean.
    EXPECT_DOUBLE_EQ(hs.height({0.5, 0.5}), (0.0 + 1.0 + 0.5 + 0.25) / 4);
    // u = 0.375: x = 0.25, between texel 0 (weight 0.75) and 1 (0.25) on row 0.
    EXPECT_DOUBLE_EQ(hs.height({0.375, 0.25}), 0.25);
    // (0.4, 0.6): x = 0.3, y = 0.7: rows 0.3 and 0.5 + (0.25-0.5)*0.3 = 0.425; 0.3*.3 + .7*.425
    EXPECT_NEAR(hs.height({0.4, 0.6}), 0.3 * 0.3 + 0.7 * 0.425, 1e-15);
}

TEST(HeightSampler, RepeatWrapping) {
    const HeightField hf = two_by_two();
    HeightSampler<double> hs(hf, 1, 0);
    // u = 0 lies halfway between texel 1 (of the previous tile) and texel 0.
    EXPECT_DOUBLE_EQ(hs.height({0.0, 0.25}), 0.5);
    EXPECT_DOUBLE_EQ(hs.height({1.0, 0.25}), 0.5);
    EXPECT_DOUBLE_EQ(hs.height({-3.0, 0.25}), 0.5);
    // Whole tiles away: identical.
    for (double u : {0.1, 0.37, 0.93})
        for (double v : {0.05, 0.61})
            EXPECT_NEAR(hs.height({u + 5, v - 7}), hs.height({u, v}), 1e-12);
    // v = 0: halfway between rows 1 and 0 at u = 0.25: (0.5 + 0.0) / 2.
    EXPECT_DOUBLE_EQ(hs.height({0.25, 0.0}), 0.25);
}

TEST(HeightSampler, SurfaceZIsScaledAndBiased) {
    const HeightField hf = two_by_two();
    HeightSampler<double> hs(hf, 0.05, 1.0);
    EXPECT_DOUBLE_EQ(hs.z({0.75, 0.25}), 0.0);    // h = 1, b = 1: at the polygon
    EXPECT_DOUBLE_EQ(hs.z({0.25, 0.25}), -0.05);  // h = 0: bottom of the slab
    HeightSampler<float> hf32(hf, 0.05f, 0.5f);
    EXPECT_FLOAT_EQ(hf32.z({0.25f, 0.75f}), 0.0f);
}

TEST(Generators, DeterministicInRangeAndSeeded) {
    for (const auto& g : all_generators()) {
        const ParamValues p = resolve_params(g.params, {}, "test", g.name);
        const HeightField a = generate_heightfield(g, 64, 48, p);
        const HeightField b = generate_heightfield(g, 64, 48, p);
        EXPECT_EQ(a.texels, b.texels) << g.name;
        EXPECT_NO_THROW(a.validate(g.name)) << g.name;
        bool has_seed = false;
        for (const auto& s : g.params) has_seed |= s.name == "seed";
        if (has_seed) {
            const HeightField c = generate_heightfield(
                g, 64, 48, resolve_params(g.params, {{"seed", 7}}, "test", g.name));
            EXPECT_NE(a.texels, c.texels) << g.name << ": seed has no effect";
        }
    }
}

// Tileable: the mean step between neighbours across the tile border is like the interior
// one (a seam would make it much larger).
TEST(Generators, SmoothOnesTileWithoutSeams) {
    for (const char* name : {"sine", "bumps", "fbm", "pyramids", "bricks", "terraces"}) {
        const GeneratorInfo* g = find_generator(name);
        const HeightField hf =
            generate_heightfield(*g, 128, 128, resolve_params(g->params, {}, "test", name));
        double interior = 0, border = 0;
        for (int j = 0; j < 128; ++j)
            for (int i = 0; i < 128; ++i) {
                const double dx = std::abs(hf.wrapped(i + 1, j) - hf.at(i, j));
                const double dy = std::abs(hf.wrapped(i, j + 1) - hf.at(i, j));
                (i == 127 ? border : interior) += dx;  // the pair (127, 0) crosses the border
                (j == 127 ? border : interior) += dy;
            }
        const double border_mean = border / (2 * 128), interior_mean = interior / (2 * 128 * 127);
        EXPECT_LE(border_mean, 2.0 * interior_mean + 1e-6) << name;
    }
}

class ImageFiles : public ::testing::Test {
  protected:
    fs::path dir = fs::temp_directory_path() / ("pxh_hf_test_" + std::to_string(::getpid()));
    void SetUp() override { fs::create_directories(dir); }
    void TearDown() override { fs::remove_all(dir); }
    std::string write_image(const std::string& name, int w, int h, int nch, OIIO::TypeDesc type,
                            const std::vector<float>& px) {
        const std::string path = (dir / name).string();
        auto out = OIIO::ImageOutput::create(path);
        EXPECT_TRUE(out) << path;
        OIIO::ImageSpec spec(w, h, nch, type);
        EXPECT_TRUE(out->open(path, spec));
        EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
        out->close();
        return path;
    }
    std::string write_bytes(const std::string& name, const std::string& bytes) {
        const std::string path = (dir / name).string();
        std::ofstream(path, std::ios::binary) << bytes;
        return path;
    }
    static std::string error_of(const std::string& path) {
        try {
            load_heightfield_file(path);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    }
};

TEST_F(ImageFiles, EightAndSixteenBitPngMapToUnitRange) {
    // Row 0 of the file holds 0 and 1; row 1 holds 128/255 and 64/255 (exact in 8 bit).
    const std::vector<float> px{0.0f, 1.0f, 128 / 255.0f, 64 / 255.0f};
    const HeightField a =
        load_heightfield_file(write_image("a.png", 2, 2, 1, OIIO::TypeDesc::UINT8, px));
    EXPECT_EQ(a.width, 2);
    EXPECT_FLOAT_EQ(a.at(0, 0), 0.0f);  // first stored row is j = 0
    EXPECT_FLOAT_EQ(a.at(1, 0), 1.0f);
    EXPECT_FLOAT_EQ(a.at(0, 1), 128 / 255.0f);
    EXPECT_FLOAT_EQ(a.at(1, 1), 64 / 255.0f);
    const std::vector<float> px16{0.0f, 1.0f, 1000 / 65535.0f, 40000 / 65535.0f};
    const HeightField b =
        load_heightfield_file(write_image("b.png", 2, 2, 1, OIIO::TypeDesc::UINT16, px16));
    EXPECT_FLOAT_EQ(b.at(0, 1), 1000 / 65535.0f);
    EXPECT_FLOAT_EQ(b.at(1, 1), 40000 / 65535.0f);
}

TEST_F(ImageFiles, TiffExrAndChannelChoice) {
    const std::vector<float> px{0.1f, 0.9f, 0.2f, 0.8f, 0.3f, 0.7f};  // 3 x 1, 2 channels
    const std::string tif = write_image("c.tif", 3, 1, 2, OIIO::TypeDesc::UINT16, px);
    EXPECT_NEAR(load_heightfield_file(tif, 0).at(1, 0), 0.2f, 1e-4);
    EXPECT_NEAR(load_heightfield_file(tif, 1).at(1, 0), 0.8f, 1e-4);
    const std::string exr = write_image("d.exr", 3, 1, 2, OIIO::TypeDesc::FLOAT, px);
    EXPECT_FLOAT_EQ(load_heightfield_file(exr).at(2, 0), 0.3f);
}

// PFM stores the bottom row first; docs/conventions.md section 1 takes the first stored row as j =
// 0.
TEST_F(ImageFiles, PfmFirstStoredRowIsRowZero) {
    std::string bytes = "Pf\n2 2\n-1.0\n";
    const float vals[4] = {0.125f, 0.25f, 0.5f, 0.75f};  // stored order
    bytes.append(reinterpret_cast<const char*>(vals), sizeof vals);
    const HeightField hf = load_heightfield_file(write_bytes("e.pfm", bytes));
    EXPECT_FLOAT_EQ(hf.at(0, 0), 0.125f);
    EXPECT_FLOAT_EQ(hf.at(1, 0), 0.25f);
    EXPECT_FLOAT_EQ(hf.at(0, 1), 0.5f);
    EXPECT_FLOAT_EQ(hf.at(1, 1), 0.75f);
}

TEST_F(ImageFiles, BadFilesAreNamedErrors) {
    const std::string missing = (dir / "missing.png").string();
    EXPECT_NE(error_of(missing).find("missing.png: no such file"), std::string::npos);
    const std::string text = write_bytes("text.png", "this is not an image\n");
    EXPECT_NE(error_of(text).find("text.png"), std::string::npos);
    const std::string empty = write_bytes("empty.png", "");
    EXPECT_NE(error_of(empty).find("empty"), std::string::npos);
    // A truncated PNG: the first 60 bytes of a valid 64 x 64 one.
    std::vector<float> px(64 * 64, 0.5f);
    for (size_t i = 0; i < px.size(); ++i) px[i] = float(i % 97) / 96.0f;
    const std::string full = write_image("full.png", 64, 64, 1, OIIO::TypeDesc::UINT8, px);
    std::ifstream in(full, std::ios::binary);
    std::string data((std::istreambuf_iterator<char>(in)), {});
    const std::string trunc = write_bytes("trunc.png", data.substr(0, data.size() / 2));
    EXPECT_NE(error_of(trunc).find("trunc.png"), std::string::npos);
    // NaN and out-of-range floats.
    const std::string nan = write_image("nan.exr", 2, 1, 1, OIIO::TypeDesc::FLOAT, {0.5f, NAN});
    EXPECT_NE(error_of(nan).find("not finite"), std::string::npos);
    const std::string big = write_image("big.exr", 2, 1, 1, OIIO::TypeDesc::FLOAT, {0.5f, 1.5f});
    EXPECT_NE(error_of(big).find("outside [0,1]"), std::string::npos);
    // A header claiming 100000 x 100000 is refused before allocating.
    const std::string huge = write_bytes("huge.pfm", "Pf\n100000 100000\n-1.0\n0000");
    EXPECT_NE(error_of(huge).find("larger than"), std::string::npos);
}

}  // namespace
}  // namespace pxh

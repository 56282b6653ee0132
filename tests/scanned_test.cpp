// Scanned height fields: the committed files, mirroring, hole masks, the npz/PLY/OFF readers,
// and hostile image files.
#include "heightfields/scanned.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "harness/core/error.h"
#include "heightfields/heightfields.h"
#include "heightfields/scan_io.h"

namespace pxh {
namespace {

namespace fs = std::filesystem;

TEST(Scanned, TheFourScansAreListedWithProvenance) {
    const auto scans = list_scans();
    std::vector<std::string> names;
    for (const auto& s : scans) names.push_back(s.name);
    for (const char* n : {"jacksboro", "motorcycle", "bunny", "lidar_b9"})
        EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
    for (const auto& s : scans) {
        std::ifstream f(std::string(PXH_SOURCE_DIR) + "/heightfields/scanned/" + s.name + ".json");
        std::stringstream ss;
        ss << f.rdbuf();
        for (const char* key : {"package", "package_version", "path_in_package", "original",
                                "value_range", "units", "grid_spacing", "licence", "holes"})
            EXPECT_NE(ss.str().find(std::string("\"") + key + "\""), std::string::npos)
                << s.name << " " << key;
    }
}

// Non-periodic scans load mirrored: 2W x 2H, texel (2W-1-i, j) = (i, j), masks likewise.
TEST(Scanned, MirroredToTileWithoutCliffs) {
    const HeightField base =
        load_heightfield_file(std::string(PXH_SOURCE_DIR) + "/heightfields/scanned/lidar_b9.png");
    const HeightField hf = load_scan("lidar_b9", "test");
    ASSERT_EQ(hf.width, 2 * base.width);
    ASSERT_EQ(hf.height, 2 * base.height);
    for (int j = 0; j < base.height; ++j)
        for (int i = 0; i < base.width; ++i) {
            const float v = base.at(i, j);
            ASSERT_EQ(hf.at(i, j), v);
            ASSERT_EQ(hf.at(hf.width - 1 - i, j), v);
            ASSERT_EQ(hf.at(i, hf.height - 1 - j), v);
            ASSERT_EQ(hf.at(hf.width - 1 - i, hf.height - 1 - j), v);
        }
    // Across the wrap, neighbours are equal (the mirror edge): no artificial cliff.
    for (int j = 0; j < hf.height; ++j)
        EXPECT_EQ(hf.wrapped(hf.width, j), hf.wrapped(hf.width - 1, j));
    ASSERT_EQ(hf.filled.size(), hf.texels.size());
    size_t filled = 0;
    for (uint8_t f : hf.filled) filled += f;
    EXPECT_EQ(filled % 4, 0u);  // each filled texel appears four times
    EXPECT_GT(filled, 0u);
}

TEST(Scanned, MotorcycleHolesMatchTheSourcesInfinities) {
    // The source: 7.3% of the disparity map is +inf (no measurement).
    std::ifstream f(std::string(PXH_SOURCE_DIR) + "/heightfields/scanned/motorcycle.json");
    std::stringstream ss;
    ss << f.rdbuf();
    const std::string j = ss.str();
    const auto p = j.find("\"fraction\":");
    ASSERT_NE(p, std::string::npos);
    const double frac = std::stod(j.substr(p + 11));
    EXPECT_NEAR(frac, 0.0735, 0.001);
    const HeightField hf = load_scan("motorcycle", "test");
    EXPECT_EQ(hf.width, 1482);
    EXPECT_NO_THROW(hf.validate("motorcycle"));
}

TEST(Scanned, UnknownScanIsNamed) {
    try {
        load_scan("nope", "exp.toml:3");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("exp.toml:3: unknown scan 'nope' (known: bunny"),
                  std::string::npos)
            << e.what();
    }
}

class ScanFiles : public ::testing::Test {
  protected:
    fs::path dir = fs::temp_directory_path() / ("pxh_scan_test_" + std::to_string(::getpid()));
    void SetUp() override { fs::create_directories(dir); }
    void TearDown() override { fs::remove_all(dir); }
    std::string bytes(const std::string& name, const std::string& b) {
        std::ofstream(dir / name, std::ios::binary) << b;
        return (dir / name).string();
    }
    static std::string error_of(const std::string& path, int channel = 0) {
        try {
            load_heightfield_file(path, channel);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    }
};

std::string be32(uint32_t v) { return {char(v >> 24), char(v >> 16), char(v >> 8), char(v)}; }

std::string chunk(const std::string& type_and_data) {
    const uint32_t crc =
        crc32(0, reinterpret_cast<const Bytef*>(type_and_data.data()), uInt(type_and_data.size()));
    return be32(uint32_t(type_and_data.size() - 4)) + type_and_data + be32(crc);
}

// A PNG whose header (valid CRCs) claims width x height, with a tiny IDAT and IEND: what a
// hostile file looks like to a reader that trusts the header.
std::string png_header(uint32_t w, uint32_t h) {
    const std::string empty_zlib("\x78\x9c\x03\x00\x00\x00\x00\x01", 8);
    return std::string("\x89PNG\r\n\x1a\n", 8) +
           chunk("IHDR" + be32(w) + be32(h) + std::string("\x10\x00\x00\x00\x00", 5)) +
           chunk("IDAT" + empty_zlib) + chunk("IEND");
}

TEST_F(ScanFiles, HostileImagesAreRefusedWithTheFileNamed) {
    // 100000 x 100000: refused from the header, before any allocation.
    const std::string huge = bytes("huge.png", png_header(100000, 100000));
    EXPECT_NE(error_of(huge).find("huge.png: image is 100000 x 100000, larger than"),
              std::string::npos)
        << error_of(huge);
    // Zero-size image (width 0 in the header) and a 0-byte file.
    const std::string zero = bytes("zero.png", png_header(0, 10));
    EXPECT_NE(error_of(zero).find("zero.png"), std::string::npos);
    EXPECT_NE(error_of(bytes("empty.png", "")).find("empty.png: empty file"), std::string::npos);
    // A text file named .png.
    EXPECT_NE(error_of(bytes("text.png", "just text\n")).find("text.png: not a readable image"),
              std::string::npos);
    // Truncated: a real PNG cut in half; the error is one line.
    std::ifstream in(std::string(PXH_SOURCE_DIR) + "/heightfields/scanned/jacksboro.png",
                     std::ios::binary);
    std::string data((std::istreambuf_iterator<char>(in)), {});
    const std::string trunc = error_of(bytes("trunc.png", data.substr(0, data.size() / 2)));
    EXPECT_NE(trunc.find("trunc.png: PNG chunk 'IDAT'"), std::string::npos) << trunc;
    EXPECT_EQ(trunc.find('\n'), std::string::npos) << trunc;
}

// RGB images: the height is channel 0 (red) unless `channel` says otherwise; 1 x 1 is a
// legitimate (flat) field.
TEST_F(ScanFiles, RgbChannelRuleAndOneByOne) {
    const std::string path = (dir / "rgb.png").string();
    auto out = OIIO::ImageOutput::create(path);
    const float px[6] = {0.2f, 0.6f, 1.0f, 0.4f, 0.0f, 0.8f};
    ASSERT_TRUE(out->open(path, OIIO::ImageSpec(2, 1, 3, OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px));
    out->close();
    EXPECT_NEAR(load_heightfield_file(path, 0).at(1, 0), 0.4f, 1.0 / 255);
    EXPECT_NEAR(load_heightfield_file(path, 2).at(1, 0), 0.8f, 1.0 / 255);
    EXPECT_NE(error_of(path, 3).find("channel 3 requested, image has 3"), std::string::npos);
    const std::string one = (dir / "one.png").string();
    auto o1 = OIIO::ImageOutput::create(one);
    const float v = 0.5f;
    ASSERT_TRUE(o1->open(one, OIIO::ImageSpec(1, 1, 1, OIIO::TypeDesc::UINT16)));
    ASSERT_TRUE(o1->write_image(OIIO::TypeDesc::FLOAT, &v));
    o1->close();
    EXPECT_NEAR(load_heightfield_file(one).at(0, 0), 0.5f, 1e-4);
}

TEST_F(ScanFiles, ReadersParseWhatTheyRead) {
    // OFF: a quad fanned into two triangles.
    const Mesh m =
        read_off(bytes("q.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0.5\n0 1 0\n4 0 1 2 3\n"));
    ASSERT_EQ(m.triangles.size(), 2u);
    EXPECT_EQ(m.triangles[1][2], 3u);
    EXPECT_DOUBLE_EQ(m.vertices[2][2], 0.5);
    // PLY: binary little endian with an extra property between the coordinates.
    std::string ply =
        "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n"
        "property uchar red\nproperty double y\nproperty float z\nend_header\n";
    for (int v = 0; v < 2; ++v) {
        const float x = 1.5f + v, z = -2.0f;
        const double y = 3.25 * (v + 1);
        const unsigned char r = 7;
        ply.append(reinterpret_cast<const char*>(&x), 4);
        ply.append(reinterpret_cast<const char*>(&r), 1);
        ply.append(reinterpret_cast<const char*>(&y), 8);
        ply.append(reinterpret_cast<const char*>(&z), 4);
    }
    const auto pts = read_ply_points(bytes("p.ply", ply));
    ASSERT_EQ(pts.size(), 2u);
    EXPECT_DOUBLE_EQ(pts[1][0], 2.5);
    EXPECT_DOUBLE_EQ(pts[1][1], 6.5);
    EXPECT_DOUBLE_EQ(pts[0][2], -2.0);
    EXPECT_NE(std::string([&] {
                  try {
                      read_ply_points(bytes("t.ply", ply.substr(0, ply.size() - 5)));
                  } catch (const InputError& e) {
                      return std::string(e.what());
                  }
                  return std::string();
              }())
                  .find("truncated"),
              std::string::npos);
    // npz: the committed source's elevation matches the known DEM facts.
    const NpyArray a = read_npz_array(
        "/usr/share/matplotlib/mpl-data/sample_data/jacksboro_fault_dem.npz", "elevation.npy");
    ASSERT_EQ(a.shape.size(), 2u);
    EXPECT_EQ(a.shape[0], 344u);
    EXPECT_EQ(a.shape[1], 403u);
    EXPECT_EQ(*std::min_element(a.values.begin(), a.values.end()), 236);
    EXPECT_EQ(*std::max_element(a.values.begin(), a.values.end()), 1076);
}

}  // namespace
}  // namespace pxh

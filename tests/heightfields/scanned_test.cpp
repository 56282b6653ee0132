// Scanned height fields: the committed files, mirroring, hole masks, the npz/PLY/OFF readers,
// and hostile image files.
#include "heightfields/scanned.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "harness/core/error.h"
#include "heightfields/heightfields.h"
#include "heightfields/scan_io.h"
#include "tests/cli_util.h"

namespace pxh {
namespace {

namespace fs = std::filesystem;

const char* const kScans[] = {"jacksboro", "motorcycle", "bunny",      "lidar_b9", "topobathy",
                              "egm96",     "olinda",     "luxembourg", "aloe"};

std::string scan_path(const std::string& file) {
    return std::string(PXH_SOURCE_DIR) + "/heightfields/scanned/" + file;
}

nlohmann::json scan_meta(const std::string& name) {
    std::ifstream f(scan_path(name + ".json"));
    return nlohmann::json::parse(f);
}

TEST(Scanned, TheNineScansAreListedWithProvenance) {
    const auto scans = list_scans();
    std::vector<std::string> names;
    for (const auto& s : scans) names.push_back(s.name);
    for (const char* n : kScans)
        EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
    EXPECT_GE(scans.size(), 9u);
    for (const auto& s : scans) {
        const std::string json = test::source_file("heightfields/scanned/" + s.name + ".json");
        for (const char* key :
             {"package", "package_version", "path_in_package", "original", "value_range", "units",
              "grid_spacing", "licence", "holes", "tiling"})
            EXPECT_NE(json.find(std::string("\"") + key + "\""), std::string::npos)
                << s.name << " " << key;
    }
}

// The new scans against their sources as read independently (NumPy and PIL on the files in
// the packages): shapes, value ranges, hole counts (no-data / zero cells) and a few texels,
// which also pins the row order (row 0 = first stored row).
TEST(Scanned, NewScansMatchTheirSources) {
    struct Fact {
        const char* name;
        int w, h;
        double lo, hi;
        int holes;
        int i, j;      // a measured texel
        double value;  // its source value
    };
    const Fact facts[] = {{"topobathy", 120, 91, -1437, 2205, 0, 60, 45, 299},
                          {"olinda", 111, 111, -1, 88, 0, 30, 20, 51},
                          {"luxembourg", 95, 90, 141, 547, 3942, 50, 45, 280},
                          {"aloe", 1282, 1110, 43, 211, 49130, 600, 500, 65},
                          {"egm96", 1440, 721, -106.99109, 85.39092, 0, 0, 360, 21.15333}};
    for (const Fact& f : facts) {
        const auto meta = scan_meta(f.name);
        EXPECT_EQ(meta["size"][0], f.w) << f.name;
        EXPECT_EQ(meta["size"][1], f.h) << f.name;
        const double lo = meta["value_range"][0], hi = meta["value_range"][1];
        EXPECT_NEAR(lo, f.lo, 1e-4) << f.name;
        EXPECT_NEAR(hi, f.hi, 1e-4) << f.name;
        EXPECT_EQ(meta["holes"]["count"], f.holes) << f.name;
        EXPECT_EQ(meta["holes"].contains("mask"), f.holes > 0) << f.name;
        const HeightField base = load_heightfield_file(scan_path(std::string(f.name) + ".png"));
        ASSERT_EQ(base.width, f.w);
        EXPECT_NEAR(base.at(f.i, f.j), (f.value - lo) / (hi - lo), 1.0 / 65535) << f.name;
    }
    // Luxembourg's texel (60, 10) is no-data in the source: filled and flagged.
    const HeightField lux = load_scan("luxembourg", "test");
    EXPECT_EQ(lux.filled.at(size_t(10) * lux.width + 60), 1);
    EXPECT_EQ(lux.filled.at(size_t(45) * lux.width + 50), 0);
}

// The geoid is periodic in longitude (no mirroring in x) and runs pole to pole: past a pole the
// tile continues down the opposite meridian, W x 2(H-1).
TEST(Scanned, GeoidTilesPeriodicInXAndOverThePoles) {
    const HeightField base = load_heightfield_file(scan_path("egm96.png"));
    const HeightField hf = load_scan("egm96", "test");
    ASSERT_EQ(base.width, 1440);
    ASSERT_EQ(base.height, 721);
    ASSERT_EQ(hf.width, 1440);
    ASSERT_EQ(hf.height, 1440);
    for (int j = 0; j < 1440; ++j)
        for (int i = 0; i < 1440; ++i) {
            const float want = j <= 720 ? base.at(i, j) : base.at((i + 720) % 1440, 1440 - j);
            ASSERT_EQ(hf.at(i, j), want) << i << " " << j;
        }
    // The poles are single points: their rows are constant.
    for (int i = 0; i < 1440; ++i) {
        ASSERT_EQ(base.at(i, 0), base.at(0, 0));
        ASSERT_EQ(base.at(i, 720), base.at(0, 720));
    }
    // Longitude wraps: the seam between column 1439 and column 0 is no steeper than the
    // steepest step between neighbouring columns inside the grid.
    float seam = 0, inside = 0;
    for (int j = 0; j < 721; ++j) {
        seam = std::max(seam, std::abs(base.at(0, j) - base.at(1439, j)));
        for (int i = 0; i + 1 < 1440; ++i)
            inside = std::max(inside, std::abs(base.at(i + 1, j) - base.at(i, j)));
    }
    EXPECT_LE(seam, inside);
    EXPECT_GT(seam, 0.0f);
}

// A scan's "tiling" is checked: an unknown rule, or "pole" without a periodic x, is refused
// with the JSON named; an older file's "periodic": true loads as stored.
TEST(Scanned, TilingRulesAreChecked) {
    const fs::path dir = fs::temp_directory_path() / ("pxh_tiling_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    fs::copy_file(scan_path("olinda.png"), dir / "o.png");
    auto meta = [&](const std::string& tiling) {
        std::ofstream(dir / "o.json") << "{\"name\": \"o\", \"file\": \"o.png\", " << tiling << "}";
    };
    auto error_of = [&] {
        try {
            load_scan("o", "test", dir.string());
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    meta("\"periodic\": true");
    EXPECT_EQ(load_scan("o", "test", dir.string()).width, 111);
    meta("\"tiling\": {\"x\": \"periodic\", \"y\": \"mirror\"}");
    const HeightField half = load_scan("o", "test", dir.string());
    EXPECT_EQ(half.width, 111);
    EXPECT_EQ(half.height, 222);
    meta("\"tiling\": {\"x\": \"mirror\", \"y\": \"pole\"}");
    EXPECT_NE(error_of().find("o.json: tiling y = \"pole\" needs x periodic"), std::string::npos)
        << error_of();
    meta("\"tiling\": {\"x\": \"twist\", \"y\": \"mirror\"}");
    EXPECT_NE(error_of().find("o.json: tiling x must be"), std::string::npos) << error_of();
    fs::remove_all(dir);
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
    const std::string j = test::source_file("heightfields/scanned/motorcycle.json");
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
        EXPECT_NE(std::string(e.what()).find("exp.toml:3: unknown scan 'nope' (known: aloe, bunny"),
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

std::string be_double(double d) {
    uint64_t u;
    std::memcpy(&u, &d, 8);
    std::string out;
    for (int k = 7; k >= 0; --k) out += char(u >> (8 * k));
    return out;
}

// .gtx: the big-endian header and values as written here; a wrong length is refused.
TEST_F(ScanFiles, GtxGridIsReadBigEndian) {
    std::string gtx =
        be_double(-90) + be_double(-180) + be_double(90) + be_double(120) + be32(3) + be32(3);
    const float v[9] = {1.5f, -2.25f, 3, 4, 5, 6, 7, 8, -106.99109f};
    for (float x : v) {
        uint32_t u;
        std::memcpy(&u, &x, 4);
        gtx += be32(u);
    }
    const GtxGrid g = read_gtx(bytes("g.gtx", gtx));
    EXPECT_EQ(g.rows, 3);
    EXPECT_EQ(g.cols, 3);
    EXPECT_EQ(g.lat0, -90);
    EXPECT_EQ(g.lon0, -180);
    EXPECT_EQ(g.dlat, 90);
    EXPECT_EQ(g.dlon, 120);
    ASSERT_EQ(g.values.size(), 9u);
    EXPECT_EQ(g.values[1], -2.25);
    EXPECT_EQ(g.values[8], double(-106.99109f));
    std::string err;
    try {
        read_gtx(bytes("short.gtx", gtx.substr(0, gtx.size() - 1)));
    } catch (const InputError& e) {
        err = e.what();
    }
    EXPECT_NE(err.find("short.gtx: .gtx is 75 bytes, its header needs 76"), std::string::npos)
        << err;
}

// TIFF tags in both byte orders: an ASCII value stored inline (4 bytes or less) and one at an
// offset, DOUBLEs at an offset, a SHORT inline; an absent tag is not found.
TEST_F(ScanFiles, TiffTagsAreReadInBothByteOrders) {
    for (const bool big : {false, true}) {
        auto u16 = [&](uint16_t x) {
            return big ? std::string{char(x >> 8), char(x)} : std::string{char(x), char(x >> 8)};
        };
        auto u32 = [&](uint32_t x) {
            std::string b = be32(x);
            return big ? b : std::string(b.rbegin(), b.rend());
        };
        auto f64 = [&](double d) {
            std::string b = be_double(d);
            return big ? b : std::string(b.rbegin(), b.rend());
        };
        // Header (8) + IFD at 8: 4 entries (2 + 48 + 4 bytes), data from 62.
        std::string t = std::string(big ? "MM\0*" : "II*\0", 4) + u32(8) + u16(4);
        t += u16(256) + u16(3) + u32(1) + u16(95) + u16(0);           // width, SHORT
        t += u16(33550) + u16(12) + u32(2) + u32(62);                 // pixel scale
        t += u16(42113) + u16(2) + u32(4) + std::string("-99\0", 4);  // inline ASCII
        t += u16(34737) + u16(2) + u32(8) + u32(78);                  // ASCII at an offset
        t += u32(0) + f64(0.25) + f64(-89.5) + std::string("UTM 25|\0", 8);
        const std::string path = bytes(big ? "b.tif" : "l.tif", t);
        EXPECT_EQ(read_tiff_tag(path, 256).values, std::vector<double>{95}) << big;
        EXPECT_EQ(read_tiff_tag(path, 33550).values, (std::vector<double>{0.25, -89.5})) << big;
        EXPECT_EQ(read_tiff_tag(path, 42113).ascii, "-99") << big;
        EXPECT_EQ(read_tiff_tag(path, 34737).ascii, "UTM 25|") << big;
        EXPECT_FALSE(read_tiff_tag(path, 42112).found);
    }
    std::string err;
    try {
        read_tiff_tag(bytes("x.tif", "GIF89a"), 1);
    } catch (const InputError& e) {
        err = e.what();
    }
    EXPECT_NE(err.find("x.tif: not a (classic) TIFF file"), std::string::npos) << err;
}

}  // namespace
}  // namespace pxh

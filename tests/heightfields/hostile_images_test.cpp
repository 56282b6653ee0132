// Height files as an attacker (or an accident) writes them: FIFOs and devices, OpenEXR headers
// that make OpenEXR allocate gigabytes, truncated files of every accepted format, alpha and
// palettes, netpbm headers with impossible values. Every file here is written by the test,
// through OpenImageIO or byte by byte.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "harness/core/error.h"
#include "heightfields/heightfields.h"
#include "tests/cli_util.h"

namespace pxh {
namespace {

namespace fs = std::filesystem;

// ---- helpers ----

using test::slurp;

long long vm_peak_kb() {
    std::ifstream f("/proc/self/status");
    for (std::string line; std::getline(f, line);)
        if (line.rfind("VmPeak:", 0) == 0) return std::atoll(line.c_str() + 7);
    return -1;
}

// load_heightfield_file in a forked child: a load that blocks is killed by alarm() instead of
// hanging the test, a crash is seen as one, and the growth of the child's peak virtual memory
// (VmPeak; fork starts it at the current size) measures what the load allocated, touched or
// not.
struct ChildLoad {
    bool finished = false;  // false: killed (it hung) or crashed
    bool loaded = false;
    std::string error;  // the InputError's text, or "other exception: ..."
    long long vm_growth_mb = -1;
};

ChildLoad load_in_child(const std::string& path, int channel = 0, unsigned timeout_s = 10) {
    int fds[2];
    if (pipe(fds) != 0) return {};
    std::fflush(stdout);
    std::fflush(stderr);
    const pid_t pid = fork();
    if (pid == 0) {
        close(fds[0]);
        alarm(timeout_s);
        const long long before = vm_peak_kb();
        std::string msg;
        try {
            load_heightfield_file(path, channel);
            msg = "L";
        } catch (const InputError& e) {
            msg = std::string("E") + e.what();
        } catch (const std::exception& e) {
            msg = std::string("Eother exception: ") + e.what();
        }
        msg = std::to_string((vm_peak_kb() - before) / 1024) + " " + msg;
        if (write(fds[1], msg.data(), msg.size()) < 0) _exit(3);
        _exit(0);
    }
    close(fds[1]);
    std::string got;
    char buf[4096];
    for (ssize_t n; (n = read(fds[0], buf, sizeof buf)) > 0;) got.append(buf, size_t(n));
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    ChildLoad r;
    const size_t space = got.find(' ');
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || space == std::string::npos) return r;
    r.finished = true;
    r.vm_growth_mb = std::atoll(got.c_str());
    r.loaded = got[space + 1] == 'L';
    if (!r.loaded) r.error = got.substr(space + 2);
    return r;
}

class HostileImages : public test::CliTest {
  public:  // the per-format writers below take the fixture as a parameter
    using test::CliTest::dir;

    std::string bytes(const std::string& name, const std::string& b) {
        std::ofstream(dir / name, std::ios::binary) << b;
        return (dir / name).string();
    }
    // Writes w x h x nch pixels (given as floats) through OpenImageIO with extra attributes.
    std::string image(const std::string& name, int w, int h, int nch, OIIO::TypeDesc type,
                      const std::vector<float>& px,
                      const std::vector<std::pair<std::string, std::string>>& attrs = {}) {
        const std::string path = (dir / name).string();
        auto out = OIIO::ImageOutput::create(path);
        EXPECT_TRUE(out) << path;
        if (!out) return path;
        OIIO::ImageSpec spec(w, h, nch, type);
        for (const auto& [k, v] : attrs) {
            if (v.find_first_not_of("0123456789") == std::string::npos)
                spec.attribute(k, std::stoi(v));
            else spec.attribute(k, v);
        }
        if (nch == 2 || nch == 4) {
            // Gray + alpha or RGBA, stored as given (not divided by alpha on the way out).
            spec.alpha_channel = nch - 1;
            spec.attribute("oiio:UnassociatedAlpha", 1);
        }
        EXPECT_TRUE(out->open(path, spec)) << out->geterror();
        EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data())) << out->geterror();
        out->close();
        return path;
    }
    // The refusal of `path`: an InputError, one line, "PATH: ...". Empty if it loaded.
    static std::string refusal(const std::string& path, int channel = 0) {
        try {
            load_heightfield_file(path, channel);
        } catch (const InputError& e) {
            const std::string msg = e.what();
            EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
            EXPECT_EQ(msg.rfind(path + ": ", 0), 0u) << msg;
            return msg;
        }
        return "";
    }
};

std::string le32(uint32_t v) { return {char(v), char(v >> 8), char(v >> 16), char(v >> 24)}; }
std::string be32(uint32_t v) { return {char(v >> 24), char(v >> 16), char(v >> 8), char(v)}; }

// ---- 1. Only regular files ----

TEST_F(HostileImages, FifosAndDevicesAreRefusedWithoutBlocking) {
    const std::string fifo = (dir / "fifo.png").string();
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    const ChildLoad a = load_in_child(fifo);
    ASSERT_TRUE(a.finished) << "loading a FIFO blocked (killed after 10 s)";
    EXPECT_EQ(a.error, fifo + ": is a FIFO, not a regular file");

    // OpenImageIO's IFF reader accepts /dev/zero and reads it forever.
    const std::string zero = (dir / "zero.iff").string();
    fs::create_symlink("/dev/zero", zero);
    const ChildLoad b = load_in_child(zero);
    ASSERT_TRUE(b.finished) << "loading a symlink to /dev/zero did not return (killed after 10 s)";
    EXPECT_EQ(b.error, zero + ": is a character device, not a regular file");

    fs::create_directories(dir / "d.png");
    EXPECT_EQ(refusal((dir / "d.png").string()), (dir / "d.png").string() + ": is a directory");
    const std::string dangling = (dir / "dangling.png").string();
    fs::create_symlink(dir / "nowhere.png", dangling);
    EXPECT_EQ(refusal(dangling), dangling + ": no such file");

    // A symlink to a regular file is followed.
    const std::string real = image("real.png", 2, 1, 1, OIIO::TypeDesc::UINT8, {0.0f, 1.0f});
    fs::create_symlink(real, dir / "link.png");
    EXPECT_FLOAT_EQ(load_heightfield_file((dir / "link.png").string()).at(1, 0), 1.0f);
}

class HostileImagesCli : public test::CliTest {
  protected:
    // `timeout 20 pxh run EXP`: a hang is exit status 124, not a hung test.
    test::CliResult run_with_timeout(const std::string& exp) {
        return pxh_timeout("run " + exp + " --out " + (dir / "res").string() + " --quiet");
    }
    std::string experiment(const std::string& height_file) {
        return write("exp.toml",
                     "name = \"img\"\nsamples = 4\ntiming_repeats = 0\n[views]\n"
                     "theta_deg = [30]\n[[heightfields]]\nfile = \"" +
                         height_file + "\"\n[[methods]]\nname = \"parallax\"\n");
    }
};

TEST_F(HostileImagesCli, FifoAsHeightFileExitsTwoWithOneLine) {
    ASSERT_EQ(mkfifo((dir / "fifo.png").c_str(), 0600), 0);
    const auto r = run_with_timeout(experiment("fifo.png"));
    ASSERT_NE(r.status, 124) << "pxh blocked on a FIFO";
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_EQ(r.err.rfind("pxh: error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find("fifo.png"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("not a regular file"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "res"));
}

// A truncated zip-compressed float TIFF: OpenImageIO's read "succeeds" (the error is only
// recorded), the run must not.
TEST_F(HostileImagesCli, TruncatedTiffExitsTwoWithOneLine) {
    const std::string full = (dir / "full.tif").string();
    {
        auto out = OIIO::ImageOutput::create(full);
        OIIO::ImageSpec spec(64, 64, 1, OIIO::TypeDesc::FLOAT);
        spec.attribute("compression", "zip");
        std::vector<float> px(64 * 64);
        for (size_t i = 0; i < px.size(); ++i) px[i] = float(i * 37 % 101) / 100.0f;
        ASSERT_TRUE(out->open(full, spec) && out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
        out->close();
    }
    const std::string data = slurp(full);
    write("cut.tif", data.substr(0, data.size() / 2));
    const auto r = run_with_timeout(experiment("cut.tif"));
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("cut.tif"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("cannot read pixels"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "res"));
}

// ---- 2. OpenEXR headers are checked before OpenEXR allocates ----

// Offset of the value of attribute NAME (of TYPE) in an OpenEXR file, or npos.
size_t exr_value_at(const std::string& exr, const std::string& name, const std::string& type) {
    const std::string key = name + '\0' + type + '\0';
    const size_t at = exr.find(key);
    return at == std::string::npos ? at : at + key.size() + 4;
}

// An attribute as OpenEXR stores it, claiming `size` bytes and holding `value`.
std::string exr_attribute(const std::string& name, const std::string& type, uint32_t size,
                          const std::string& value) {
    return name + '\0' + type + '\0' + le32(size) + value;
}

TEST_F(HostileImages, OpenExrHeaderIsCheckedBeforeOpenExrAllocates) {
    std::vector<float> px(8 * 6);
    for (size_t i = 0; i < px.size(); ++i) px[i] = float(i) / 47.0f;
    const std::string good = image("good.exr", 8, 6, 1, OIIO::TypeDesc::FLOAT, px);
    const std::string exr = slurp(good);
    ASSERT_LT(exr.size(), 1000u);
    EXPECT_FLOAT_EQ(load_heightfield_file(good).at(3, 2), 19 / 47.0f);

    struct Case {
        std::string name, file, expect;
    };
    std::vector<Case> cases;
    // An attribute of an unknown type claiming 2 GB: OpenEXR allocates the 2 GB, then finds
    // the file too short.
    cases.push_back(
        {"opaque.exr",
         exr.substr(0, 8) + exr_attribute("junk", "opaque", 0x7ff00000u, "x") + exr.substr(8),
         "OpenEXR attribute 'junk' claims 2146435072 bytes, more than the file holds"});
    // A string attribute (the capture date) claiming 2 GB.
    {
        std::string x = exr;
        const size_t at = exr_value_at(x, "capDate", "string");
        ASSERT_NE(at, std::string::npos);
        x.replace(at - 4, 4, le32(0x7ff00000u));
        cases.push_back({"string.exr", x, "OpenEXR attribute 'capDate' claims 2146435072 bytes"});
    }
    // A preview whose width and height (60000 x 60000 RGBA: 14 GB) disagree with its size.
    cases.push_back(
        {"preview.exr",
         exr.substr(0, 8) +
             exr_attribute("preview", "preview", 12, le32(60000) + le32(60000) + "abcd") +
             exr.substr(8),
         "OpenEXR attribute 'preview' claims a 60000 x 60000 preview in 12 bytes"});
    // A string vector holding a string of 2 GB.
    cases.push_back({"strvec.exr",
                     exr.substr(0, 8) +
                         exr_attribute("names", "stringvector", 8, le32(0x7ff00000u) + "abcd") +
                         exr.substr(8),
                     "OpenEXR attribute 'names' holds a string longer than the attribute"});
    // A data window of 100000 x 100000 texels.
    {
        std::string x = exr;
        const size_t at = exr_value_at(x, "dataWindow", "box2i");
        ASSERT_NE(at, std::string::npos);
        x.replace(at + 8, 8, le32(99999) + le32(99999));
        cases.push_back({"window.exr", x, "image is 100000 x 100000, larger than the accepted"});
    }
    // 8000 x 8000 is within the limits, but its 8000 scanline chunks need an offset table of
    // 64000 bytes that this file does not hold.
    {
        std::string x = exr;
        const size_t at = exr_value_at(x, "dataWindow", "box2i");
        x.replace(at + 8, 8, le32(7999) + le32(7999));
        const size_t c = exr_value_at(x, "compression", "compression");
        ASSERT_NE(c, std::string::npos);
        x[c] = 0;  // none: one scanline per chunk
        cases.push_back(
            {"chunks.exr", x, "OpenEXR chunk offset table (8000 entries) runs past the end"});
    }
    // 65 channels: more than kMaxImageChannels.
    {
        std::string chlist;
        for (int k = 0; k < 65; ++k)
            chlist +=
                "c" + std::to_string(k) + '\0' + le32(2) + std::string(4, '\0') + le32(1) + le32(1);
        chlist += '\0';
        std::string x = exr;
        const size_t at = exr_value_at(x, "channels", "chlist");
        ASSERT_NE(at, std::string::npos);
        const uint32_t old_size = uint8_t(x[at - 4]) | uint8_t(x[at - 3]) << 8;
        x.replace(at - 4, 4 + old_size, le32(uint32_t(chlist.size())) + chlist);
        cases.push_back({"channels.exr", x, "image has more than the accepted 64 channels"});
    }
    for (const auto& c : cases) {
        const std::string path = bytes(c.name, c.file);
        const ChildLoad r = load_in_child(path);
        ASSERT_TRUE(r.finished) << c.name << " crashed or hung the loader";
        EXPECT_FALSE(r.loaded) << c.name;
        EXPECT_EQ(r.error.rfind(path + ": " + c.expect, 0), 0u) << c.name << ": " << r.error;
        EXPECT_EQ(r.error.find('\n'), std::string::npos) << r.error;
        // Refused from the header: the load did not reserve even 100 MB.
        EXPECT_LT(r.vm_growth_mb, 100) << c.name << ": peak virtual memory grew by "
                                       << r.vm_growth_mb << " MB before the refusal";
    }
}

// The PNG, TIFF and netpbm headers claiming huge images are refused before allocation as well
// (OpenImageIO's own PGM reader allocated 4 GB, and threw, for a 4e9 x 1 header).
TEST_F(HostileImages, HugeHeadersOfOtherFormatsAllocateNothing) {
    const std::string pgm = bytes("wide.pgm", "P5\n4000000000 1\n255\n" + std::string(16, 'x'));
    const std::string pfm = bytes("wide.pfm", "Pf\n100000 100000\n-1.0\n0000");
    // A TIFF whose width and height tags are patched to 100000.
    const std::string small =
        image("small.tif", 4, 3, 1, OIIO::TypeDesc::UINT16, std::vector<float>(12, 0.5f));
    std::string tif = slurp(small);
    ASSERT_EQ(tif.substr(0, 4), std::string("II*\0", 4));
    const uint32_t ifd =
        uint8_t(tif[4]) | uint8_t(tif[5]) << 8 | uint8_t(tif[6]) << 16 | uint8_t(tif[7]) << 24;
    const int entries = uint8_t(tif[ifd]) | uint8_t(tif[ifd + 1]) << 8;
    for (int e = 0; e < entries; ++e) {
        const size_t at = ifd + 2 + 12 * size_t(e);
        const int tag = uint8_t(tif[at]) | uint8_t(tif[at + 1]) << 8;
        if (tag == 256 || tag == 257) {  // ImageWidth, ImageLength: as a LONG of 100000
            tif.replace(at + 2, 10, std::string("\x04\x00\x01\x00\x00\x00", 6) + le32(100000));
        }
    }
    const std::string big_tif = bytes("big.tif", tif);
    for (const std::string& path : {pgm, pfm, big_tif}) {
        const ChildLoad r = load_in_child(path);
        ASSERT_TRUE(r.finished) << path << " crashed or hung the loader";
        EXPECT_NE(r.error.find(path + ": image is "), std::string::npos) << r.error;
        EXPECT_NE(r.error.find(", larger than the accepted 16384 per side"), std::string::npos)
            << r.error;
        EXPECT_LT(r.vm_growth_mb, 100) << path;
    }
    // Within the limits (16384 x 4096: a 256 MB field) but the file cannot hold the pixels:
    // a netpbm file is refused before the field is allocated.
    const std::string raw = bytes("raw.pgm", "P5\n16384 4096\n255\nabc");
    const std::string plain = bytes("plain.pgm", "P2\n16384 4096\n65535\n1 2 3\n");
    for (const auto& [path, expect] :
         {std::pair{raw, ": truncated: 3 bytes of pixel data, the header promises 67108864"},
          std::pair{
              plain,
              ": truncated: 6 bytes of pixel data, the header promises at least 134217727"}}) {
        const ChildLoad r = load_in_child(path);
        ASSERT_TRUE(r.finished) << path << " crashed or hung the loader";
        EXPECT_EQ(r.error, path + expect);
        EXPECT_LT(r.vm_growth_mb, 100) << path;
    }
}

// ---- 3. Truncation of every accepted format ----

struct Format {
    std::string name;
    std::function<std::string(HostileImages&, const std::vector<float>&)> write;
    float tolerance;  // of the full file's heights against the pixels written; < 0: lossy
};

TEST_F(HostileImages, EveryFormatTruncatedAtEveryTenthIsRefused) {
    const int w = 64, h = 48;
    std::vector<float> px(w * h);
    for (size_t i = 0; i < px.size(); ++i) px[i] = float(i * 37 % 101) / 100.0f;
    auto oiio = [&](const char* file, OIIO::TypeDesc t,
                    std::vector<std::pair<std::string, std::string>> a) {
        return [=](HostileImages& self, const std::vector<float>& p) {
            return self.image(file, w, h, 1, t, p, a);
        };
    };
    auto pgm = [&](bool plain, int maxval, const char* file) {
        return [=](HostileImages& self, const std::vector<float>& p) {
            std::string s = std::string(plain ? "P2" : "P5") + "\n# a comment\n" +
                            std::to_string(w) + " " + std::to_string(h) + "\n" +
                            std::to_string(maxval) + "\n";
            for (size_t i = 0; i < p.size(); ++i) {
                const int v = int(std::lround(p[i] * maxval));
                if (plain) s += std::to_string(v) + (i % 16 == 15 ? "\n" : " ");
                else if (maxval < 256) s += char(v);
                else s += std::string{char(v >> 8), char(v)};
            }
            return self.bytes(file, s);
        };
    };
    const std::vector<Format> formats = {
        {"PNG 8-bit", oiio("a.png", OIIO::TypeDesc::UINT8, {}), 0.6f / 255},
        {"PNG 16-bit", oiio("b.png", OIIO::TypeDesc::UINT16, {}), 0.6f / 65535},
        {"PNG interlaced", oiio("c.png", OIIO::TypeDesc::UINT8, {{"png:interlace", "1"}}),
         0.6f / 255},
        {"TIFF float zip", oiio("d.tif", OIIO::TypeDesc::FLOAT, {{"compression", "zip"}}), 0},
        {"TIFF float uncompressed", oiio("e.tif", OIIO::TypeDesc::FLOAT, {{"compression", "none"}}),
         0},
        {"TIFF 16-bit lzw", oiio("f.tif", OIIO::TypeDesc::UINT16, {{"compression", "lzw"}}),
         0.6f / 65535},
        {"OpenEXR float zip", oiio("g.exr", OIIO::TypeDesc::FLOAT, {{"compression", "zip"}}), 0},
        {"OpenEXR half uncompressed",
         oiio("h.exr", OIIO::TypeDesc::HALF, {{"compression", "none"}}), 1e-3f},
        {"OpenEXR half piz", oiio("i.exr", OIIO::TypeDesc::HALF, {{"compression", "piz"}}), 1e-3f},
        {"JPEG", oiio("j.jpg", OIIO::TypeDesc::UINT8, {}), -1},
        {"JPEG progressive", oiio("k.jpg", OIIO::TypeDesc::UINT8, {{"jpeg:progressive", "1"}}), -1},
        {"PGM raw 8-bit", pgm(false, 255, "l.pgm"), 0.6f / 255},
        {"PGM raw 16-bit", pgm(false, 65535, "m.pgm"), 0.6f / 65535},
        {"PGM plain", pgm(true, 1000, "n.pgm"), 0.6f / 1000},
        {"PFM",
         [&](HostileImages& self, const std::vector<float>& p) {
             std::string s = "Pf\n" + std::to_string(w) + " " + std::to_string(h) + "\n-1.0\n";
             s.append(reinterpret_cast<const char*>(p.data()), p.size() * 4);
             return self.bytes("o.pfm", s);
         },
         0},
    };
    for (const Format& f : formats) {
        const std::string full = f.write(*this, px);
        // The complete file loads (so the refusals below are about truncation).
        const HeightField hf = load_heightfield_file(full);
        ASSERT_EQ(hf.width, w) << f.name;
        ASSERT_EQ(hf.height, h) << f.name;
        if (f.tolerance >= 0) {
            for (size_t i = 0; i < px.size(); ++i)
                ASSERT_NEAR(hf.texels[i], px[i], f.tolerance) << f.name << " texel " << i;
        }
        const std::string data = slurp(full);
        for (int tenth = 1; tenth <= 9; ++tenth) {
            const std::string cut =
                bytes("cut_" + std::to_string(tenth) + "_" + fs::path(full).filename().string(),
                      data.substr(0, data.size() * tenth / 10));
            EXPECT_NE(refusal(cut), "")
                << f.name << " cut to " << tenth << "0% loaded as a complete field";
        }
    }
}

// The one truncation no reader can see: a plain (ASCII) netpbm file cut inside its last
// number is a valid file whose last sample has fewer digits. Cut anywhere before that
// number, it is refused.
TEST_F(HostileImages, PlainPgmCutInsideItsLastNumberIsTheDocumentedLimit) {
    const std::string cut = bytes("cut.pgm", "P2\n2 1\n1000\n500 99");  // "999" lost a digit
    EXPECT_FLOAT_EQ(load_heightfield_file(cut).at(1, 0), 99 / 1000.0f);
    const std::string shorter = bytes("shorter.pgm", "P2\n2 1\n1000\n500 ");
    EXPECT_NE(refusal(shorter).find("truncated: 1 of the 2 samples the header promises"),
              std::string::npos);
}

// ---- 4. Alpha, palettes, netpbm values ----

TEST_F(HostileImages, AlphaDoesNotScaleTheHeight) {
    // Gray 0.6 everywhere, alpha ramping 0 .. 1: the heights are 0.6, not a ramp.
    std::vector<float> ga;
    for (int i = 0; i < 4; ++i) ga.insert(ga.end(), {153 / 255.0f, float(i) / 3});
    const std::string gray_alpha = image("ga.png", 4, 1, 2, OIIO::TypeDesc::UINT8, ga);
    const HeightField a = load_heightfield_file(gray_alpha);
    for (int i = 0; i < 4; ++i) EXPECT_FLOAT_EQ(a.at(i, 0), 153 / 255.0f) << "texel " << i;
    EXPECT_FLOAT_EQ(load_heightfield_file(gray_alpha, 1).at(1, 0), 85 / 255.0f);  // alpha itself

    // RGBA with alpha 0: red is still what the file holds.
    const std::vector<float> rgba{200 / 255.0f, 0.2f, 0.4f, 0.0f, 50 / 255.0f, 0.2f, 0.4f, 1.0f};
    EXPECT_FLOAT_EQ(
        load_heightfield_file(image("rgba.png", 2, 1, 4, OIIO::TypeDesc::UINT8, rgba)).at(0, 0),
        200 / 255.0f);
    // The same in a 16-bit TIFF with unassociated alpha.
    const std::string tif = image("rgba.tif", 2, 1, 4, OIIO::TypeDesc::UINT16, rgba);
    EXPECT_NEAR(load_heightfield_file(tif).at(0, 0), 200 / 255.0f, 1e-4);
}

std::string png_chunk(const std::string& type_and_data) {
    const uint32_t crc =
        crc32(0, reinterpret_cast<const Bytef*>(type_and_data.data()), uInt(type_and_data.size()));
    return be32(uint32_t(type_and_data.size() - 4)) + type_and_data + be32(crc);
}

// A palette PNG: the height is the palette entry's red (OpenImageIO expands the palette to
// RGB, or RGBA with a tRNS chunk), never the index, and not scaled by the entry's alpha.
TEST_F(HostileImages, PalettePngGivesTheEntrysRed) {
    // 2 x 2, 8-bit indices; entries 0: (200, 10, 20), 1: (50, 60, 70), 2: (255, 0, 0);
    // alphas 255, 0, 128.
    const std::string rows("\x00\x01\x00\x00\x02\x01", 6);  // filter byte 0 before each row
    uLongf zlen = compressBound(uLong(rows.size()));
    std::string z(zlen, '\0');
    ASSERT_EQ(compress(reinterpret_cast<Bytef*>(z.data()), &zlen,
                       reinterpret_cast<const Bytef*>(rows.data()), uLong(rows.size())),
              Z_OK);
    z.resize(zlen);
    const std::string png =
        std::string("\x89PNG\r\n\x1a\n", 8) +
        png_chunk("IHDR" + be32(2) + be32(2) + std::string("\x08\x03\x00\x00\x00", 5)) +
        png_chunk(std::string("PLTE\xc8\x0a\x14\x32\x3c\x46\xff\x00\x00", 13)) +
        png_chunk(std::string("tRNS\xff\x00\x80", 7)) + png_chunk("IDAT" + z) + png_chunk("IEND");
    const std::string path = bytes("palette.png", png);
    const HeightField red = load_heightfield_file(path);
    EXPECT_FLOAT_EQ(red.at(0, 0), 50 / 255.0f);   // index 1, alpha 0: its red, not 0
    EXPECT_FLOAT_EQ(red.at(1, 0), 200 / 255.0f);  // index 0
    EXPECT_FLOAT_EQ(red.at(0, 1), 1.0f);          // index 2, alpha 128: not halved
    EXPECT_FLOAT_EQ(red.at(1, 1), 50 / 255.0f);
    EXPECT_FLOAT_EQ(load_heightfield_file(path, 1).at(0, 0), 60 / 255.0f);   // green
    EXPECT_FLOAT_EQ(load_heightfield_file(path, 3).at(0, 1), 128 / 255.0f);  // alpha
    EXPECT_NE(refusal(path, 4).find("channel 4 requested, image has 4"), std::string::npos);
}

TEST_F(HostileImages, NetpbmValuesAreExactAndImpossibleHeadersRefused) {
    const std::string two_floats = le32(0x3e800000) + le32(0x3f000000);  // 0.25, 0.5
    // PFM: values times |scale| (OpenImageIO's reading, kept); scale 0 or not a number refused.
    EXPECT_FLOAT_EQ(load_heightfield_file(bytes("s2.pfm", "Pf\n2 1\n-2.0\n" + two_floats)).at(1, 0),
                    1.0f);
    EXPECT_FLOAT_EQ(
        load_heightfield_file(bytes("be.pfm", "Pf\n1 1\n1.0\n" + be32(0x3e800000))).at(0, 0),
        0.25f);
    EXPECT_NE(refusal(bytes("s0.pfm", "Pf\n2 1\n0\n" + two_floats))
                  .find("PFM scale '0' is not a finite non-zero number"),
              std::string::npos);
    EXPECT_NE(refusal(bytes("sm0.pfm", "Pf\n2 1\n-0.0\n" + two_floats)).find("PFM scale '-0.0'"),
              std::string::npos);
    EXPECT_NE(refusal(bytes("snan.pfm", "Pf\n2 1\nnan\n" + two_floats)).find("PFM scale 'nan'"),
              std::string::npos);
    // PGM maxval 0 (OpenImageIO loaded ones) and above 65535 are refused.
    EXPECT_NE(refusal(bytes("m0.pgm", "P2\n2 1\n0\n0 0\n")).find("maxval 0 is outside 1..65535"),
              std::string::npos);
    EXPECT_NE(refusal(bytes("m0b.pgm", "P5\n2 1\n0\n\x01\x02")).find("maxval 0 is outside"),
              std::string::npos);
    EXPECT_NE(refusal(bytes("m7.pgm", "P2\n2 1\n70000\n5 20\n")).find("maxval 70000 is outside"),
              std::string::npos);
    // Samples above maxval (OpenImageIO clamped them), negative or not numbers are refused.
    EXPECT_NE(refusal(bytes("over.pgm", "P2\n2 1\n10\n5 20\n"))
                  .find("sample 20 at texel (1, 0) is above maxval 10"),
              std::string::npos);
    EXPECT_NE(refusal(bytes("overb.pgm", std::string("P5\n2 1\n1000\n\x01\xf4\x13\xe8", 16)))
                  .find("sample 5096 at texel (1, 0) is above maxval 1000"),
              std::string::npos);
    EXPECT_NE(refusal(bytes("neg.pgm", "P2\n2 1\n10\n-5 2\n"))
                  .find("sample '-5' at texel (0, 0) is not a number"),
              std::string::npos);
    // 0..maxval maps exactly to [0,1] (OpenImageIO went through 8 or 16 bits: 5/10 gave
    // 0.498, and a raw 16-bit file with maxval 1000 did not load at all).
    EXPECT_FLOAT_EQ(load_heightfield_file(bytes("ten.pgm", "P2\n2 1\n10\n5 10\n")).at(0, 0), 0.5f);
    const HeightField k =
        load_heightfield_file(bytes("k.pgm", std::string("P5\n2 1\n1000\n\x01\xf4\x03\xe8", 16)));
    EXPECT_FLOAT_EQ(k.at(0, 0), 0.5f);
    EXPECT_FLOAT_EQ(k.at(1, 0), 1.0f);
    // Colour (channel chooses) and bitmaps (1 is black: height 0).
    EXPECT_FLOAT_EQ(load_heightfield_file(bytes("c.ppm", "P3\n2 1\n10\n1 2 3 4 5 6\n"), 2).at(1, 0),
                    0.6f);
    EXPECT_FLOAT_EQ(
        load_heightfield_file(bytes("c6.ppm", std::string("P6\n1 1\n255\n\x00\x80\xff", 14)), 1)
            .at(0, 0),
        128 / 255.0f);
    const HeightField p1 = load_heightfield_file(bytes("b.pbm", "P1\n3 1\n011\n"));
    EXPECT_EQ(p1.texels, (std::vector<float>{1.0f, 0.0f, 0.0f}));
    const HeightField p4 = load_heightfield_file(bytes("b4.pbm", std::string("P4\n3 1\n\x40", 8)));
    EXPECT_EQ(p4.texels, (std::vector<float>{1.0f, 0.0f, 1.0f}));
}

// ---- 5. Unknown formats and library messages: one line naming the file ----

TEST_F(HostileImages, OnlyTheListedFormatsAreRead) {
    // A Radiance HDR file is an image OpenImageIO reads, but not one pxh accepts.
    const std::string hdr =
        image("x.hdr", 2, 1, 3, OIIO::TypeDesc::FLOAT, std::vector<float>(6, 0.5f));
    EXPECT_NE(refusal(hdr).find(
                  "not a readable image (not a PNG, TIFF, OpenEXR, JPEG, PGM/PPM/PBM or PFM file)"),
              std::string::npos);
    // A PNG named .exr is read as the PNG it is.
    const std::string png = image("p.png", 2, 1, 1, OIIO::TypeDesc::UINT8, {0.0f, 1.0f});
    fs::copy_file(png, dir / "p.exr");
    EXPECT_FLOAT_EQ(load_heightfield_file((dir / "p.exr").string()).at(1, 0), 1.0f);
    // A file name with a line break still gives a one-line error.
    const std::string odd = bytes("odd\nname.png", "not an image");
    std::string msg;
    try {
        load_heightfield_file(odd);
    } catch (const InputError& e) {
        msg = e.what();
    }
    EXPECT_NE(msg.find("odd\\nname.png: not a readable image"), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos);
}

}  // namespace
}  // namespace pxh

// Error-map file names carry the setting: two settings of one method at one view get names
// that differ in their parameters, long parameter strings are cut and ended by their hash,
// and only safe characters reach the file system.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "harness/core/sha256.h"
#include "harness/metrics/row.h"
#include "harness/results/error_maps.h"

namespace pxh {
namespace {

ResultRow map_row(const std::string& method, const std::string& params) {
    ResultRow r;
    r.set_text("method", method);
    r.set_text("params", params);
    r.set_text("heightfield", "fbm");
    r.set("theta_deg", 60);
    r.set("phi_deg", 0);
    r.set_text("backend", "cpu");
    r.set_text("precision", "float");
    return r;
}

TEST(ErrorMapName, CarriesTheSettingsParameters) {
    EXPECT_EQ(error_map_name(map_row("pom", "layers=32;layers_min=off"), 12).stem,
              "00012_pom_layers-32_layers_min-off_fbm_t60_p0_cpu-float");
    EXPECT_EQ(error_map_name(map_row("parallax", ""), 3).stem,
              "00003_parallax_fbm_t60_p0_cpu-float");
    // Two settings of one method at one view: different names even without the index.
    const auto a = error_map_name(map_row("pom", "layers=8"), 0).stem;
    const auto b = error_map_name(map_row("pom", "layers=64"), 0).stem;
    EXPECT_NE(a, b);
}

TEST(ErrorMapName, LongParametersCutAndEndedByTheirHash) {
    std::string params;
    for (int i = 0; i < 20; ++i)
        params += (i ? ";" : "") + std::string("knob") + std::to_string(i) + "=1.5";
    const std::string stem = error_map_name(map_row("march", params), 7).stem;
    // 64 characters of parameters at most: 55 of them, '~' (made safe as '_') and 8 hex digits.
    const std::string hash = sha256_hex(params).substr(0, 8);
    EXPECT_NE(stem.find("_" + hash + "_fbm_t60"), std::string::npos) << stem;
    EXPECT_LT(stem.size(), size_t(120)) << stem;
    // Another long string with the same first 55 characters gets another name.
    const std::string other = error_map_name(map_row("march", params + ";x=2"), 7).stem;
    EXPECT_NE(stem, other);
}

TEST(ErrorMapName, OnlySafeCharacters) {
    const std::string stem = error_map_name(map_row("my shader/../x", "a=\"q\";b=off"), 1).stem;
    for (char ch : stem)
        EXPECT_TRUE(std::isalnum((unsigned char)ch) || ch == '_' || ch == '-' || ch == '.') << stem;
    EXPECT_EQ(stem.find('/'), std::string::npos);
}

}  // namespace
}  // namespace pxh

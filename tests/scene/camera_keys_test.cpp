// A camera's own keys are declared once, in its registry entry (CameraEntry::keys), and every
// consumer takes them from there: results.csv's columns, the settings the camera reads, pxh
// check's filters, pxh compare's row keys and the views' file names.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "harness/core/param_dict.h"
#include "harness/metrics/columns.h"
#include "harness/metrics/row.h"
#include "harness/results/error_maps.h"
#include "harness/scene/view.h"
#include "tests/test_util.h"

namespace pxh {
namespace {

TEST(CameraKeys, EveryCamerasKeysAreNumericKeyColumnsRightAfterCamera) {
    std::vector<std::string> declared;
    for (const CameraEntry& e : camera_registry())
        for (const CameraKey& k : e.keys)
            if (std::find(declared.begin(), declared.end(), k.name) == declared.end())
                declared.push_back(k.name);
    // The perspective camera's keys among them (a camera added later brings its own).
    for (const char* k : {"distance", "fov_deg", "resolution"})
        EXPECT_NE(std::find(declared.begin(), declared.end(), k), declared.end()) << k;
    std::vector<std::string> keys;
    for (const CameraKey& k : camera_key_columns()) keys.push_back(k.name);
    EXPECT_EQ(keys, declared);
    const std::vector<std::string> cols = test::result_column_names();
    const auto at = std::find(cols.begin(), cols.end(), "camera");
    ASSERT_NE(at, cols.end());
    for (size_t i = 0; i < declared.size(); ++i) {
        ASSERT_LT(size_t(at - cols.begin()) + 1 + i, cols.size());
        EXPECT_EQ(at[std::ptrdiff_t(1 + i)], declared[i]);
        const ColumnSpec* c = find_column(declared[i]);
        ASSERT_NE(c, nullptr);
        EXPECT_EQ(c->role, ColumnRole::key) << c->name;
        EXPECT_EQ(c->type, ColumnType::number) << c->name;
        EXPECT_FALSE(c->meaning.empty()) << c->name;
    }
    // Tags tell the settings apart in file names: one per key, none shared.
    std::set<std::string> tags;
    for (const CameraKey& k : camera_key_columns()) EXPECT_TRUE(tags.insert(k.tag).second) << k.tag;
}

TEST(CameraKeys, EachSettingsValuesAreItsCamerasKeysInOrder) {
    for (const CameraEntry& e : camera_registry()) {
        // Two values of each of its keys (a valid value of every key of the cameras so far).
        std::string text;
        for (const CameraKey& k : e.keys) text += k.name + " = [32, 48]\n";
        const ParamDict p = ParamDict::parse(text, "v.toml", "[views]");
        const std::vector<CameraSetting> settings = e.read(p, "v.toml:1", 32);
        ASSERT_EQ(settings.size(), size_t(1) << e.keys.size()) << e.name;  // their product
        for (const CameraSetting& s : settings) {
            ASSERT_EQ(s.values.size(), e.keys.size()) << e.name;
            for (size_t i = 0; i < e.keys.size(); ++i) EXPECT_EQ(s.values[i].first, e.keys[i].name);
        }
    }
}

TEST(CameraKeys, FileNamesCarryEachKeyByItsTag) {
    ResultRow r;
    r.set_text("method", "pom");
    r.set_text("heightfield", "f");
    r.set_text("backend", "cpu");
    r.set_text("precision", "float");
    r.set("theta_deg", 70);
    r.set("phi_deg", 0);
    EXPECT_EQ(camera_name_part(r), "");  // the orthographic camera has no keys
    r.set("distance", 1.5);
    r.set("fov_deg", 60);
    r.set("resolution", 256);
    EXPECT_EQ(camera_name_part(r), "_d1.5_f60_r256");
    EXPECT_NE(error_map_name(r, 3).stem.find("_t70_p0_d1.5_f60_r256_cpu-float"), std::string::npos)
        << error_map_name(r, 3).stem;
}

}  // namespace
}  // namespace pxh

// Scanned height fields (heightfields/scanned.h): the scans in a folder listed from their JSON,
// and one loaded as the tile its tiling rule makes (mirrored, periodic, or over the poles).
// `pxh import` writes them: heightfields/scanned_import.cpp.
#include "heightfields/scanned.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "harness/core/error.h"
#include "heightfields/heightfields.h"
#include "heightfields/scan_convert.h"

namespace pxh {

std::string scan::default_scan_dir() {
    return std::string(PXH_SOURCE_DIR) + "/heightfields/scanned";
}

namespace {

using namespace scan;

namespace fs = std::filesystem;
using nlohmann::json;

// The tiling a scan's JSON asks for: "tiling" {x, y}, or (older files) "periodic" for both.
Tiling tiling_of(const json& meta, const std::string& where) {
    Tiling t;
    if (meta.contains("tiling") && meta["tiling"].is_object()) {
        t.x = meta["tiling"].value("x", "");
        t.y = meta["tiling"].value("y", "");
    } else if (meta.value("periodic", false)) {
        t.x = t.y = "periodic";
    }
    if (t.x != "mirror" && t.x != "periodic")
        throw InputError(where, "tiling x must be \"mirror\" or \"periodic\", not \"" + t.x + "\"");
    if (t.y != "mirror" && t.y != "periodic" && t.y != "pole")
        throw InputError(
            where, "tiling y must be \"mirror\", \"periodic\" or \"pole\", not \"" + t.y + "\"");
    return t;
}

int tile_extent(const std::string& rule, int n) {
    if (rule == "mirror") return 2 * n;
    if (rule == "pole") return 2 * (n - 1);
    return n;
}

// The W x H grid's texel that tile texel (i, j) shows (Tiling in heightfields/scan_convert.h).
std::pair<int, int> tile_source(const Tiling& t, int w, int h, int i, int j) {
    int si = t.x == "mirror" && i >= w ? 2 * w - 1 - i : i;
    int sj = j;
    if (j >= h && t.y == "mirror") sj = 2 * h - 1 - j;
    if (j >= h && t.y == "pole") {
        sj = 2 * (h - 1) - j;
        si = (si + w / 2) % w;
    }
    return {si, sj};
}

}  // namespace

std::vector<ScanInfo> list_scans(const std::string& dir_in) {
    const std::string dir = dir_in.empty() ? default_scan_dir() : dir_in;
    std::vector<ScanInfo> out;
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) return out;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().extension() == ".json") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& p : files) {
        std::ifstream f(p);
        const json j = json::parse(f, nullptr, false);
        if (j.is_discarded()) continue;
        ScanInfo s;
        s.name = j.value("name", p.stem().string());
        s.description = j.value("description", "");
        if (j.contains("size")) {
            s.width = j["size"][0];
            s.height = j["size"][1];
        }
        s.periodic = j.value("periodic", false);
        const Tiling t = tiling_of(j, p.string());
        s.tiling_x = t.x;
        s.tiling_y = t.y;
        s.tile_width = tile_extent(t.x, s.width);
        s.tile_height = tile_extent(t.y, s.height);
        out.push_back(s);
    }
    return out;
}

HeightField load_scan(const std::string& name, const std::string& where,
                      const std::string& dir_in) {
    const std::string dir = dir_in.empty() ? default_scan_dir() : dir_in;
    const fs::path meta_path = fs::path(dir) / (name + ".json");
    std::ifstream f(meta_path);
    if (!f) {
        std::string names;
        for (const auto& s : list_scans(dir)) names += (names.empty() ? "" : ", ") + s.name;
        throw InputError(where, "unknown scan '" + name + "' (known: " + names + ")");
    }
    const json meta = json::parse(f, nullptr, false);
    if (meta.is_discarded()) throw InputError(meta_path.string(), "malformed JSON");
    HeightField base =
        load_heightfield_file((fs::path(dir) / meta.value("file", name + ".png")).string());
    std::vector<uint8_t> mask;
    if (meta.contains("holes") && meta["holes"].contains("mask")) {
        const HeightField m = load_heightfield_file(
            (fs::path(dir) / meta["holes"]["mask"].get<std::string>()).string());
        if (m.width != base.width || m.height != base.height)
            throw InputError(meta_path.string(), "mask size differs from the height field");
        mask.resize(m.texels.size());
        for (size_t k = 0; k < mask.size(); ++k) mask[k] = m.texels[k] > 0.5f;
    }
    const Tiling t = tiling_of(meta, meta_path.string());
    if (t.y == "pole" && (t.x != "periodic" || base.width % 2 != 0 || base.height < 2))
        throw InputError(meta_path.string(),
                         "tiling y = \"pole\" needs x periodic, an even width and 2 rows or more");
    // Texel (i, j) of the tile is the stored texel tile_source(i, j): e.g. mirrored in x, the
    // 2W-wide tile's column i >= W is the stored column 2W - 1 - i.
    HeightField hf(tile_extent(t.x, base.width), tile_extent(t.y, base.height), "scan:" + name);
    if (!mask.empty()) hf.filled.resize(hf.texels.size());
    for (int j = 0; j < hf.height; ++j)
        for (int i = 0; i < hf.width; ++i) {
            const auto [si, sj] = tile_source(t, base.width, base.height, i, j);
            hf.at(i, j) = base.at(si, sj);
            if (!mask.empty())
                hf.filled[size_t(j) * hf.width + i] = mask[size_t(sj) * base.width + si];
        }
    return hf;
}

}  // namespace pxh

// `pxh import` (heightfields/scanned.h): the scanned sources' registries (sources(): the
// package each comes from and the one whose copyright covers it; convert(): its converter),
// each source converted and written as NAME.png, NAME.mask.png and NAME.json, and --check's
// comparison with the committed files.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "harness/core/image_codec.h"
#include "heightfields/heightfields.h"
#include "heightfields/scan_convert.h"
#include "heightfields/scanned.h"

namespace pxh {
namespace {

using namespace scan;

namespace fs = std::filesystem;
using nlohmann::json;

// The JSON's sentence for a tiling (the mirrored scans keep the one they had before tiling
// had a rule per axis).
std::string tiling_rule(const Tiling& t) {
    if (t.x == "mirror" && t.y == "mirror")
        return "not periodic: mirrored to 2W x 2H (same texel size) when loaded";
    if (t.x == "periodic" && t.y == "pole")
        return "periodic in x (the columns go once around in longitude); the rows run pole to "
               "pole, so past a pole the field continues down the opposite meridian (rows in "
               "reverse, shifted by W/2): W x 2(H-1) when loaded, no mirroring";
    return "x: " + t.x + ", y: " + t.y;
}

void write_scan(const Converted& c, const std::string& name, const std::string& dir) {
    const Grid& g = c.grid;
    double lo = INFINITY, hi = -INFINITY;
    for (double x : g.v) {
        lo = std::min(lo, x);
        hi = std::max(hi, x);
    }
    HeightField hf(g.w, g.h, name);
    for (size_t k = 0; k < g.v.size(); ++k)
        hf.texels[k] = float(hi > lo ? (g.v[k] - lo) / (hi - lo) : 0.5);
    fs::create_directories(dir);
    save_heightfield_file(hf, (fs::path(dir) / (name + ".png")).string());
    json meta = c.meta;
    meta["name"] = name;
    meta["file"] = name + ".png";
    meta["size"] = {g.w, g.h};
    meta["stored_as"] = "16-bit PNG, first row = j = 0, (value - min) / (max - min)";
    meta["periodic"] = c.tiling.x == "periodic" && c.tiling.y == "periodic";
    meta["tiling"] = {{"x", c.tiling.x}, {"y", c.tiling.y}};
    meta["periodic_rule"] = tiling_rule(c.tiling);
    size_t holes = 0;
    for (uint8_t f : g.filled) holes += f;
    meta["holes"]["count"] = holes;
    meta["holes"]["fraction"] = double(holes) / double(g.v.size());
    if (holes) {
        meta["holes"]["mask"] = name + ".mask.png";
        HeightField mask(g.w, g.h);
        for (size_t k = 0; k < g.filled.size(); ++k) mask.texels[k] = g.filled[k] ? 1.0f : 0.0f;
        save_heightfield_file(mask, (fs::path(dir) / (name + ".mask.png")).string());
    }
    std::ofstream(fs::path(dir) / (name + ".json")) << meta.dump(2) << "\n";
}

struct Source {
    const char* name;
    const char* package;               // holds the data
    const char* licence_package;       // whose copyright file covers it
    std::vector<std::string> members;  // what to unpack ("./usr/..."); empty: everything
};
const std::vector<Source>& sources() {
    static const std::vector<Source> s = {
        {"jacksboro", "python-matplotlib-data", "python-matplotlib-data", {}},
        {"motorcycle", "python3-skimage", "python3-skimage", {}},
        {"bunny", "libcgal-demo", "libcgal-dev", {}},
        {"lidar_b9", "libcgal-demo", "libcgal-dev", {}},
        {"topobathy", "python-matplotlib-data", "python-matplotlib-data", {}},
        {"egm96", "proj-data", "proj-data", {}},
        {"olinda", "r-cran-stars", "r-cran-stars", {}},
        {"luxembourg", "r-cran-terra", "r-cran-terra", {}},
        {"aloe",
         "opencv-doc",
         "opencv-doc",
         {"./usr/share/doc/opencv-doc/examples/data/aloeGT.png",
          "./usr/share/doc/opencv-doc/copyright"}}};
    return s;
}

Converted convert(const std::string& name, const Package& pkg, const std::string& cache) {
    if (name == "jacksboro") return convert_jacksboro(pkg);
    if (name == "motorcycle") return convert_motorcycle(pkg);
    if (name == "bunny") return convert_bunny(pkg, cache);
    if (name == "lidar_b9") return convert_lidar(pkg, cache);
    if (name == "topobathy") return convert_topobathy(pkg);
    if (name == "egm96") return convert_egm96(pkg);
    if (name == "olinda") return convert_olinda(pkg);
    if (name == "luxembourg") return convert_luxembourg(pkg);
    return convert_aloe(pkg);
}

void import_all(const std::string& out, const std::string& cache) {
    for (const Source& s : sources()) {
        std::cerr << "import: " << s.name << " from " << s.package << "\n";
        const Package pkg = fetch_package(s.package, cache, s.members);
        const Package lic = std::string(s.licence_package) == s.package
                                ? pkg
                                : fetch_package(s.licence_package, cache);
        Converted c = convert(s.name, pkg, cache);
        c.meta["package"] = pkg.name;
        c.meta["package_version"] = pkg.version;
        const std::string copyright = lic.root + "/usr/share/doc/" + lic.name + "/copyright";
        c.meta["licence"] = {{"from", "/usr/share/doc/" + lic.name + "/copyright (" + lic.name +
                                          " " + lic.version + ")"},
                             {"licenses", licences(copyright)}};
        write_scan(c, s.name, out);
    }
}

std::vector<float> pixels(const std::string& path) {
    ImagePixels img;
    std::string why;
    if (!read_image_pixels(path, img, why, 1 << 20)) return {};
    return img.px;
}

}  // namespace

int run_import(const ImportOptions& opt) {
    const std::string out = opt.out_dir.empty() ? default_scan_dir() : opt.out_dir;
    const std::string cache =
        opt.cache_dir.empty() ? std::string(PXH_SOURCE_DIR) + "/build/scan-cache" : opt.cache_dir;
    if (!opt.check) {
        import_all(out, cache);
        std::cout << "imported " << sources().size() << " scans into " << out << "\n";
        return 0;
    }
    const fs::path tmp =
        fs::temp_directory_path() / ("pxh-import-check-" + std::to_string(::getpid()));
    import_all(tmp.string(), cache);
    int differ = 0;
    for (const auto& e : fs::directory_iterator(tmp)) {
        const fs::path committed = fs::path(out) / e.path().filename();
        bool same = fs::exists(committed);
        if (same && e.path().extension() == ".png")
            same = pixels(e.path().string()) == pixels(committed.string());
        if (same && e.path().extension() == ".json") {
            std::ifstream a(e.path()), b(committed);
            same = json::parse(a) == json::parse(b);
        }
        std::cout << (same ? "same     " : "DIFFERS  ") << committed.string() << "\n";
        differ += !same;
    }
    fs::remove_all(tmp);
    std::cout << (differ ? "the import does not reproduce the committed files\n"
                         : "the import reproduces the committed files exactly\n");
    return differ ? 1 : 0;
}

}  // namespace pxh

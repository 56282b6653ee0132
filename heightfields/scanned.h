// Scanned (measured) height fields: imported from Debian packages into heightfields/scanned/
// (16-bit PNG + hole mask + provenance JSON), loaded by name (scan = "jacksboro").
#pragma once
#include <string>
#include <vector>

#include "harness/scene/heightfield.h"

namespace pxh {

struct ImportOptions {
    std::string out_dir;    // default: <source>/heightfields/scanned
    std::string cache_dir;  // downloaded packages (default: <source>/build/scan-cache)
    bool check = false;     // re-import into a temporary folder and compare with out_dir
};

// Imports every source; with check, returns 1 if any file differs from the committed one.
int run_import(const ImportOptions& opt);

struct ScanInfo {
    std::string name, description;
    int width = 0, height = 0;            // as stored (before tiling)
    bool periodic = false;                // in both axes, as stored
    std::string tiling_x, tiling_y;       // "mirror" | "periodic" (| "pole" in y)
    int tile_width = 0, tile_height = 0;  // as loaded (load_scan)
};
// The imported scans (from the JSON files in dir, default the source tree's).
std::vector<ScanInfo> list_scans(const std::string& dir = "");

// Loads scan NAME: heights in [0,1] and the filled-hole mask, made to tile by its JSON's
// "tiling" per axis (same texel size): "mirror" doubles the axis with the mirror image so that
// repeat wrapping adds no artificial cliff, "periodic" keeps it (the data wraps), "pole" (y, for
// a grid running pole to pole) continues past each pole down the opposite meridian.
HeightField load_scan(const std::string& name, const std::string& where,
                      const std::string& dir = "");

}  // namespace pxh

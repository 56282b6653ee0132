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
    int width = 0, height = 0;  // as stored (before mirroring)
    bool periodic = false;
};
// The imported scans (from the JSON files in dir, default the source tree's).
std::vector<ScanInfo> list_scans(const std::string& dir = "");

// Loads scan NAME: heights in [0,1] and the filled-hole mask; a non-periodic scan is mirrored
// to 2W x 2H (same texel size) so that repeat wrapping adds no artificial cliff.
HeightField load_scan(const std::string& name, const std::string& where,
                      const std::string& dir = "");

}  // namespace pxh

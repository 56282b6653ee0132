// Internal to `pxh import` (heightfields/scanned_import.cpp and the files it calls) and the
// scans' loading (heightfields/scanned.cpp): a Debian package's unpacked files, a grid with
// holes, and the converters of the sources.
#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace pxh::scan {

// A Debian package's files: root is where they were unpacked.
struct Package {
    std::string name, version, root;
};

struct Grid {
    int w = 0, h = 0;
    std::vector<double> v;  // row-major; NaN = hole
    std::vector<uint8_t> filled;
};

// How the stored W x H grid is made to tile (load_scan): per axis "mirror" (2W: the grid then
// its mirror image), "periodic" (as is: the data wraps around) or, for y only, "pole" (the rows
// run pole to pole: past a pole the field continues down the opposite meridian, i.e. the rows
// in reverse shifted by W/2; 2(H-1) rows; needs x periodic and W even).
struct Tiling {
    std::string x = "mirror", y = "mirror";
};

struct Converted {
    Grid grid;
    nlohmann::json meta;
    Tiling tiling;
};

// Fills every NaN: each pass gives every hole with measured (or already filled) 4-neighbours
// the mean of those neighbours, all from the previous pass's state; sets grid.filled. Returns
// the number of holes.
int fill_holes(Grid& g);

// The folder of the committed scans (heightfields/scanned): where `pxh import` writes and the
// scans are listed and loaded from by default (heightfields/scanned.cpp).
std::string default_scan_dir();

// A Debian package's files, unpacked into cache/NAME once (later calls read the cache);
// with `members`, only those paths ("./usr/...") (heightfields/scanned_packages.cpp).
Package fetch_package(const std::string& name, const std::string& cache,
                      const std::vector<std::string>& members = {});
// License names from a Debian copyright file (machine-readable format: "License:" fields).
std::vector<std::string> licences(const std::string& copyright);

// The sources converted in heightfields/scanned_converters.cpp.
Converted convert_jacksboro(const Package& pkg);
Converted convert_motorcycle(const Package& pkg);
Converted convert_bunny(const Package& pkg, const std::string& cache);
Converted convert_lidar(const Package& pkg, const std::string& cache);

// The sources converted in heightfields/scanned_sources.cpp.
Converted convert_topobathy(const Package& pkg);
Converted convert_egm96(const Package& pkg);
Converted convert_olinda(const Package& pkg);
Converted convert_luxembourg(const Package& pkg);
Converted convert_aloe(const Package& pkg);

}  // namespace pxh::scan

// Readers for the scanned sources: NumPy .npz/.npy arrays, PLY point clouds, OFF meshes, PROJ's
// .gtx grids, and TIFF tags (GeoTIFF's pixel size and GDAL's no-data value).
#pragma once
#include <array>
#include <string>
#include <vector>

namespace pxh {

struct NpyArray {
    std::vector<size_t> shape;  // row-major (C order)
    std::vector<double> values;
};

// One array from an .npz archive (stored or deflated members); throws InputError.
NpyArray read_npz_array(const std::string& path, const std::string& member);

// Vertex positions of a PLY file (ascii or binary_little_endian; x, y, z as float or double).
std::vector<std::array<double, 3>> read_ply_points(const std::string& path);

struct Mesh {
    std::vector<std::array<double, 3>> vertices;
    std::vector<std::array<unsigned, 3>> triangles;  // polygons fanned into triangles
};
// An ASCII OFF mesh.
Mesh read_off(const std::string& path);

// A PROJ/NOAA .gtx grid: a 40-byte big-endian header (south-west corner latitude and longitude,
// latitude and longitude step in degrees: 4 doubles; rows and columns: 2 int32), then rows x
// columns big-endian float32, row 0 = the southernmost, column 0 = the westernmost.
struct GtxGrid {
    double lat0 = 0, lon0 = 0, dlat = 0, dlon = 0;
    int rows = 0, cols = 0;
    std::vector<double> values;  // row-major
};
GtxGrid read_gtx(const std::string& path);

// One tag of a TIFF file's first image (IFD 0), either byte order; found = false if absent.
struct TiffTag {
    bool found = false;
    std::string ascii;           // type 2 (ASCII), without the trailing NUL
    std::vector<double> values;  // numeric types (BYTE, SHORT, LONG, SHORT/LONG signed, DOUBLE)
};
TiffTag read_tiff_tag(const std::string& path, int tag);

}  // namespace pxh

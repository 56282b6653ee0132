// Scanned sources beside those of scanned_converters.cpp (read by `pxh import`,
// heightfields/scanned_import.cpp). All verified inside the Debian 12 packages (apt-get
// download + dpkg-deb -x):
//   topobathy  python-matplotlib-data: mpl-data/sample_data/topobathy.npz, float32 91 x 120
//              metres (land and sea floor off British Columbia), lat/lon axes in the archive
//   egm96      proj-data: /usr/share/proj/egm96_15.gtx, the EGM96 geoid undulation on a 15'
//              grid, 721 x 1440 big-endian float32 after a 40-byte header (PROJ's .gtx)
//   olinda     r-cran-stars: stars/tif/olinda_dem_utm25s.tif, float32 GeoTIFF DEM 111 x 111
//   luxembourg r-cran-terra: terra/ex/elev.tif, int16 GeoTIFF 95 x 90, GDAL no-data -32768
//   aloe       opencv-doc: examples/data/aloeGT.png, the Middlebury 2006 'Aloe' ground-truth
//              disparity (H. Hirschmueller and D. Scharstein, "Evaluation of cost functions
//              for stereo matching", CVPR 2007; D. Scharstein and C. Pal, "Learning
//              conditional random fields for stereo", CVPR 2007), 8-bit, 0 = unknown
// Formats: .npz (NumPy), .gtx (PROJ's NOAA vertical grid format: header of 4 big-endian
// doubles and 2 int32, then rows from the south), GeoTIFF tags 33550 (ModelPixelScale),
// 34737 (GeoAsciiParams) and GDAL's 42113 (GDAL_NODATA, ASCII), read by heightfields/scan_io.

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "harness/core/error.h"
#include "harness/core/image_codec.h"
#include "heightfields/scan_convert.h"
#include "heightfields/scan_io.h"

namespace pxh::scan {
namespace {

using nlohmann::json;

// Channel 0 of a single-image raster as stored (no normalisation of integers): the file's own
// pixel type must be `type` ("uint8", "int16" or "float").
Grid read_raster(const std::string& path, const std::string& type) {
    const ImageCodec& codec = image_codec();
    ImageFileInfo spec;
    std::string why;
    ImageReader* in = codec.open_path(path, spec, why);
    if (!in) throw InputError(path, "cannot read: " + why);
    if (spec.type != type || spec.channels != 1) {
        codec.close(in, why);
        throw InputError(path, "expected 1 channel of " + type + ", found " +
                                   std::to_string(spec.channels) + " of " + spec.type);
    }
    Grid g;
    g.w = spec.width;
    g.h = spec.height;
    const size_t n = size_t(g.w) * size_t(g.h);
    std::vector<unsigned char> raw(n * spec.pixel_bytes);
    const bool ok = codec.read(in, 0, 1, true, raw.data(), why);
    std::string ignored;
    codec.close(in, ignored);
    if (!ok) throw InputError(path, "cannot read pixels: " + why);
    g.v.resize(n);
    for (size_t k = 0; k < n; ++k) {
        const unsigned char* p = raw.data() + k * spec.pixel_bytes;
        if (type == "uint8") g.v[k] = *p;
        else if (type == "int16") {
            int16_t x;
            std::memcpy(&x, p, 2);
            g.v[k] = x;
        } else {
            float x;
            std::memcpy(&x, p, 4);
            g.v[k] = x;
        }
    }
    return g;
}

std::pair<double, double> finite_range(const std::vector<double>& v) {
    double lo = INFINITY, hi = -INFINITY;
    for (double x : v)
        if (std::isfinite(x)) {
            lo = std::min(lo, x);
            hi = std::max(hi, x);
        }
    return {lo, hi};
}

// Marks every value equal to `nodata` as a hole (NaN); returns how many.
size_t mark_nodata(Grid& g, double nodata) {
    size_t n = 0;
    for (double& x : g.v)
        if (x == nodata) {
            x = NAN;
            ++n;
        }
    return n;
}

}  // namespace

Converted convert_topobathy(const Package& pkg) {
    const std::string rel = "/usr/share/matplotlib/mpl-data/sample_data/topobathy.npz";
    const std::string path = pkg.root + rel;
    const NpyArray a = read_npz_array(path, "topo.npy");
    const NpyArray lon = read_npz_array(path, "longitude.npy");
    const NpyArray lat = read_npz_array(path, "latitude.npy");
    if (a.shape.size() != 2 || lat.values.size() != a.shape[0] || lon.values.size() != a.shape[1])
        throw InputError(path, "topo is not latitude x longitude");
    Converted c;
    c.grid.h = int(a.shape[0]);
    c.grid.w = int(a.shape[1]);
    c.grid.v = a.values;
    fill_holes(c.grid);
    const auto [lo, hi] = finite_range(a.values);
    const double dlon = (lon.values.back() - lon.values.front()) / double(c.grid.w - 1);
    const double dlat = (lat.values.back() - lat.values.front()) / double(c.grid.h - 1);
    c.meta = {
        {"description",
         "topography and bathymetry off British Columbia (Vancouver Island, Strait of Georgia): "
         "mountains, fjords and sea floor, 44% below sea level"},
        {"path_in_package", rel},
        {"original", {{"shape", a.shape}, {"dtype", "float32"}}},
        {"value_range", {lo, hi}},
        {"units", "metres above sea level (negative: below)"},
        {"grid_spacing",
         {{"dlon_deg", dlon},
          {"dlat_deg", dlat},
          {"lon_range_deg", {lon.values.front(), lon.values.back()}},
          {"lat_range_deg", {lat.values.front(), lat.values.back()}},
          {"note", "row 0 is the southernmost latitude; cells about 2.4 km square"}}},
        {"holes", {{"rule", "none present"}}}};
    return c;
}

Converted convert_egm96(const Package& pkg) {
    const std::string rel = "/usr/share/proj/egm96_15.gtx";
    const GtxGrid g = read_gtx(pkg.root + rel);
    // Periodic in x only if the columns go exactly once around; "pole" tiling only if the rows
    // run from pole to pole.
    if (std::abs(g.cols * g.dlon - 360) > 1e-9 || g.lat0 != -90 ||
        std::abs(g.lat0 + (g.rows - 1) * g.dlat - 90) > 1e-9)
        throw InputError(pkg.root + rel, "not a global pole-to-pole grid");
    Converted c;
    c.grid = {g.cols, g.rows, g.values, {}};
    fill_holes(c.grid);
    c.tiling = {"periodic", "pole"};
    const auto [lo, hi] = finite_range(g.values);
    c.meta = {{"description",
               "EGM96 geoid undulation, the whole Earth on a 15' grid: very smooth, "
               "long-wavelength relief (periodic in longitude)"},
              {"path_in_package", rel},
              {"original",
               {{"shape", {g.rows, g.cols}},
                {"dtype", "big-endian float32 after a 40-byte .gtx header"},
                {"south_west_deg", {g.lat0, g.lon0}}}},
              {"value_range", {lo, hi}},
              {"units", "metres: the geoid's height above the WGS84 ellipsoid"},
              {"grid_spacing",
               {{"dlon_deg", g.dlon},
                {"dlat_deg", g.dlat},
                {"note",
                 "row 0 = latitude -90 (south pole), row 720 = +90; column 0 = longitude -180; "
                 "equal angles, not equal areas"}}},
              {"holes", {{"rule", "none present"}}}};
    return c;
}

Converted convert_olinda(const Package& pkg) {
    const std::string rel = "/usr/lib/R/site-library/stars/tif/olinda_dem_utm25s.tif";
    const std::string path = pkg.root + rel;
    Converted c;
    c.grid = read_raster(path, "float");
    const TiffTag scale = read_tiff_tag(path, 33550), nodata = read_tiff_tag(path, 42113);
    if (scale.values.size() < 2) throw InputError(path, "no GeoTIFF pixel scale (tag 33550)");
    if (nodata.found) throw InputError(path, "declares no-data '" + nodata.ascii + "'");
    std::string citation = read_tiff_tag(path, 34737).ascii;  // GeoAsciiParams, '|'-separated
    while (!citation.empty() && citation.back() == '|') citation.pop_back();
    fill_holes(c.grid);
    const auto [lo, hi] = finite_range(c.grid.v);
    c.meta = {{"description",
               "DEM of Olinda (Pernambuco, Brazil): a plateau dissected by branching valleys, "
               "a coastal plain and the sea (value 0, 17% of cells)"},
              {"path_in_package", rel},
              {"original", {{"shape", {c.grid.h, c.grid.w}}, {"dtype", "float32 GeoTIFF"}}},
              {"value_range", {lo, hi}},
              {"units",
               "elevation, whole numbers (the GeoTIFF names no vertical unit; metres "
               "fits this coastal relief); horizontal: " +
                   citation},
              {"grid_spacing",
               {{"dx_m", scale.values[0]},
                {"dy_m", scale.values[1]},
                {"note", "GeoTIFF ModelPixelScale; row 0 is the northernmost"}}},
              {"holes", {{"rule", "none present (no GDAL_NODATA tag)"}}}};
    return c;
}

Converted convert_luxembourg(const Package& pkg) {
    const std::string rel = "/usr/lib/R/site-library/terra/ex/elev.tif";
    const std::string path = pkg.root + rel;
    Converted c;
    c.grid = read_raster(path, "int16");
    const TiffTag scale = read_tiff_tag(path, 33550), nodata = read_tiff_tag(path, 42113);
    if (scale.values.size() < 2) throw InputError(path, "no GeoTIFF pixel scale (tag 33550)");
    if (!nodata.found) throw InputError(path, "no GDAL_NODATA tag (42113)");
    const double nd = std::stod(nodata.ascii);
    mark_nodata(c.grid, nd);
    const auto [lo, hi] = finite_range(c.grid.v);
    fill_holes(c.grid);
    c.meta = {{"description",
               "elevation of Luxembourg (terra's example elev.tif): Ardennes uplands in the "
               "north, river valleys; no data outside the border (holes, 46%)"},
              {"path_in_package", rel},
              {"original", {{"shape", {c.grid.h, c.grid.w}}, {"dtype", "int16 GeoTIFF"}}},
              {"value_range", {lo, hi}},
              {"units", "metres of elevation"},
              {"grid_spacing",
               {{"dx_deg", scale.values[0]},
                {"dy_deg", scale.values[1]},
                {"note", "30 arc-seconds (GeoTIFF ModelPixelScale); row 0 is the northernmost"}}},
              {"holes",
               {{"rule", "GDAL_NODATA " + nodata.ascii +
                             " (outside the border) filled by repeated passes giving each hole "
                             "the mean of its measured or already filled 4-neighbours; mask "
                             "kept (1 = filled)"}}}};
    return c;
}

Converted convert_aloe(const Package& pkg) {
    const std::string rel = "/usr/share/doc/opencv-doc/examples/data/aloeGT.png";
    Converted c;
    c.grid = read_raster(pkg.root + rel, "uint8");
    mark_nodata(c.grid, 0);
    const auto [lo, hi] = finite_range(c.grid.v);
    fill_holes(c.grid);
    c.meta = {{"description",
               "Middlebury 2006 'Aloe' structured-light disparity: leaves and a pot before a "
               "backdrop, occluding edges; 8-bit, so quantised to whole pixels (terraces)"},
              {"path_in_package", rel},
              {"original", {{"shape", {c.grid.h, c.grid.w}}, {"dtype", "uint8 PNG"}}},
              {"value_range", {lo, hi}},
              {"units",
               "disparity in whole pixels at full size (larger is nearer): used as height; "
               "quantised, 1 pixel = 1/" +
                   std::to_string(int(hi - lo)) + " of the range"},
              {"grid_spacing", "one camera pixel"},
              {"source_papers",
               "H. Hirschmueller, D. Scharstein, Evaluation of cost functions for stereo matching, "
               "CVPR 2007; D. Scharstein, C. Pal, Learning conditional random fields for stereo, "
               "CVPR 2007"},
              {"holes",
               {{"rule",
                 "0 (unknown disparity) filled by repeated passes giving each hole the mean of its "
                 "measured or already filled 4-neighbours; mask kept (1 = filled)"}}}};
    return c;
}

}  // namespace pxh::scan

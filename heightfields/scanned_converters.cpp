// The converters of four scanned sources (the others: heightfields/scanned_sources.cpp), and
// fill_holes (heightfields/scan_convert.h). Sources (all verified in Debian 12):
//   jacksboro  python-matplotlib-data: a USGS DEM of the Jacksboro fault (int16 metres)
//   motorcycle python3-skimage: Middlebury 2014 structured-light disparity (+inf holes)
//   bunny      libcgal-demo: the Stanford bunny range scan bunny00.off (mesh, Embree ray cast)
//   lidar_b9   libcgal-demo: airborne LiDAR of an urban block, b9_training.ply (point cloud)
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "heightfields/scan_convert.h"
#include "heightfields/scan_io.h"

namespace pxh::scan {
namespace {

namespace fs = std::filesystem;

std::string cgal_data(const Package& pkg, const std::string& member, const std::string& cache) {
    const fs::path out = fs::path(cache) / "cgal-data";
    const fs::path file = out / member;
    if (!fs::exists(file)) {
        fs::create_directories(out);
        const std::string cmd = "tar xzf '" + pkg.root +
                                "/usr/share/doc/libcgal-dev/data.tar.gz' -C '" + out.string() +
                                "' '" + member + "'";
        if (std::system(cmd.c_str()) != 0) throw std::runtime_error("cannot extract " + member);
    }
    return file.string();
}

// The mesh as a committed Embree scene (triangles, float vertices).
RTCScene mesh_scene(RTCDevice dev, const Mesh& m) {
    RTCScene scene = rtcNewScene(dev);
    RTCGeometry geom = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), m.vertices.size()));
    for (size_t i = 0; i < m.vertices.size(); ++i)
        for (int a = 0; a < 3; ++a) vb[3 * i + a] = float(m.vertices[i][a]);
    auto* ib = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(unsigned), m.triangles.size()));
    for (size_t i = 0; i < m.triangles.size(); ++i)
        for (int a = 0; a < 3; ++a) ib[3 * i + a] = m.triangles[i][a];
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene);
    return scene;
}

// The height of triangle `prim`'s plane over (x, y), in double: Embree's float hit distance
// depends on the kernel it picks for the CPU (SSE, AVX2, AVX-512 round differently), this does
// not, so the import reproduces the committed file on any x86-64 machine. An edge-on triangle
// gives `edge_on` (Embree's own hit).
double plane_height(const Mesh& m, unsigned prim, double x, double y, double edge_on) {
    const auto& tri = m.triangles[prim];
    const auto &A = m.vertices[tri[0]], &B = m.vertices[tri[1]], &C = m.vertices[tri[2]];
    const double e1[3] = {B[0] - A[0], B[1] - A[1], B[2] - A[2]};
    const double e2[3] = {C[0] - A[0], C[1] - A[1], C[2] - A[2]};
    const double nx = e1[1] * e2[2] - e1[2] * e2[1], ny = e1[2] * e2[0] - e1[0] * e2[2],
                 nz = e1[0] * e2[1] - e1[1] * e2[0];
    return nz != 0 ? A[2] - (nx * (x - A[0]) + ny * (y - A[1])) / nz : edge_on;
}

}  // namespace

// Holes: each pass gives every hole with measured (or already filled) 4-neighbours the mean
// of those neighbours, all from the previous pass's state; repeated until none is left.
int fill_holes(Grid& g) {
    g.filled.assign(g.v.size(), 0);
    int holes = 0;
    for (double x : g.v) holes += std::isnan(x);
    for (int left = holes; left > 0;) {
        std::vector<double> next = g.v;
        int done = 0;
        for (int j = 0; j < g.h; ++j)
            for (int i = 0; i < g.w; ++i) {
                const size_t k = size_t(j) * g.w + i;
                if (!std::isnan(g.v[k])) continue;
                double s = 0;
                int n = 0;
                const int di[4] = {-1, 1, 0, 0}, dj[4] = {0, 0, -1, 1};
                for (int t = 0; t < 4; ++t) {
                    const int a = i + di[t], b = j + dj[t];
                    if (a < 0 || b < 0 || a >= g.w || b >= g.h) continue;
                    const double x = g.v[size_t(b) * g.w + a];
                    if (!std::isnan(x)) {
                        s += x;
                        ++n;
                    }
                }
                if (n) {
                    next[k] = s / n;
                    g.filled[k] = 1;
                    ++done;
                }
            }
        if (done == 0) throw std::runtime_error("hole filling made no progress (no data?)");
        g.v = std::move(next);
        left -= done;
    }
    return holes;
}

Converted convert_jacksboro(const Package& pkg) {
    const std::string rel = "/usr/share/matplotlib/mpl-data/sample_data/jacksboro_fault_dem.npz";
    const std::string path = pkg.root + rel;
    const NpyArray a = read_npz_array(path, "elevation.npy");
    const double dx = read_npz_array(path, "dx.npy").values.at(0);
    const double dy = read_npz_array(path, "dy.npy").values.at(0);
    Converted c;
    c.grid.h = int(a.shape.at(0));
    c.grid.w = int(a.shape.at(1));
    c.grid.v = a.values;
    fill_holes(c.grid);
    const auto [lo, hi] = std::minmax_element(a.values.begin(), a.values.end());
    c.meta = {{"description",
               "USGS digital elevation model around the Jacksboro fault (TN): "
               "valleys, ridges and a fault escarpment"},
              {"path_in_package", rel},
              {"original", {{"shape", a.shape}, {"dtype", "int16"}}},
              {"value_range", {*lo, *hi}},
              {"units", "metres of elevation"},
              {"grid_spacing", {{"dx_deg", dx}, {"dy_deg", dy}, {"note", "3 arc-seconds"}}},
              {"holes", {{"rule", "none present"}}}};
    return c;
}

Converted convert_motorcycle(const Package& pkg) {
    const std::string rel = "/usr/lib/python3/dist-packages/skimage/data/motorcycle_disp.npz";
    const NpyArray a = read_npz_array(pkg.root + rel, "arr_0.npy");
    Converted c;
    c.grid.h = int(a.shape.at(0));
    c.grid.w = int(a.shape.at(1));
    c.grid.v = a.values;
    double lo = INFINITY, hi = -INFINITY;
    for (double& x : c.grid.v) {
        if (!std::isfinite(x)) x = NAN;  // +inf: no measurement
        else {
            lo = std::min(lo, x);
            hi = std::max(hi, x);
        }
    }
    fill_holes(c.grid);
    c.meta = {{"description",
               "Middlebury 2014 'Motorcycle' structured-light disparity map: "
               "smooth surfaces, big depth jumps at occluding edges, holes"},
              {"path_in_package", rel},
              {"original", {{"shape", a.shape}, {"dtype", "float32"}}},
              {"value_range", {lo, hi}},
              {"units", "disparity in pixels (larger is nearer): used as height"},
              {"grid_spacing", "one camera pixel"},
              {"holes",
               {{"rule",
                 "+inf (no measurement) filled by repeated passes giving each "
                 "hole the mean of its measured or already filled 4-neighbours; "
                 "mask kept (1 = filled)"}}}};
    return c;
}

// Orthographic ray casting from above with Embree: the first hit of a ray along -z over each
// texel centre; rays that miss the mesh are background, set to the lowest hit and flagged.
Converted convert_bunny(const Package& pkg, const std::string& cache) {
    const std::string member = "data/meshes/bunny00.off";
    const Mesh m = read_off(cgal_data(pkg, member, cache));
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (const auto& v : m.vertices)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], v[a]);
            hi[a] = std::max(hi[a], v[a]);
        }
    const int W = 256;
    const double spacing = (hi[0] - lo[0]) / W;
    const int H = int(std::ceil((hi[1] - lo[1]) / spacing));
    RTCDevice dev = rtcNewDevice(nullptr);
    RTCScene scene = mesh_scene(dev, m);
    Converted c;
    c.grid.w = W;
    c.grid.h = H;
    c.grid.v.assign(size_t(W) * H, NAN);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    const double top = hi[2] + 1;
    double zmin = INFINITY;
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            RTCRayHit rh{};
            rh.ray.org_x = float(lo[0] + (i + 0.5) * spacing);
            rh.ray.org_y = float(lo[1] + (j + 0.5) * spacing);
            rh.ray.org_z = float(top);
            rh.ray.dir_z = -1;
            rh.ray.tnear = 0;
            rh.ray.tfar = std::numeric_limits<float>::infinity();
            rh.ray.mask = 0xFFFFFFFF;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(scene, &ctx, &rh);
            if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
                // Embree finds the triangle; the height is that triangle's plane at the texel
                // centre (plane_height).
                const double x = lo[0] + (i + 0.5) * spacing, y = lo[1] + (j + 0.5) * spacing;
                const double z = plane_height(m, rh.hit.primID, x, y, top - double(rh.ray.tfar));
                c.grid.v[size_t(j) * W + i] = z;
                zmin = std::min(zmin, z);
            }
        }
    rtcReleaseScene(scene);
    rtcReleaseDevice(dev);
    c.grid.filled.assign(c.grid.v.size(), 0);
    size_t background = 0;
    for (size_t k = 0; k < c.grid.v.size(); ++k)
        if (std::isnan(c.grid.v[k])) {
            c.grid.v[k] = zmin;
            c.grid.filled[k] = 1;
            ++background;
        }
    c.meta = {{"description",
               "Stanford bunny, one range scan (bunny00.off), as the height seen "
               "from above (+z)"},
              {"path_in_package", "/usr/share/doc/libcgal-dev/data.tar.gz:" + member},
              {"original",
               {{"vertices", m.vertices.size()},
                {"triangles", m.triangles.size()},
                {"bounds_min", {lo[0], lo[1], lo[2]}},
                {"bounds_max", {hi[0], hi[1], hi[2]}}}},
              {"value_range", {zmin, hi[2]}},
              {"units", "model units (the scan normalised to a unit box)"},
              {"grid_spacing", spacing},
              {"holes",
               {{"rule",
                 "orthographic ray casting with Embree along -z over each texel "
                 "centre (first hit from above); rays missing the mesh are "
                 "background, set to the lowest hit and flagged in the mask"}}}};
    return c;
}

// Point cloud to grid: the highest return in each cell (a surface model, as seen from
// above); empty cells are holes, filled like the others.
Converted convert_lidar(const Package& pkg, const std::string& cache) {
    const std::string member = "data/points_3/b9_training.ply";
    const auto pts = read_ply_points(cgal_data(pkg, member, cache));
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (const auto& p : pts)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], p[a]);
            hi[a] = std::max(hi[a], p[a]);
        }
    // About two points per cell on average.
    const double area = (hi[0] - lo[0]) * (hi[1] - lo[1]);
    const double spacing = std::sqrt(area * 2 / double(pts.size()));
    Converted c;
    c.grid.w = int(std::ceil((hi[0] - lo[0]) / spacing));
    c.grid.h = int(std::ceil((hi[1] - lo[1]) / spacing));
    c.grid.v.assign(size_t(c.grid.w) * c.grid.h, NAN);
    for (const auto& p : pts) {
        const int i = std::min(int((p[0] - lo[0]) / spacing), c.grid.w - 1);
        const int j = std::min(int((p[1] - lo[1]) / spacing), c.grid.h - 1);
        double& cell = c.grid.v[size_t(j) * c.grid.w + i];
        cell = std::isnan(cell) ? p[2] : std::max(cell, p[2]);
    }
    fill_holes(c.grid);
    c.meta = {{"description",
               "airborne LiDAR of an urban block (CGAL's b9_training.ply): "
               "buildings with vertical walls and flat roofs, trees"},
              {"path_in_package", "/usr/share/doc/libcgal-dev/data.tar.gz:" + member},
              {"original",
               {{"points", pts.size()},
                {"bounds_min", {lo[0], lo[1], lo[2]}},
                {"bounds_max", {hi[0], hi[1], hi[2]}}}},
              {"value_range", {lo[2], hi[2]}},
              {"units", "metres (as in the point cloud)"},
              {"grid_spacing", spacing},
              {"holes",
               {{"rule",
                 "rasterised to the highest point per cell (about 2 points per "
                 "cell); empty cells filled by repeated passes giving each the "
                 "mean of its measured or already filled 4-neighbours; mask "
                 "kept (1 = filled)"}}}};
    return c;
}

}  // namespace pxh::scan

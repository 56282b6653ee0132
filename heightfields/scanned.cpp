// Scanned height fields from Debian packages. Sources (all verified in Debian 12):
//   jacksboro  python-matplotlib-data: a USGS DEM of the Jacksboro fault (int16 metres)
//   motorcycle python3-skimage: Middlebury 2014 structured-light disparity (+inf holes)
//   bunny      libcgal-demo: the Stanford bunny range scan bunny00.off (mesh, Embree ray cast)
//   lidar_b9   libcgal-demo: airborne LiDAR of an urban block, b9_training.ply (point cloud)
#include "heightfields/scanned.h"

#include <OpenImageIO/imageio.h>
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "harness/core/error.h"
#include "heightfields/heightfields.h"
#include "heightfields/scan_convert.h"
#include "heightfields/scan_io.h"

namespace pxh {
namespace scan {

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

}  // namespace scan

namespace {

using namespace scan;

namespace fs = std::filesystem;
using nlohmann::json;

std::string source_dir() { return PXH_SOURCE_DIR; }
std::string default_scan_dir() { return source_dir() + "/heightfields/scanned"; }

std::string shell(const std::string& cmd) {
    std::string out;
    if (FILE* p = popen(cmd.c_str(), "r")) {
        char buf[512];
        while (fgets(buf, sizeof buf, p)) out += buf;
        pclose(p);
    }
    while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
    return out;
}

// A Debian package's files: unpacked into the cache with apt-get download + dpkg-deb -x (the
// same .deb the machine would install, without installing it); with `members`, only those
// paths ("./usr/...") are unpacked (opencv-doc is 95 MB for one 300 kB image).
std::string download_deb(const std::string& name, const fs::path& dir) {
    const std::string dl =
        "cd '" + dir.string() + "' && apt-get download -q " + name + " >/dev/null 2>&1";
    if (std::system(dl.c_str()) != 0) {
        // Package lists may be missing on a fresh machine: update once, then retry.
        std::system("apt-get update -qq >/dev/null 2>&1");
        if (std::system(dl.c_str()) != 0)
            throw std::runtime_error("apt-get download " + name +
                                     " failed (is Debian's apt reachable?)");
    }
    std::string deb;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().extension() == ".deb") deb = e.path().string();
    if (deb.empty()) throw std::runtime_error("no .deb for " + name + " in " + dir.string());
    return deb;
}

Package fetch_package(const std::string& name, const std::string& cache,
                      const std::vector<std::string>& members = {}) {
    const fs::path dir = fs::path(cache) / name;
    const fs::path stamp = dir / ".version";
    if (fs::exists(stamp)) {
        std::ifstream f(stamp);
        std::string v;
        std::getline(f, v);
        return {name, v, (dir / "root").string()};
    }
    fs::create_directories(dir);
    const std::string deb = download_deb(name, dir);
    const std::string root = (dir / "root").string();
    std::string x = "dpkg-deb -x '" + deb + "' '" + root + "'";
    if (!members.empty()) {
        fs::create_directories(root);
        x = "dpkg-deb --fsys-tarfile '" + deb + "' | tar -x -C '" + root + "'";
        for (const auto& m : members) x += " '" + m + "'";
    }
    if (std::system(x.c_str()) != 0) throw std::runtime_error("unpacking " + deb + " failed");
    const std::string version = shell("dpkg-deb -f '" + deb + "' Version");
    std::ofstream(stamp) << version << "\n";
    fs::remove(deb);
    return {name, version, root};
}

// License names from a Debian copyright file (machine-readable format: "License:" fields).
std::vector<std::string> licences(const std::string& copyright) {
    std::ifstream f(copyright);
    std::vector<std::string> out;
    for (std::string line; std::getline(f, line);)
        if (line.rfind("License:", 0) == 0) {
            std::string l = line.substr(8);
            l.erase(0, l.find_first_not_of(' '));
            if (!l.empty() && std::find(out.begin(), out.end(), l) == out.end()) out.push_back(l);
        }
    if (out.empty()) {
        // Not machine-readable: record the licences its text names.
        std::ifstream g(copyright);
        std::stringstream ss;
        ss << g.rdbuf();
        const std::string text = ss.str();
        for (const char* name : {"GNU General Public License", "GNU Lesser General Public License",
                                 "Boost Software License"})
            if (text.find(name) != std::string::npos)
                out.push_back(std::string("mentions: ") + name);
        if (out.empty()) out.push_back("no licence named (read the copyright file)");
    }
    return out;
}

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
    auto in = OIIO::ImageInput::open(path);
    if (!in) return {};
    std::vector<float> px(size_t(in->spec().width) * in->spec().height * in->spec().nchannels);
    in->read_image(0, 0, 0, in->spec().nchannels, OIIO::TypeDesc::FLOAT, px.data());
    return px;
}

}  // namespace

int run_import(const ImportOptions& opt) {
    const std::string out = opt.out_dir.empty() ? default_scan_dir() : opt.out_dir;
    const std::string cache =
        opt.cache_dir.empty() ? source_dir() + "/build/scan-cache" : opt.cache_dir;
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

namespace {

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

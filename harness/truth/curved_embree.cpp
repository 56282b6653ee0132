#include "harness/truth/curved_embree.h"

#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "harness/truth/embree_truth.h"

namespace pxh {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

CurvedEmbreeGrid::CurvedEmbreeGrid(const HeightField& hf, double scale, double bias,
                                   const BaseSurface& base, const std::vector<WorldRay>& rays,
                                   double max_vertices) {
    const auto t_start = std::chrono::steady_clock::now();
    const double top = scale * (1 - bias), bottom = -scale * bias;
    // the box of (u, v) over the rays' chords in the shell
    double u0 = INFINITY, u1 = -INFINITY, v0 = INFINITY, v1 = -INFINITY;
    for (const WorldRay& r : rays) {
        double ta = 0;
        if (base.coords(r.o).height > top) {
            ta = base.hit(r.o, r.d, top, 0, false);
            if (!std::isfinite(ta)) continue;
        }
        const double t_leave = base.hit(r.o, r.d, top, ta, true);
        const double t_floor = base.hit(r.o, r.d, bottom, ta, false);
        double tb = std::isfinite(t_floor) ? t_floor : t_leave;
        if (std::isfinite(t_floor) && std::isfinite(t_leave)) tb = std::min(t_floor, t_leave);
        if (!std::isfinite(tb)) continue;
        for (int i = 0; i <= 4; ++i) {
            const Vec2d uv = base.coords(v3_add(r.o, v3_scale(r.d, ta + (tb - ta) * i / 4))).uv;
            u0 = std::min(u0, uv.x);
            u1 = std::max(u1, uv.x);
            v0 = std::min(v0, uv.y);
            v1 = std::max(v1, uv.y);
        }
    }
    const int W = hf.width, H = hf.height;
    if (!(u0 <= u1)) u0 = u1 = v0 = v1 = 0.5;  // no ray in the shell: a token grid
    const double R = base.radius();
    double ulo = u0 - 2.0 / W, uhi = u1 + 2.0 / W, vlo = v0 - 2.0 / H, vhi = v1 + 2.0 / H;
    if (std::isfinite(R)) {
        ulo = std::max(ulo, 0.5 - kPi * R);
        uhi = std::min(uhi, 0.5 + kPi * R);
        if (base.name() == "sphere") {
            vlo = std::max(vlo, 0.5 - kPi / 2 * R);
            vhi = std::min(vhi, 0.5 + kPi / 2 * R);
        }
    }
    // texel centres (i + 0.5) / W within the box
    const long long i0 = (long long)std::ceil(ulo * W - 0.5),
                    i1 = (long long)std::floor(uhi * W - 0.5);
    const long long j0 = (long long)std::ceil(vlo * H - 0.5),
                    j1 = (long long)std::floor(vhi * H - 0.5);
    const long long nu = std::max(2LL, i1 - i0 + 1), nv = std::max(2LL, j1 - j0 + 1);
    if (double(nu) * double(nv) > max_vertices)
        throw std::runtime_error("the displaced grid would take " + std::to_string(nu * nv) +
                                 " vertices");
    vertices_ = size_t(nu * nv);
    const std::string config = EmbreeTracer::device_config();
    RTCDevice dev = rtcNewDevice(config.empty() ? nullptr : config.c_str());
    if (!dev) throw std::runtime_error("Embree: cannot create a device");
    RTCScene scene = rtcNewScene(dev);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry geom = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_GRID);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertices_));
    tbb::parallel_for(0LL, nv, [&](long long j) {
        for (long long i = 0; i < nu; ++i) {
            const Vec2d uv{(double(i0 + i) + 0.5) / W, (double(j0 + j) + 0.5) / H};
            const BaseFrame f = base.frame(uv);
            const double z = scale * (double(hf.wrapped(i0 + i, j0 + j)) - bias);
            const Vec3d X = v3_add(f.B, v3_scale(f.N, z));
            float* p = vb + 3 * (size_t(j) * size_t(nu) + size_t(i));
            p[0] = float(X.x);
            p[1] = float(X.y);
            p[2] = float(X.z);
        }
    });
    // GRID primitives of at most 32767 x 32767 vertices, sharing their edges
    std::vector<RTCGrid> grids;
    for (long long gj = 0; gj < nv - 1; gj += 32766)
        for (long long gi = 0; gi < nu - 1; gi += 32766) {
            RTCGrid g;
            g.startVertexID = unsigned(gj * nu + gi);
            g.stride = unsigned(nu);
            g.width = (unsigned short)std::min(32767LL, nu - gi);
            g.height = (unsigned short)std::min(32767LL, nv - gj);
            grids.push_back(g);
        }
    auto* gb = static_cast<RTCGrid*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_GRID, 0, RTC_FORMAT_GRID, sizeof(RTCGrid), grids.size()));
    std::copy(grids.begin(), grids.end(), gb);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene);
    if (rtcGetDeviceError(dev) != RTC_ERROR_NONE) {
        rtcReleaseScene(scene);
        rtcReleaseDevice(dev);
        throw std::runtime_error("Embree: the displaced grid's build failed");
    }
    device_ = dev;
    scene_ = scene;
    build_ms_ =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_start)
            .count();
}

CurvedEmbreeGrid::~CurvedEmbreeGrid() {
    if (scene_) rtcReleaseScene(static_cast<RTCScene>(scene_));
    if (device_) rtcReleaseDevice(static_cast<RTCDevice>(device_));
}

void CurvedEmbreeGrid::trace(const std::vector<WorldRay>& rays, std::vector<double>& t) const {
    const size_t n = rays.size();
    t.assign(n, NAN);
    const size_t packets = (n + 15) / 16;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, packets, 16), [&](const auto& rg) {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        for (size_t pk = rg.begin(); pk != rg.end(); ++pk) {
            alignas(64) RTCRayHit16 rh;
            alignas(64) int valid[16];
            for (int k = 0; k < 16; ++k) {
                const size_t idx = pk * 16 + size_t(k);
                rh.ray.time[k] = 0;
                rh.ray.mask[k] = 0xFFFFFFFFu;
                rh.ray.id[k] = unsigned(k);
                rh.ray.flags[k] = 0;
                rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
                if (idx >= n) {
                    valid[k] = 0;
                    rh.ray.org_x[k] = rh.ray.org_y[k] = rh.ray.org_z[k] = 0;
                    rh.ray.dir_x[k] = rh.ray.dir_y[k] = 0;
                    rh.ray.dir_z[k] = -1;
                    rh.ray.tnear[k] = std::numeric_limits<float>::infinity();
                    rh.ray.tfar[k] = -std::numeric_limits<float>::infinity();
                    rh.ray.mask[k] = 0;
                    continue;
                }
                valid[k] = -1;
                const WorldRay& r = rays[idx];
                rh.ray.org_x[k] = float(r.o.x);
                rh.ray.org_y[k] = float(r.o.y);
                rh.ray.org_z[k] = float(r.o.z);
                rh.ray.dir_x[k] = float(r.d.x);
                rh.ray.dir_y[k] = float(r.d.y);
                rh.ray.dir_z[k] = float(r.d.z);
                rh.ray.tnear[k] = 0;
                rh.ray.tfar[k] = std::numeric_limits<float>::infinity();
            }
            rtcIntersect16(valid, static_cast<RTCScene>(scene_), &ctx, &rh);
            for (int k = 0; k < 16; ++k) {
                const size_t idx = pk * 16 + size_t(k);
                if (valid[k] && rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID)
                    t[idx] = double(rh.ray.tfar[k]);
            }
        }
    });
}

}  // namespace pxh

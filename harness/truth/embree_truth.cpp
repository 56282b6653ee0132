#include "harness/truth/embree_truth.h"

#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <memory>
#include <stdexcept>

#include "harness/truth/travel_limit.h"

namespace pxh {

std::string EmbreeTracer::device_config() {
    const char* env = std::getenv("PXH_TRACER_PATH");
    const std::string path = env ? env : "";
    if (path == "avx2") return "max_isa=avx2";
    if (path == "scalar") return "max_isa=sse4.2";
    return "";
}

std::string EmbreeTracer::isa() {
    // Embree's own tests (its cpuinfo: AVX512SKX needs avx512f, cd, dq, bw and vl).
    const bool avx512 = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
                        __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw") &&
                        __builtin_cpu_supports("avx512vl");
    const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
                      __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2");
    const std::string config = device_config();
    const int cap = config == "max_isa=sse4.2" ? 0 : config == "max_isa=avx2" ? 2 : 3;
    if (avx512 && cap >= 3) return "avx512";
    if (avx2 && cap >= 2) return "avx2";
    if (__builtin_cpu_supports("avx") && cap >= 1) return "avx";
    return "sse4.2";
}

EmbreeTracer::EmbreeTracer(const HeightField& hf, double scale, double bias)
    : W_(hf.width), H_(hf.height), s_(scale), b_(bias) {
    throw_if_problem(scale_problem(scale));
    // Heights in units of zs_: 1 (no change at all) for every scale up to 2^32; above, the
    // power of two just under s, so that single-precision geometry and ray parameters stay in
    // range for any finite scale (Embree then traces z / zs_ along t / zs_).
    if (scale > 0x1p32) {
        int e = 0;
        std::frexp(scale, &e);
        zs_ = std::ldexp(1.0, e - 1);
    }
    const auto t0 = std::chrono::steady_clock::now();
    const std::string config = device_config();
    RTCDevice dev = rtcNewDevice(config.empty() ? nullptr : config.c_str());
    if (!dev) throw std::runtime_error("Embree: cannot create a device");
    RTCScene scene = rtcNewScene(dev);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry geom = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_GRID);
    // (W + 1) x (H + 1) vertices at texel centres of one period: u from 0.5/W to 1 + 0.5/W.
    const int vw = W_ + 1, vh = H_ + 1;
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), size_t(vw) * vh));
    for (int j = 0; j < vh; ++j)
        for (int i = 0; i < vw; ++i) {
            float* p = v + 3 * (size_t(j) * vw + i);
            p[0] = float((i + 0.5) / W_);
            p[1] = float((j + 0.5) / H_);
            p[2] = float(scale / zs_ * (double(hf.wrapped(i, j)) - bias));
        }
    auto* g = static_cast<RTCGrid*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_GRID, 0,
                                                            RTC_FORMAT_GRID, sizeof(RTCGrid), 1));
    g->startVertexID = 0;
    g->stride = unsigned(vw);
    g->width = (unsigned short)vw;
    g->height = (unsigned short)vh;
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene);
    // The tile instanced 3 x 3 around the base tile: a ray segment shorter than one tile in
    // u and v, started in the base tile, stays inside.
    RTCScene top = rtcNewScene(dev);
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            RTCGeometry inst = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_INSTANCE);
            rtcSetGeometryInstancedScene(inst, scene);
            const float xfm[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, float(dx), float(dy), 0};
            rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
            rtcCommitGeometry(inst);
            rtcAttachGeometry(top, inst);
            rtcReleaseGeometry(inst);
        }
    rtcCommitScene(top);
    if (rtcGetDeviceError(dev) != RTC_ERROR_NONE) {
        rtcReleaseScene(top);
        rtcReleaseScene(scene);
        rtcReleaseDevice(dev);
        throw std::runtime_error("Embree: scene build failed");
    }
    device_ = dev;
    tile_scene_ = scene;
    scene_ = top;
    build_ms_ =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

EmbreeTracer::~EmbreeTracer() {
    if (scene_) rtcReleaseScene(static_cast<RTCScene>(scene_));
    if (tile_scene_) rtcReleaseScene(static_cast<RTCScene>(tile_scene_));
    if (device_) rtcReleaseDevice(static_cast<RTCDevice>(device_));
}

namespace {

// One ray's walk, tile by tile: from the slab top at (ex, ey) along -V, up to tau_max (the slab
// bottom), in segments of at most seg (less than one tile in u and v).
struct Lane {
    Vec3d V;
    double ex, ey, t_in, tau_max, seg;
    bool done;
};

Lane start_lane(Vec2d P, Vec3d V, double zt, double s) {
    const double tau_max = s / V.z;
    const double reach = std::max(std::abs(V.x), std::abs(V.y));
    const double seg = reach > 0 ? 0.999 / reach : tau_max;  // < 1 tile per segment
    return {V, P.x + V.x / V.z * zt, P.y + V.y / V.z * zt, 0.0, tau_max, seg, false};
}

// An inactive lane (beyond a partial packet's rays, or finished) still holds a well-formed
// empty ray, whatever Embree reads of it: tnear > tfar, mask 0.
void set_empty_ray(RTCRayHit16& rh, int k) {
    rh.ray.org_x[k] = rh.ray.org_y[k] = rh.ray.org_z[k] = 0;
    rh.ray.dir_x[k] = rh.ray.dir_y[k] = 0;
    rh.ray.dir_z[k] = -1;
    rh.ray.tnear[k] = std::numeric_limits<float>::infinity();
    rh.ray.tfar[k] = -std::numeric_limits<float>::infinity();
    rh.ray.time[k] = 0;
    rh.ray.mask[k] = 0;
    rh.ray.id[k] = unsigned(k);
    rh.ray.flags[k] = 0;
    rh.hit.geomID[k] = rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
}

// The lane's next segment, [t_in, t_out], with its origin moved by whole tiles into the base
// tile (u0, v0: the first texel centre); returns t_out. Embree's ray parameter is tau / zs.
double set_segment(RTCRayHit16& rh, int k, const Lane& s, double zt, double zs, double u0,
                   double v0) {
    const Vec3d& V = s.V;
    double t_out = std::min(s.t_in + s.seg, s.tau_max);
    // A walk that cannot advance (t_in + seg == t_in: only far beyond the travel limit,
    // which trace refuses) ends in one last segment instead of looping forever.
    if (!(t_out > s.t_in)) t_out = s.tau_max;
    const double ox = std::floor(s.ex - s.t_in * V.x - u0);
    const double oy = std::floor(s.ey - s.t_in * V.y - v0);
    rh.ray.org_x[k] = float(s.ex - ox);
    rh.ray.org_y[k] = float(s.ey - oy);
    rh.ray.org_z[k] = float(zt / zs);
    rh.ray.dir_x[k] = float(-V.x * zs);
    rh.ray.dir_y[k] = float(-V.y * zs);
    rh.ray.dir_z[k] = float(-V.z);
    rh.ray.tnear[k] = float(s.t_in / zs);
    rh.ray.tfar[k] = float(t_out / zs * (1 + 1e-6) + 1e-9);
    rh.ray.time[k] = 0;
    rh.ray.mask[k] = 0xFFFFFFFF;
    rh.ray.id[k] = unsigned(k);
    rh.ray.flags[k] = 0;
    rh.hit.geomID[k] = rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    return t_out;
}

}  // namespace

// Per ray: segments of less than one tile in u and v (one segment for most rays), each
// traced with its origin moved into the base tile of the 3 x 3 instance block. Embree's ray
// parameter is tau / zs (z in units of zs, see the constructor; zs = 1 for ordinary scales).
void EmbreeTracer::trace_packet(const Vec2d* P, const Vec3d* V, size_t v_step, int n,
                                Vec2d* out) const {
    const double zs = zs_;
    const double zt = s_ * (1 - b_);
    const double u0 = 0.5 / W_, v0 = 0.5 / H_;
    Lane st[16];
    for (int k = 0; k < n; ++k) st[k] = start_lane(P[k], V[size_t(k) * v_step], zt, s_);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (;;) {
        alignas(64) RTCRayHit16 rh;
        alignas(64) int valid[16];
        double t_out[16];
        bool any = false;
        for (int k = 0; k < 16; ++k) {
            valid[k] = 0;
            if (k >= n || st[k].done) {
                set_empty_ray(rh, k);
                continue;
            }
            t_out[k] = set_segment(rh, k, st[k], zt, zs, u0, v0);
            valid[k] = -1;
            any = true;
        }
        if (!any) return;
        rtcIntersect16(valid, static_cast<RTCScene>(scene_), &ctx, &rh);
        for (int k = 0; k < n; ++k) {
            if (!valid[k]) continue;
            Lane& s = st[k];
            if (rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID) {
                const double t = double(rh.ray.tfar[k]) * zs;
                out[k] = {s.ex - t * s.V.x, s.ey - t * s.V.y};
                s.done = true;
            } else if (t_out[k] >= s.tau_max) {  // reached z_bot: on or below any surface
                out[k] = {s.ex - s.tau_max * s.V.x, s.ey - s.tau_max * s.V.y};
                s.done = true;
            } else {
                s.t_in = t_out[k];
            }
        }
    }
}

std::vector<Vec2d> EmbreeTracer::trace(const std::vector<Vec2d>& P, Vec3d V) const {
    std::vector<Vec2d> out;
    trace(P, V, out);
    return out;
}

void EmbreeTracer::trace(const std::vector<Vec2d>& P, Vec3d V, std::vector<Vec2d>& out) const {
    // Beyond the travel limit (or not above the surface) nothing is traced: the tile-by-tile
    // walk would take a packet call per tile of the travel.
    throw_if_problem(ray_travel_problem(s_, V));
    trace_all(P, &V, 0, out);
}

void EmbreeTracer::trace(const View& view, Hits& out) const {
    throw_if_problem(view_travel_problem(s_, view));  // every ray, before any work
    out.z.clear();
    out.cells.clear();
    trace_all(view.P, view.V.data(), view.parallel ? 0 : 1, out.uv);
}

void EmbreeTracer::trace_all(const std::vector<Vec2d>& P, const Vec3d* V, size_t v_step,
                             std::vector<Vec2d>& out) const {
    out.resize(P.size());
    const size_t packets = (P.size() + 15) / 16;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, packets, 16), [&](const auto& r) {
        for (size_t p = r.begin(); p < r.end(); ++p) {
            const size_t first = p * 16;
            const int n = int(std::min<size_t>(16, P.size() - first));
            trace_packet(P.data() + first, V + first * v_step, v_step, n, out.data() + first);
        }
    });
}

std::unique_ptr<Tracer> make_embree_tracer(const HeightField& hf, double scale, double bias) {
    return std::make_unique<EmbreeTracer>(hf, scale, bias);
}

}  // namespace pxh

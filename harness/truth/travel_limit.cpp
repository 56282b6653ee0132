#include "harness/truth/travel_limit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace pxh {

namespace {

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

std::string travel_problem(double scale, double theta_deg, double travel) {
    return "scale " + number(scale) + " at theta " + number(theta_deg) +
           " deg: the rays travel s tan(theta) = " + number(travel) +
           " tiles sideways through the relief, more than the ground truths' limit of " +
           number(kMaxRayTravelTiles) + " tiles (kMaxRayTravelTiles); lower the scale or the angle";
}

// Whether a ray along D of scale s stays within kMaxRayTravelTiles (s already checked).
bool within_travel_limit(double scale, Vec3d D) {
    if (!(D.z > 0 && std::isfinite(D.x) && std::isfinite(D.y))) return false;
    const double side = std::sqrt(D.x * D.x + D.y * D.y);
    return scale * (side / D.z) <= kMaxRayTravelTiles * (1 + 1e-9);  // NaN, inf: false
}

}  // namespace

std::string scale_problem(double scale) {
    if (std::isfinite(scale) && scale > 0) return "";
    return "scale = " + number(scale) + " is not a finite positive number";
}

void throw_if_problem(const std::string& problem) {
    if (!problem.empty()) throw std::invalid_argument(problem);
}

std::string ray_travel_problem(double scale, double theta_deg) {
    if (std::string p = scale_problem(scale); !p.empty()) return p;
    if (!(theta_deg >= 0 && theta_deg < 90))
        return "theta = " + number(theta_deg) + " deg lies outside [0, 90)";
    const double travel = scale * std::tan(theta_deg * M_PI / 180.0);  // view_vector's radians
    return travel <= kMaxRayTravelTiles ? "" : travel_problem(scale, theta_deg, travel);
}

std::string ray_travel_problem(double scale, Vec3d D) {
    if (std::string p = scale_problem(scale); !p.empty()) return p;
    if (within_travel_limit(scale, D)) return "";
    if (!(D.z > 0 && std::isfinite(D.x) && std::isfinite(D.y)))
        return "the ray direction (" + number(D.x) + ", " + number(D.y) + ", " + number(D.z) +
               ") does not point above the surface (theta must lie in [0, 90))";
    const double side = std::sqrt(D.x * D.x + D.y * D.y);
    const double travel = scale * (side / D.z);  // beyond the limit, NaN or inf
    return travel_problem(scale, std::atan2(side, D.z) * 180 / M_PI, travel);
}

std::string sample_reach_problem(Vec2d P, int width, int height) {
    const double cells = std::max(std::abs(P.x) * width, std::abs(P.y) * height);
    if (cells <= kMaxSampleCells) return "";  // NaN: false
    return "the sample at uv (" + number(P.x) + ", " + number(P.y) + ") lies " + number(cells) +
           " cells from the origin of the " + std::to_string(width) + " x " +
           std::to_string(height) + " field, beyond the exact tracer's limit of 2^36 cells " +
           "(kMaxSampleCells), where its doubles no longer resolve a hit: bring the eye closer";
}

std::string reach_problem(double reach, int width, int height) {
    const double cells = reach * std::max(width, height);
    if (cells <= kMaxSampleCells) return "";  // NaN: false
    return "puts inside pixels up to " + number(reach) + " tiles from the origin, " +
           number(cells) + " cells of the " + std::to_string(width) + " x " +
           std::to_string(height) +
           " field: beyond the exact tracer's reach of 2^36 cells (kMaxSampleCells), where its "
           "doubles no longer resolve a hit; bring the eye closer";
}

std::string view_reach_problem(const View& view, int width, int height) {
    for (const Vec2d& P : view.P)  // no string built per accepted sample
        if (!(std::max(std::abs(P.x) * width, std::abs(P.y) * height) <= kMaxSampleCells))
            return sample_reach_problem(P, width, height);
    return "";
}

std::string view_travel_problem(double scale, const View& view) {
    if (std::string p = view_problem(view); !p.empty()) return p;
    if (std::string p = scale_problem(scale); !p.empty()) return p;
    for (const Vec3d& D : view.V)  // no string built per accepted ray
        if (!within_travel_limit(scale, D)) return ray_travel_problem(scale, D);
    return "";
}

}  // namespace pxh

// The sphere base (docs/conventions.md section 12), a UV sphere around the look-at point:
// B = (0.5, 0.5, -R) + R n, n = (cos(v'/R) sin(u'/R), sin(v'/R), cos(v'/R) cos(u'/R)), N = n,
// u' = u - 0.5, v' = v - 0.5. Along the equator v' = 0 arc length equals u; away from it u is
// compressed by cos(v'/R).
#include <algorithm>

#include "harness/scene/bases/bases.h"

namespace pxh {

namespace {

class SphereBase final : public BaseSurface {
  public:
    explicit SphereBase(double R) : R_(R) {}
    std::string name() const override { return "sphere"; }
    double radius() const override { return R_; }
    BaseFrame frame(Vec2d uv) const override {
        const double a = (uv.x - 0.5) / R_, e = (uv.y - 0.5) / R_;
        const double sa = std::sin(a), ca = std::cos(a), se = std::sin(e), ce = std::cos(e);
        const Vec3d n{ce * sa, se, ce * ca};
        return {{0.5 + R_ * n.x, 0.5 + R_ * n.y, -R_ + R_ * n.z},
                {ca, 0, -sa},
                {-se * sa, ce, -se * ca},
                n};
    }
    BaseCoord coords(Vec3d p) const override {
        const Vec3d q{p.x - 0.5, p.y - 0.5, p.z + R_};
        const double r = std::sqrt(v3_dot(q, q));
        const double e = std::asin(std::clamp(q.y / r, -1.0, 1.0));
        return {{0.5 + R_ * std::atan2(q.x, q.z), 0.5 + R_ * e}, r - R_};
    }
    double hit(Vec3d o, Vec3d d, double offset, double t_min, bool leaving) const override {
        const Vec3d q{o.x - 0.5, o.y - 0.5, o.z + R_};
        const double r = R_ + offset;
        const QuadRoots roots = quad_roots(v3_dot(d, d), v3_dot(q, d), v3_dot(q, q) - r * r);
        const double t = leaving ? roots.t1 : roots.t0;
        return t > t_min ? t : NAN;
    }
    Vec2d curvature() const override { return {1 / R_, 1 / R_}; }
    double uv_speed(Vec3d p) const override {
        // |d(lat)/dt| <= 1/r, |d(azimuth)/dt| <= 1/(r cos(lat)): u and v move R times that
        const Vec3d q{p.x - 0.5, p.y - 0.5, p.z + R_};
        const double r = std::sqrt(v3_dot(q, q));
        const double c = std::sqrt(std::max(q.x * q.x + q.z * q.z, 0.0)) / std::max(r, 1e-300);
        return std::max(1.0, R_ / std::max(r * std::max(c, 1e-3), 1e-12 * R_));
    }

  private:
    double R_;
};

}  // namespace

std::unique_ptr<BaseSurface> make_sphere_base(double radius) {
    return std::make_unique<SphereBase>(radius);
}

}  // namespace pxh

// The cylinder base (docs/conventions.md section 12), axis along y through (0.5, *, -R):
// B = (0.5 + R sin(u'/R), v, R cos(u'/R) - R), N = (sin(u'/R), 0, cos(u'/R)), u' = u - 0.5.
// Arc length along u equals u: the texture is not stretched.
#include "harness/scene/bases/bases.h"

namespace pxh {

namespace {

class CylinderBase final : public BaseSurface {
  public:
    explicit CylinderBase(double R) : R_(R) {}
    std::string name() const override { return "cylinder"; }
    double radius() const override { return R_; }
    BaseFrame frame(Vec2d uv) const override {
        const double a = (uv.x - 0.5) / R_, s = std::sin(a), c = std::cos(a);
        return {{0.5 + R_ * s, uv.y, R_ * c - R_}, {c, 0, -s}, {0, 1, 0}, {s, 0, c}};
    }
    BaseCoord coords(Vec3d p) const override {
        const double x = p.x - 0.5, z = p.z + R_;
        return {{0.5 + R_ * std::atan2(x, z), p.y}, std::hypot(x, z) - R_};
    }
    double hit(Vec3d o, Vec3d d, double offset, double t_min, bool leaving) const override {
        // |(o + t d) - axis|^2 in xz = (R + offset)^2
        const double x = o.x - 0.5, z = o.z + R_, r = R_ + offset;
        const QuadRoots q =
            quad_roots(d.x * d.x + d.z * d.z, x * d.x + z * d.z, x * x + z * z - r * r);
        const double t = leaving ? q.t1 : q.t0;
        return t > t_min ? t : NAN;
    }
    Vec2d curvature() const override { return {1 / R_, 0}; }
    double uv_speed(Vec3d p) const override {
        const double rho = std::hypot(p.x - 0.5, p.z + R_);
        return std::max(1.0, R_ / std::max(rho, 1e-12 * R_));
    }

  private:
    double R_;
};

}  // namespace

std::unique_ptr<BaseSurface> make_cylinder_base(double radius) {
    return std::make_unique<CylinderBase>(radius);
}

}  // namespace pxh

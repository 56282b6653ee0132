// The plane base (docs/conventions.md section 12): B = (u, v, 0), N = (0, 0, 1): sections 1-11.
#include "harness/scene/bases/bases.h"

namespace pxh {

namespace {

class PlaneBase final : public BaseSurface {
  public:
    std::string name() const override { return "plane"; }
    double radius() const override { return NAN; }
    BaseFrame frame(Vec2d uv) const override {
        return {{uv.x, uv.y, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    }
    BaseCoord coords(Vec3d p) const override { return {{p.x, p.y}, p.z}; }
    double hit(Vec3d o, Vec3d d, double offset, double t_min, bool leaving) const override {
        // inside the shell: z <= offset; entering it going down, leaving it going up
        if (d.z == 0) return NAN;
        const double t = (offset - o.z) / d.z;
        if (!(t > t_min)) return NAN;
        return (d.z < 0) != leaving ? t : NAN;
    }
    double uv_speed(Vec3d) const override { return 1; }
    Vec2d curvature() const override { return {0, 0}; }
};

}  // namespace

std::unique_ptr<BaseSurface> make_plane_base(double) { return std::make_unique<PlaneBase>(); }

}  // namespace pxh

// The base surfaces' factories, one per file in this folder (registry.cpp lists them).
#pragma once
#include "harness/scene/base_surface.h"

namespace pxh {

std::unique_ptr<BaseSurface> make_plane_base(double radius);
std::unique_ptr<BaseSurface> make_cylinder_base(double radius);
std::unique_ptr<BaseSurface> make_sphere_base(double radius);

}  // namespace pxh

// The travel limit: how far sideways, in tiles, an eye or light ray may travel through the
// relief before the ground truths refuse it.
#pragma once
#include <string>

#include "harness/core/vec.h"
#include "harness/scene/view.h"

namespace pxh {

// The longest horizontal path, in tiles, an eye or light ray may travel through the relief:
// s tan(theta) (the ray drops through the slab's height s and moves tan(theta) sideways per
// unit of drop). Near 90 degrees it grows without bound, and with it the work of both ground
// truths whenever a ray skims the relief and meets it late (at worst only at the slab bottom):
// Embree walks the path one tile per packet call, the exact tracer keeps bounds per band of
// rays along it, and the true-shadow walk steps through its cells. 6000 tiles keeps every
// shipped view (hard_cases.toml: s = 1 at 89.99 degrees, 5730 tiles). Measured at the limit
// (pxh run, s = 1, 256 x 256 samples, 2 cores; fbm, a single spike, flat at the slab bottom;
// azimuths 0 and 20): at most 13 s and 184 MB on a 32 x 32 field, 20 s and 1.09 GB on a
// 4096 x 4096 one (whose run takes 8 s and 1.01 GB at any angle). It also keeps every grid
// index the tracers convert from a double in range (6000 tiles x 16384 texels < 2^27). Views
// beyond it are refused when an experiment is read and by pxh bench and, as a last line of
// defence, by the tracers' entry points.
inline constexpr double kMaxRayTravelTiles = 6000;

// "" when rays of scale s at polar angle theta (degrees) stay within kMaxRayTravelTiles, else
// a one-line reason naming the value and the limit (also for a scale that is not a finite
// positive number, or theta outside [0, 90)).
std::string ray_travel_problem(double scale, double theta_deg);
// The same for a ray direction D (unit; D.z > 0 points from the surface toward the eye or
// light), as the tracers see it; a rounding margin over the limit is let through, so that
// every view ray_travel_problem(scale, theta) accepts is accepted here too.
std::string ray_travel_problem(double scale, Vec3d D);
// The first problem of a view: view_problem's, else ray_travel_problem's for its directions.
std::string view_travel_problem(double scale, const View& view);

// The reach limit: how far from the origin, in cells of the field (|u| W, |v| H), a sample's
// point may lie before the exact tracer refuses it: 2^36 cells. There its doubles still resolve
// 2^-16 of a cell (a hit to 1.5e-5 texel); far beyond, a perspective eye at D = 1e15 tiles over
// a 32 x 32 field puts samples 2^53 cells out, where the DDA's next exit line x + 1 rounds back to
// x and the walk never ends. The ray's entry into the slab lies within the travel limit of its
// sample (6000 tiles x 16384 texels < 2^27 cells), inside the margin this leaves. Views beyond it
// are refused when an experiment is read (the perspective camera's farthest inside pixel, at the
// camera's key) and by pxh bench, and, as a last line of defence, by the tracers' entry points.
inline constexpr double kMaxSampleCells = 68719476736.0;  // 2^36

// "" when the point P of a field of W x H texels lies within kMaxSampleCells of the origin (in
// each of |P.x| W and |P.y| H; NaN or infinite: a problem), else a one-line reason naming the
// point, the cells and the limit.
std::string sample_reach_problem(Vec2d P, int width, int height);
// "" when samples up to `reach` tiles from the origin (in u and in v) lie within
// kMaxSampleCells of a W x H field, else a reason naming both ("... puts inside pixels up to
// R tiles from the origin, C cells of the W x H field: beyond ...").
std::string reach_problem(double reach, int width, int height);
// The first problem of a view's samples (sample_reach_problem of each P), "" if none.
std::string view_reach_problem(const View& view, int width, int height);

// "" unless the scale is not a finite positive number.
std::string scale_problem(double scale);

// Throws std::invalid_argument with the reason, if there is one.
void throw_if_problem(const std::string& problem);

}  // namespace pxh

// The depth metrics beyond the per-output ones of depth.cpp (depth_err_*, depth_bias_mean,
// depth_toward_frac): what a depth test against an opaque plane shows (docs/conventions.md
// section 11).
#pragma once
#include "harness/backends/backend.h"
#include "harness/metrics/row.h"
#include "harness/truth/ground_truth.h"

namespace pxh {

// cut_flip_frac: over the inside samples (not excluded) with a written depth and a true hit,
// the fraction where the plane z = z_cut shows in truth (the ray meets it before the surface)
// but not for the method (its depth is not nearer than the written one), or the other way.
// Returns, per sample, what each shows (bit 0: the plane in truth, bit 1: the plane for the
// method; 0 for the samples not counted), for pictures of the depth test; empty where the
// row has no depths.
std::vector<uint8_t> add_cut_flips(const MethodOutput& out, const GroundTruth& gt, const View& view,
                                   const std::vector<uint8_t>* exclude, double z_cut,
                                   ResultRow& row);

}  // namespace pxh

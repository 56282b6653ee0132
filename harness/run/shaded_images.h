// [shading]: every row's view shaded through its uv and through the truth's (harness/scene/
// shading.h, docs/conventions.md section 13), compared by LDR-FLIP (flip_mean, flip_p95,
// flip_max); for the [render] views also the shaded images and the FLIP map as PNG. A results
// writer (harness/run/view_writers.h), registered there after the pictures.
#pragma once
#include "harness/run/view_writers.h"

namespace pxh {

bool shading_wanted(const Experiment& ex);
void write_shaded(const ViewWriteContext& c, ViewOutput& v);

// Whether a view's rows see the camera's whole image: samples equal to the camera's
// resolution (always for a camera without one). Under a `samples` subset the shaded images
// are made of the view evaluated over the whole image (ViewOutput::whole).
bool shades_whole_image(const ResultRow& row, int samples);

}  // namespace pxh

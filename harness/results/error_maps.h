// Error maps: per row, an EXR with the error vector and its magnitude per sample, and a
// false-colour PNG with a title and a legend (through OpenImageIO).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "harness/core/vec.h"
#include "harness/metrics/row.h"

namespace pxh {

// Texel error to colour: log2 scale from 1/16 to 16 texels (viridis-like ramp); exactly 0
// is the darkest colour, non-finite is magenta.
void error_colour(double texels, float rgb[3]);

// Where the map itself lies in the PNG of an N x N map: a side x side square whose top-left
// pixel is (x0, y0), the title above it and the colour bar below (pxh report crops it out).
struct ErrorMapBox {
    int x0, y0, side;
};
ErrorMapBox error_map_box(int n);

// Writes DIR/STEM.exr (channels e_x, e_y, |e| in texels; row j of the sample grid is file row
// j, as for height maps) and DIR/STEM.png, both new files (never through a link, never over a
// file; DIR is created if missing); returns the PNG's file name. A camera's map: `inside`
// (empty: every sample) marks the samples in the view, the others grey (0.5) in the PNG, not
// the magenta of a non-finite error; `as_seen` draws the PNG's rows as the camera's pictures
// are (harness/results/pictures.h, write_picture: sample row j is PNG row n - 1 - j), so a
// map lies as the picture of its view does. The EXR keeps the sample grid's order.
std::string write_error_map(const std::vector<Vec2d>& errors, int n, const std::string& dir,
                            const std::string& stem, const std::string& title,
                            const std::vector<uint8_t>& inside = {}, bool as_seen = false);

// A row's error map: its file stem ("00012_pom_layers-32_fbm_t60_p0_cpu-float": index, method,
// its parameters (long ones cut and ended by a hash), field, view, backend variant; safe
// characters only; `index` is the row's index in results.csv) and the title drawn on it.
struct ErrorMapName {
    std::string stem, title;
};
ErrorMapName error_map_name(const ResultRow& row, size_t index);
// "_TAG VALUE" for each of its camera's keys (the perspective camera: "_dD_fF"), "" for a camera
// without keys: the part of every map, picture and truth picture name that tells camera
// settings apart.
std::string camera_name_part(const ResultRow& row);

}  // namespace pxh

// Sliding and shimmering of a row from its error vectors and those of the next view of a sweep:
// a view dt degrees away (theta) or the next eye distance (a perspective camera's distance
// sweep) (docs/conventions.md section 5.3; the statistics are sweep_metrics in metrics.h).
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "harness/core/vec.h"
#include "harness/metrics/row.h"
#include "harness/scene/view.h"

namespace pxh {

// sliding, shimmering, sweep_dt_deg; nothing when either view has no error vectors (a failed
// row). `lo` is the view at the smaller θ.
void add_sweep(const std::vector<Vec2d>& lo, const std::vector<Vec2d>& hi, double dt_deg,
               ResultRow& row);

// sliding_dist, shimmering_dist (texels per tile of eye distance), sweep_dd (tiles); nothing
// when either view has no error vectors. `near` is the view at the smaller distance, `far` the
// one dd tiles farther, pixel for pixel.
void add_distance_sweep(const std::vector<Vec2d>& near, const std::vector<Vec2d>& far, double dd,
                        ResultRow& row);

// A camera setting's successor along the sweep of the camera's pair key (CameraEntry::pair_key:
// the perspective camera's distance): the next setting in the list with every other key
// (fov_deg, resolution) equal, when its value of the key is larger (dd > 0); the settings'
// order is the experiment's (the pair key outer). No key (""): no successors.
struct DistanceStep {
    size_t next = 0;  // index into the settings
    double dd = 0;    // its value minus this one's (tiles); 0: no successor
    bool pairs() const { return dd > 0; }
};
std::vector<DistanceStep> distance_steps(const std::vector<CameraSetting>& settings,
                                         const std::string& pair_key);

}  // namespace pxh

// The run's views as one grid: (height-field entry, azimuth, camera setting, theta), in the
// order the runner meets them (field outer, theta inner), each view's index in that order, the
// theta sweeps (one per field, azimuth and camera setting), and a slice of the grid (pxh run
// --shard: the views of the units it takes). The runner, the shard partition, the run's
// estimate and the run record all index views here and nowhere else.
#pragma once
#include <cstddef>
#include <functional>
#include <vector>

#include "harness/experiment/experiment.h"

namespace pxh {

// One view of the grid: indices into heightfields, phi_deg, camera_settings and theta_deg.
struct ViewAt {
    size_t field = 0, phi = 0, camera = 0, theta = 0;
};

class ViewGrid {
  public:
    explicit ViewGrid(const Experiment& ex)
        : fields(ex.heightfields.size()),
          phis(ex.phi_deg.size()),
          cameras(ex.camera_settings.size()),
          thetas(ex.theta_deg.size()) {}
    ViewGrid(size_t fields_, size_t phis_, size_t cameras_, size_t thetas_)
        : fields(fields_), phis(phis_), cameras(cameras_), thetas(thetas_) {}

    size_t fields, phis, cameras, thetas;

    size_t views() const { return fields * views_per_field(); }
    size_t views_per_field() const { return sweeps_per_field() * thetas; }
    // The theta sweeps of one field (azimuth outer, camera setting inner), and of the run.
    size_t sweeps_per_field() const { return phis * cameras; }
    size_t sweeps() const { return fields * sweeps_per_field(); }
    // Sweep s of the run (s < sweeps()): its field, azimuth and camera setting (theta 0).
    ViewAt sweep(size_t s) const {
        const size_t per = sweeps_per_field();
        return {s / per, s % per / cameras, s % cameras, 0};
    }
    size_t sweep_index(const ViewAt& v) const {
        return (v.field * phis + v.phi) * cameras + v.camera;
    }
    // The view's place in run order.
    size_t index(const ViewAt& v) const { return sweep_index(v) * thetas + v.theta; }
};

// Which views of the grid a run makes: all, or a slice's (pxh run --shard).
using ViewFilter = std::function<bool(const ViewAt&)>;

}  // namespace pxh

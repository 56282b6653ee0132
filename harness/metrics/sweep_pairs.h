// Which views of a run pair up for sliding and shimmering (docs/conventions.md section 5.3),
// and what each pair waits for while the run makes its views: consecutive views of a theta sweep
// (or, with sweep_dt_deg, each view and a companion view dt away), and along the camera's pair
// key (CameraEntry::pair_key: the perspective camera's distance) each view and the view at its
// successor setting (same field, azimuth and theta). The runner says which views ran and where
// their rows are; the pairer keeps the error vectors a pair still needs and writes the pair's
// columns (add_sweep, add_distance_sweep) into the nearer or lower view's rows.
#pragma once
#include <array>
#include <cstddef>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "harness/core/vec.h"
#include "harness/metrics/row.h"
#include "harness/metrics/sweep.h"
#include "harness/scene/view.h"

namespace pxh {

// Per row of a view, its per-sample error vectors (empty for a failed row).
using ViewErrors = std::vector<std::vector<Vec2d>>;

class SweepPairer {
  public:
    SweepPairer(std::vector<double> theta_deg, double sweep_dt_deg,
                const std::vector<CameraSetting>& settings, const std::string& pair_key);

    // The theta of the companion view a view at `theta` pairs with (sweep_dt_deg > 0: dt above,
    // or below when theta + dt would reach 90); nullopt when views pair with their neighbours.
    std::optional<double> theta_companion(double theta) const;
    // A view at `theta` and its companion: the pair's columns into the view's rows.
    void pair_companion(double theta, const ViewErrors& view, const ViewErrors& companion,
                        std::vector<ResultRow>& rows) const;

    // The view's successor along the pair key at camera setting `camera` (pairs() false: none).
    const DistanceStep& successor(size_t camera) const { return steps_[camera]; }
    // A view and the view at its successor setting run as a companion (the slice does not run
    // that view): the pair's columns into the view's rows.
    void pair_successor(size_t camera, const ViewErrors& view, const ViewErrors& far,
                        std::vector<ResultRow>& rows) const;

    // A field (and its s, b) starts: nothing waits across fields.
    void start_field();
    // A theta sweep (field, phi, camera setting) starts: no previous view.
    void start_sweep();
    // View theta_deg[theta] of the sweep at (phi, camera) ran: pairs it with the previous view of
    // its sweep and with the nearer view waiting for it, writing those views' rows in `run_rows`.
    void pair_earlier(size_t phi, size_t camera, size_t theta, const ViewErrors& errors,
                      std::vector<ResultRow>& run_rows);
    // Keeps what the view's later pairs need: its errors as the sweep's previous view, and, when
    // `wait` (its successor setting's view runs later in this run), until that view runs.
    // `index`: its rows' indices in the run.
    void keep(size_t phi, size_t camera, size_t theta, ViewErrors errors, std::vector<size_t> index,
              bool wait);

  private:
    struct Kept {
        std::shared_ptr<const ViewErrors> errors;
        std::vector<size_t> index;  // the rows' indices in the run
    };
    std::vector<double> theta_;
    double dt_;
    std::vector<DistanceStep> steps_;  // per camera setting
    std::vector<size_t> before_;       // per camera setting: the one whose successor it is
    std::optional<Kept> previous_;     // the sweep's previous view (consecutive thetas)
    size_t previous_theta_ = 0;
    std::map<std::array<size_t, 3>, Kept> waiting_;  // (phi, camera, theta) of a nearer view
};

}  // namespace pxh

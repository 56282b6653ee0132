// One view of one field: its rays (from the base's entry), its truth (the base's truth), and
// one row per method setting x backend x variant, scored (harness/metrics/score.h).
#pragma once
#include <memory>
#include <vector>

#include "harness/backends/backend.h"
#include "harness/experiment/experiment.h"
#include "harness/run/side_lane.h"
#include "harness/run/truth_stage.h"
#include "harness/scene/texture_levels.h"

namespace pxh {

// Everything one view produces: its rows and, per row, the per-sample error vectors (empty
// for a failed row), in a fixed order (methods x backends x variants).
struct ViewRows {
    std::vector<ResultRow> rows;
    std::vector<std::vector<Vec2d>> errors;
    std::vector<Vec2d> truth_uv;                  // the view's true hits (per sample, unwrapped)
    std::vector<uint8_t> inside;                  // the view's inside mask (View::inside)
    std::vector<std::vector<uint8_t>> cut_shows;  // per row: ViewOutput::cut_shows
    // per row, where the truth reports coverage (a curved base's): ViewOutput::shown_uv
    std::vector<std::vector<Vec2d>> shown_uv;
    std::vector<uint8_t> truth_hit;          // ... and ViewOutput::truth_hit
    std::vector<double> lambda;              // each sample's level of detail: ViewOutput::lambda
    std::vector<std::vector<float>> shaded;  // per row: ViewOutput::shaded
    // [shading] with `samples` below the camera's resolution: the same rows over the camera's
    // whole image (ViewOutput::whole); nullptr otherwise.
    std::shared_ptr<const ViewRows> whole;
};

// One field (with its s, b and base) and what every view of it shares.
struct FieldContext {
    const Experiment& ex;
    const std::vector<std::unique_ptr<Backend>>& backends;
    Backend& reference;  // the reference backend's float run other backends are compared with
    const HeightField& hf;
    const HeightfieldSpec& spec;
    ResourceCache& resources;     // the methods' precomputed textures for this field
    const TextureLevels* levels;  // the field's texture levels when a setting samples them
    const BaseEntry& base_entry;  // the base's entry: its views
    const BaseSurface& base;      // the base itself (its curvature: the methods' scene)
    const FieldTruth& truth;      // the base's truth
    // The thread the rows of backends in a process of their own are drawn on, beside the truth
    // and the other rows (harness/run/side_lane.h); nullptr: every row on the calling thread.
    // Used in untimed views, and in every view when the run times nothing (`times_nothing`).
    SideLane* lane = nullptr;
    bool times_nothing = false;
};

// The rows of one view (theta, phi, the experiment's camera setting `camera`). timed = false
// (a sweep's companion view, whose rows are not reported): no timing passes, no agreement
// statistics.
ViewRows evaluate_view(const FieldContext& c, double theta, double phi, size_t camera, bool timed);

}  // namespace pxh

// The truth stage: a field's truth on its base, built once per field (and s, b, base) and shared
// by its views, and what it gives each view (its ground truth, the references' agreement, a
// curved base's coverage). Which truth traces a base is the base's entry's (BaseEntry::truth),
// by name from truth_registry(): the runner names neither.
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "harness/experiment/experiment.h"
#include "harness/metrics/metric.h"
#include "harness/metrics/metrics.h"
#include "harness/scene/curved_view.h"
#include "harness/truth/ground_truth.h"

namespace pxh {

// What the truth stage gives a view: its ground truth and the two references' disagreement.
struct ViewTruth {
    GroundTruth gt;
    ErrorStats agree;  // |hit_other - hit_exact| in texels (NaN when the other did not run)
    std::optional<Coverage> cover;  // a curved base's: base and true hits per sample
    double residual_max = NAN;      // a curved base's: max |g| at the true hits (tiles)
};

// One field's (and s, b, base's) truth.
class FieldTruth {
  public:
    virtual ~FieldTruth() = default;
    // The view's truth (its rays as the base's entry gave them). timed = false (a sweep's
    // companion view): the agreement statistics are left out where they cost a second trace.
    // A view the truth refuses is an InputError at the field's entry naming the view.
    virtual ViewTruth trace(const BaseView& view, double theta, double phi, bool timed) const = 0;
};

// What a truth is built for.
struct TruthSetting {
    const Experiment& ex;
    const HeightField& hf;
    const HeightfieldSpec& spec;
    const BaseSurface& base;
};

struct TruthEntry {
    const char* name;
    std::unique_ptr<FieldTruth> (*make)(const TruthSetting&);
};
const std::vector<TruthEntry>& truth_registry();
// The truth NAME (a base's BaseEntry::truth) built for the field.
std::unique_ptr<FieldTruth> make_field_truth(const std::string& name, const TruthSetting& s);

}  // namespace pxh

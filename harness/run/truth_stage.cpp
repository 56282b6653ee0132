#include "harness/run/truth_stage.h"

#include <cmath>

#include "harness/core/error.h"
#include "harness/core/params.h"
#include "harness/core/registry.h"
#include "harness/metrics/agreement.h"
#include "harness/truth/curved_tracer.h"
#include "harness/truth/tracer.h"

namespace pxh {

namespace {

void no_agreement(ErrorStats& a) { a.p50 = a.p99 = a.max = a.frac_gt_0_5 = NAN; }

// The flat relief's truth: the tracer registry's two references, the exact one (heights, true
// shadows, cost) and the cross-check (gt_agree_*); the experiment's ground_truth names which of
// the two gives the uv. A sweep's companion view (timed = false) traces the other reference
// only when it is the ground truth.
class ExactTruth final : public FieldTruth {
  public:
    explicit ExactTruth(const TruthSetting& s)
        : ex_(s.ex),
          hf_(s.hf),
          other_(make_tracer(TracerRole::cross_check, s.hf, s.spec.scale, s.spec.bias)),
          exact_(make_tracer(TracerRole::exact_reference, s.hf, s.spec.scale, s.spec.bias)) {}

    ViewTruth trace(const BaseView& bv, double, double, bool timed) const override {
        const View& view = bv.view;
        const Vec3d L = ex_.light ? view_vector(ex_.light->theta_deg, ex_.light->phi_deg) : Vec3d{};
        ViewTruth t;
        t.gt = trace_ground_truth(*exact_, view, ex_.light ? &L : nullptr);
        no_agreement(t.agree);
        const bool other_is_truth = ex_.ground_truth == other_->name();
        if (timed || other_is_truth) {
            Hits other;
            other_->trace(view, other);
            t.agree = reference_agreement(other.uv, t.gt.uv, hf_.width, hf_.height);
            if (other_is_truth) t.gt.uv = std::move(other.uv);
        }
        return t;
    }

  private:
    const Experiment& ex_;
    const HeightField& hf_;
    std::unique_ptr<Tracer> other_, exact_;
};

// A curved base's truth: the walk's hits (uv NaN where the ray misses the displaced surface),
// its residual, and (timed views) its agreement with the walk at half the step over the rays
// both hit.
class CurvedWalkTruth final : public FieldTruth {
  public:
    explicit CurvedWalkTruth(const TruthSetting& s)
        : spec_(s.spec),
          hf_(s.hf),
          base_(s.base),
          walk_(make_curved_truth(s.hf, s.spec.scale, s.spec.bias, s.base)),
          check_(s.hf, s.spec.scale, s.spec.bias, s.base, walk_->step_texels() / 2) {}

    ViewTruth trace(const BaseView& cv, double theta, double phi, bool timed) const override {
        // A view's curved walks over their step budget (kMaxCurvedWalkSteps; views the
        // estimate lets through whose rays skim the relief) refuse the run at the field's
        // entry, naming the view, the steps, the limit and the knobs.
        try {
            return walk(cv, timed);
        } catch (const CurvedWalkTooLong& e) {
            throw InputError(
                spec_.where,
                "heightfield '" + spec_.name + "' (base " + spec_.base + " radius " +
                    format_number(spec_.radius) + ") at theta " + format_number(theta) + " phi " +
                    format_number(phi) + ": the curved truth's walk stopped after " +
                    format_number(e.steps) + " steps for the " + std::to_string(cv.rays.size()) +
                    " rays of this view (the walk and its check together), over the limit of "
                    "2^28 steps a view (kMaxCurvedWalkSteps; rays that skim the relief step "
                    "shorter than the quarter texel the estimate before the run assumes): lower "
                    "theta, the scale, the field's size or samples");
        }
    }

  private:
    ViewTruth walk(const BaseView& cv, bool timed) const {
        ViewTruth t;
        // Both walks count against one budget per view, kMaxCurvedWalkSteps: the same limit,
        // and the same steps, as the estimate the experiment was checked with when it was read.
        CurvedHits h = walk_->trace(cv.rays, kMaxCurvedWalkSteps);
        const double check_budget = kMaxCurvedWalkSteps - h.steps;
        // depths from the base hit along the camera's axis (docs/conventions.md sections 11, 12)
        t.gt.depth.assign(h.uv.size(), NAN);
        for (size_t k = 0; k < h.uv.size(); ++k)
            if (h.hit[k] && cv.base_hit[k])
                t.gt.depth[k] = v3_dot(v3_sub(h.point[k], cv.base_point[k]), cv.forward);
        const BaseSurface* base = &base_;
        t.gt.shell_depth = [base, &cv](size_t k, double z) {
            if (!cv.base_hit[k]) return double(NAN);
            const WorldRay& r = cv.rays[k];
            const double tc = base->hit(r.o, r.d, z, 0, false);
            if (!std::isfinite(tc)) return double(NAN);
            return v3_dot(v3_sub(v3_add(r.o, v3_scale(r.d, tc)), cv.base_point[k]), cv.forward);
        };
        t.gt.uv = std::move(h.uv);
        t.gt.z = std::move(h.z);
        t.gt.cells_mean = NAN;
        t.residual_max = h.residual_max;
        t.cover = Coverage{cv.base_hit, std::move(h.hit)};
        no_agreement(t.agree);
        if (timed) {
            CurvedHits fine;
            try {
                fine = check_.trace(cv.rays, check_budget);
            } catch (const CurvedWalkTooLong& e) {  // the view's steps: both walks'
                throw CurvedWalkTooLong(e.what(), h.steps + e.steps, kMaxCurvedWalkSteps);
            }
            std::vector<Vec2d> a, b;
            for (size_t k = 0; k < fine.uv.size(); ++k)
                if (t.cover->truth_hit[k] && fine.hit[k]) {
                    a.push_back(fine.uv[k]);
                    b.push_back(t.gt.uv[k]);
                }
            t.agree = reference_agreement(a, b, hf_.width, hf_.height);
        }
        return t;
    }

    const HeightfieldSpec& spec_;
    const HeightField& hf_;
    const BaseSurface& base_;
    // the curved truth (the pyramid tracer where the base has a closed form: make_curved_truth)
    // and the walk at half the step its agreement columns compare it with
    std::unique_ptr<CurvedTracer> walk_;
    CurvedTracer check_;
};

template <class T>
std::unique_ptr<FieldTruth> make(const TruthSetting& s) {
    return std::make_unique<T>(s);
}

}  // namespace

const std::vector<TruthEntry>& truth_registry() {
    static const std::vector<TruthEntry> entries = {
        {"exact", &make<ExactTruth>},
        {"curved_walk", &make<CurvedWalkTruth>},
    };
    return entries;
}

std::unique_ptr<FieldTruth> make_field_truth(const std::string& name, const TruthSetting& s) {
    return find_entry(truth_registry(), name, "truth", "base '" + s.spec.base + "'").make(s);
}

}  // namespace pxh

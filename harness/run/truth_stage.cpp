#include "harness/run/truth_stage.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "harness/core/error.h"
#include "harness/core/params.h"
#include "harness/core/registry.h"
#include "harness/metrics/agreement.h"
#include "harness/truth/curved_tracer.h"
#include "harness/truth/tracer.h"

namespace pxh {

namespace {

void no_agreement(ErrorStats& a) {
    a.p50 = a.p99 = a.max = a.frac_gt_0_5 = NAN;
    a.count = 0;
}

// The view of the samples `ks` of `v` (their P, V, footprints, inside flags and depth axes).
View sub_view(const View& v, const std::vector<size_t>& ks) {
    View s;
    s.parallel = v.parallel;
    s.forward = v.forward;
    for (size_t k : ks) {
        s.P.push_back(v.P[k]);
        if (!v.parallel) s.V.push_back(v.V[k]);
        if (v.J.size() > 1) s.J.push_back(v.J[k]);
        if (!v.inside.empty()) s.inside.push_back(v.inside[k]);
        if (!v.axes.empty()) s.axes.push_back(v.axes[k]);
    }
    if (v.parallel) s.V = v.V;
    if (v.J.size() == 1) s.J = v.J;
    return s;
}

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
        if (other_is_truth) {  // the other reference gives the uv: traced on every ray
            Hits other;
            other_->trace(view, other);
            t.agree = reference_agreement(other.uv, t.gt.uv, hf_.width, hf_.height);
            t.gt.uv = std::move(other.uv);
        } else if (timed) {
            const std::vector<size_t> ks =
                truth_check_rays(view.size(), ex_.truth_check.empty() ? "all" : ex_.truth_check);
            if (ks.empty()) return t;
            Hits other;
            if (ks.size() == view.size()) {
                other_->trace(view, other);
                t.agree = reference_agreement(other.uv, t.gt.uv, hf_.width, hf_.height);
            } else {
                other_->trace(sub_view(view, ks), other);
                std::vector<Vec2d> mine;
                mine.reserve(ks.size());
                for (size_t k : ks) mine.push_back(t.gt.uv[k]);
                t.agree = reference_agreement(other.uv, mine, hf_.width, hf_.height);
            }
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
        : ex_(s.ex),
          spec_(s.spec),
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
        // The check walk costs about twice a whole walk (the pyramid's own steps are a few
        // percent of that): by default it walks one ray in 16 (kCurvedTruthCheck).
        const std::vector<size_t> ks =
            timed ? truth_check_rays(cv.rays.size(),
                                     ex_.truth_check.empty() ? kCurvedTruthCheck : ex_.truth_check)
                  : std::vector<size_t>{};
        if (!ks.empty()) {
            std::vector<WorldRay> rays;
            rays.reserve(ks.size());
            for (size_t k : ks) rays.push_back(cv.rays[k]);
            CurvedHits fine;
            try {
                fine = check_.trace(rays, check_budget);
            } catch (const CurvedWalkTooLong& e) {  // the view's steps: both walks'
                throw CurvedWalkTooLong(e.what(), h.steps + e.steps, kMaxCurvedWalkSteps);
            }
            std::vector<Vec2d> a, b;
            for (size_t m = 0; m < ks.size(); ++m)
                if (t.cover->truth_hit[ks[m]] && fine.hit[m]) {
                    a.push_back(fine.uv[m]);
                    b.push_back(t.gt.uv[ks[m]]);
                }
            t.agree = reference_agreement(a, b, hf_.width, hf_.height);
        }
        return t;
    }

    const Experiment& ex_;
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

#include "harness/metrics/sweep_pairs.h"

namespace pxh {

SweepPairer::SweepPairer(std::vector<double> theta_deg, double sweep_dt_deg,
                         const std::vector<CameraSetting>& settings, const std::string& pair_key)
    : theta_(std::move(theta_deg)),
      dt_(sweep_dt_deg),
      steps_(distance_steps(settings, pair_key)),
      before_(settings.size(), size_t(-1)) {
    for (size_t c = 0; c < steps_.size(); ++c)
        if (steps_[c].pairs()) before_[steps_[c].next] = c;
}

std::optional<double> SweepPairer::theta_companion(double theta) const {
    if (!(dt_ > 0)) return std::nullopt;
    return theta + dt_ < 90 ? theta + dt_ : theta - dt_;
}

void SweepPairer::pair_companion(double theta, const ViewErrors& view, const ViewErrors& companion,
                                 std::vector<ResultRow>& rows) const {
    const bool up = theta + dt_ < 90;  // the companion above: the view is the lower one
    for (size_t i = 0; i < rows.size(); ++i)
        add_sweep(up ? view[i] : companion[i], up ? companion[i] : view[i], dt_, rows[i]);
}

void SweepPairer::pair_successor(size_t camera, const ViewErrors& view, const ViewErrors& far,
                                 std::vector<ResultRow>& rows) const {
    for (size_t i = 0; i < rows.size(); ++i)
        add_distance_sweep(view[i], far[i], steps_[camera].dd, rows[i]);
}

void SweepPairer::start_field() {
    waiting_.clear();
    previous_.reset();
}

void SweepPairer::start_sweep() { previous_.reset(); }

void SweepPairer::pair_earlier(size_t phi, size_t camera, size_t theta, const ViewErrors& errors,
                               std::vector<ResultRow>& run_rows) {
    // Consecutive views: the pair (theta_{k-1}, theta_k) goes on the rows of view k-1.
    if (!(dt_ > 0) && previous_ && theta > 0) {
        const double dt = theta_[theta] - theta_[previous_theta_];
        const Kept& p = *previous_;
        for (size_t i = 0; i < errors.size() && i < p.index.size(); ++i)
            if (dt > 0) add_sweep((*p.errors)[i], errors[i], dt, run_rows[p.index[i]]);
    }
    // The farther view of a pair whose nearer view waits for it.
    const size_t near = before_[camera];
    if (near == size_t(-1)) return;
    const auto it = waiting_.find({phi, near, theta});
    if (it == waiting_.end()) return;
    const Kept& w = it->second;
    for (size_t i = 0; i < errors.size() && i < w.index.size(); ++i)
        add_distance_sweep((*w.errors)[i], errors[i], steps_[near].dd, run_rows[w.index[i]]);
    waiting_.erase(it);
}

void SweepPairer::keep(size_t phi, size_t camera, size_t theta, ViewErrors errors,
                       std::vector<size_t> index, bool wait) {
    Kept k{std::make_shared<const ViewErrors>(std::move(errors)), std::move(index)};
    // The next theta of the sweep pairs with it only without companions, and if there is one.
    const bool theta_next = !(dt_ > 0) && theta + 1 < theta_.size();
    if (wait) waiting_[{phi, camera, theta}] = k;
    if (theta_next) {
        previous_ = std::move(k);
        previous_theta_ = theta;
    } else {
        previous_.reset();
    }
}

}  // namespace pxh

#include "harness/report/bands.h"

#include "harness/core/error.h"
#include "harness/core/params.h"

namespace pxh {

namespace {
const std::vector<double> kDefaultBandEdges = {0, 30, 60, 75, 85, 90};
}

Bands::Bands(std::vector<double> edges) : edges_(std::move(edges)) {
    if (edges_.empty()) edges_ = kDefaultBandEdges;
    bool ok = edges_.size() >= 2;
    for (size_t i = 0; ok && i < edges_.size(); ++i)
        ok = edges_[i] >= 0 && edges_[i] <= 90 && (i == 0 || edges_[i] > edges_[i - 1]);
    if (!ok) {
        std::string list;
        for (double e : edges_) {
            if (!list.empty()) list += ',';
            list += format_number(e);
        }
        throw InputError("--bands", "'" + list +
                                        "': band edges must be at least 2 ascending "
                                        "angles in [0, 90] degrees, e.g. 0,30,60,75,85,90");
    }
    thetas_.resize(size());
}

int Bands::of(double theta) const {
    for (size_t i = 0; i < size(); ++i)
        if (theta >= edges_[i] &&
            (theta < edges_[i + 1] || (i + 1 == size() && theta == edges_[i + 1])))
            return int(i);
    return -1;
}

std::string Bands::edges(size_t i) const {
    return format_number(edges_[i]) + " <= θ " + (i + 1 == size() ? "<= " : "< ") +
           format_number(edges_[i + 1]);
}

std::string Bands::note() const {
    std::string list;
    for (size_t i = 0; i < size(); ++i)
        if (single_view(i))
            list += (list.empty() ? "" : ", ") + edges(i) +
                    " holds only θ = " + format_number(*thetas_[i].begin());
    return list.empty() ? ""
                        : "† A single view in the band (" + list +
                              "): its figures are "
                              "that one angle's, not the whole band's.";
}

std::string Bands::range() const {
    return format_number(edges_.front()) + " to " + format_number(edges_.back()) + " degrees";
}

}  // namespace pxh

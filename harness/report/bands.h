// Angle bands of the report: [e_i, e_i+1) between ascending edges, the last one closed.
#pragma once
#include <set>
#include <string>
#include <vector>

namespace pxh {

class Bands {
  public:
    // Empty edges: 0,30,60,75,85,90. Bad edges are an InputError naming --bands.
    explicit Bands(std::vector<double> edges);
    size_t size() const { return edges_.size() - 1; }
    // The band holding theta, or -1 outside every band.
    int of(double theta) const;
    void add_view(int band, double theta) { thetas_[size_t(band)].insert(theta); }
    bool present(size_t i) const { return !thetas_[i].empty(); }
    bool single_view(size_t i) const { return thetas_[i].size() == 1; }
    // The band's exact edges: "0 <= θ < 30", the last one "85 <= θ <= 90".
    std::string edges(size_t i) const;
    // Its label in the tables: the edges, marked † when the band holds a single view.
    std::string label(size_t i) const { return edges(i) + (single_view(i) ? " †" : ""); }
    double lo(size_t i) const { return edges_[i]; }
    double hi(size_t i) const { return edges_[i + 1]; }
    size_t views(size_t i) const { return thetas_[i].size(); }
    // The footnote for the bands marked †, "" when none is.
    std::string note() const;
    std::string range() const;

  private:
    std::vector<double> edges_;
    std::vector<std::set<double>> thetas_;  // the distinct θ of the reported rows per band
};

}  // namespace pxh

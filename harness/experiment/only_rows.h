// pxh compare --only: pxh run --only's spec (harness/experiment/only.cpp) as a test of result
// rows.
#pragma once
#include <functional>
#include <string>
#include <vector>

namespace pxh {

class ResultRow;

// What an empty cell of a text axis stands for: the default base (the plane) for base, "base"
// for lod and depth, "orthographic" for camera (results written before those columns said so);
// "" for the others. pxh check's filters and pxh compare --only match against it.
std::string empty_axis_means(const std::string& axis);

// The same spec as a test of result rows (pxh compare --only): a row matches when each key's
// cell does (an empty cell as empty_axis_means says: base plane, lod and depth base, camera
// orthographic). Any axis may be given; an empty spec matches every row. Bad specs are
// apply_only's InputErrors.
class OnlyRows {
  public:
    explicit OnlyRows(const std::string& spec);
    bool matches(const ResultRow& row) const;
    bool empty() const { return tests_.empty(); }

  private:
    std::vector<std::function<bool(const ResultRow&)>> tests_;
};

}  // namespace pxh

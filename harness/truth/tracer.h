// The truth stage's tracers: first hits of a view's eye rays with the bilinear surface
// z = s (h - b) (docs/conventions.md section 4), built once per height field (and s, b) and
// shared by its views.
//
// Adding a tracer: one file harness/truth/NAME_tracer.cpp (or .h/.cpp) defining a Tracer
// subclass and a factory, plus one line in tracer_registry() (harness/truth/registry.cpp).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "harness/core/vec.h"
#include "harness/scene/heightfield.h"
#include "harness/scene/view.h"

namespace pxh {

struct TruthHit {
    Vec2d uv;       // unwrapped texture coordinate of the visible point
    double z = 0;   // its height z = s (h - b)
    int cells = 0;  // cells handed to the exact cell solver (cost)
};

// A view's first hits, per sample, in the view's order.
struct Hits {
    std::vector<Vec2d> uv;   // unwrapped texture coordinates
    std::vector<double> z;   // heights; empty where the tracer does not report them
    std::vector<int> cells;  // cells solved; empty where the tracer does not report them

    void resize_all(size_t n) {
        uv.resize(n);
        z.resize(n);
        cells.resize(n);
    }
    void set(size_t k, const TruthHit& h) {
        uv[k] = h.uv;
        z[k] = h.z;
        cells[k] = h.cells;
    }
};

class Tracer {
  public:
    virtual ~Tracer() = default;
    virtual std::string name() const = 0;
    virtual double scale() const = 0;
    // The first hit of every ray of the view (in parallel; the result does not depend on the
    // thread count). Throws std::invalid_argument (view_travel_problem's reason) for a
    // malformed view or a ray beyond the travel limit or not above the surface, before any
    // work. `out` is resized and reused.
    virtual void trace(const View& view, Hits& out) const = 0;
    // The optional true-shadow query: does the ray from the surface point (uv, z) toward L
    // (unit) pass strictly below the surface before leaving the slab? Tracers without one
    // answer false to has_shadow_query and throw std::logic_error from occluded.
    virtual bool has_shadow_query() const { return false; }
    virtual bool occluded(Vec2d uv, double z, Vec3d L) const;
};

// What a run asks of a tracer: every view is traced by both references, the exact tracer (the
// truth's heights, true shadows and cost) and a second, independent one its hits are checked
// against (gt_agree_*); the experiment's ground_truth names which of the two gives the uv.
enum class TracerRole { exact_reference, cross_check };

// The registry (harness/truth/registry.cpp): one line per tracer.
struct TracerEntry {
    const char* name;
    std::unique_ptr<Tracer> (*make)(const HeightField& hf, double scale, double bias);
    TracerRole role;
};
const std::vector<TracerEntry>& tracer_registry();
std::vector<std::string> tracer_names();  // in registry order
// Throws InputError(where, "unknown tracer 'x' (known: exact, embree)") for an unknown name.
void check_tracer_name(const std::string& name, const std::string& where);
// Builds it for the field and s, b (throws std::invalid_argument for a scale that is not a
// finite positive number).
std::unique_ptr<Tracer> make_tracer(const std::string& name, const HeightField& hf, double scale,
                                    double bias);
// The tracer of this role (the registry's first of it), built for the field and s, b.
std::unique_ptr<Tracer> make_tracer(TracerRole role, const HeightField& hf, double scale,
                                    double bias);

}  // namespace pxh

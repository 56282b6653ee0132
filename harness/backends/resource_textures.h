// A method's resources (methods/resource.h) as GL textures: one texture object per resource
// slot, uploaded on every run (as the height field: a cache keyed on addresses could see a freed
// image's address reused), every level, with the resource's format, filter and wrap, bound to
// consecutive texture units and named by the resource's sampler2D uniform.
#pragma once
#include <vector>

#include "methods/resource.h"

namespace pxh {

class ResourceTextures {
  public:
    // Deletes the textures (the backend's context must be current).
    void release();
    // Uploads res.items[k] to texture unit first_unit + k and sets the program's sampler
    // uniform of that name to the unit (the program must be in use). Throws std::runtime_error
    // naming the resource when GL refuses the upload.
    void bind(unsigned program, const MethodResources& res, int first_unit);

  private:
    std::vector<unsigned> textures_;
};

}  // namespace pxh

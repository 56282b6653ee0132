// Height field sources: procedural generators (deterministic, seeded, tileable) and image files.
#pragma once
#include <string>
#include <vector>

#include "harness/core/params.h"
#include "harness/scene/heightfield.h"

namespace pxh {

struct GeneratorInfo {
    std::string name;
    std::string summary;
    std::vector<ParamSpec> params;
    // Fills a W x H field (texel centres) from resolved parameters; values in [0,1].
    void (*generate)(HeightField& out, const ParamValues& p);
    // Optional: "" when the parameters can be generated within bounded memory and time, else
    // the reason (checked when the experiment is read).
    std::string (*problem)(const ParamValues& p) = nullptr;
};

const std::vector<GeneratorInfo>& all_generators();
const GeneratorInfo* find_generator(const std::string& name);
HeightField generate_heightfield(const GeneratorInfo& g, int width, int height,
                                 const ParamValues& p);

// Reads a height map (docs/conventions.md section 1) from a regular file: PNG, TIFF, OpenEXR or
// JPEG through OpenImageIO, PGM/PPM/PBM/PFM read directly; the size limits are in
// harness/scene/heightfield.h. First stored row is j = 0; integers map 0..max (maxval for netpbm)
// to [0,1]; float data is taken as is and must lie in [0,1]. `channel` picks the height channel
// (default 0: gray, or red as stored, never multiplied by alpha; a palette image's red, not its
// index). Anything refused is an InputError naming the file, on one line.
HeightField load_heightfield_file(const std::string& path, int channel = 0);

// Writes a single-channel float or 16-bit image (by extension), first row j = 0.
void save_heightfield_file(const HeightField& hf, const std::string& path);

}  // namespace pxh

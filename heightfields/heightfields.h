// Height field sources: procedural generators (deterministic, seeded, tileable) and image files.
#pragma once
#include <string>
#include <vector>

#include "harness/heightfield.h"
#include "harness/params.h"

namespace pxh {

struct GeneratorInfo {
    std::string name;
    std::string summary;
    std::vector<ParamSpec> params;
    // Fills a W x H field (texel centres) from resolved parameters; values in [0,1].
    void (*generate)(HeightField& out, const ParamValues& p);
};

const std::vector<GeneratorInfo>& all_generators();
const GeneratorInfo* find_generator(const std::string& name);
HeightField generate_heightfield(const GeneratorInfo& g, int width, int height,
                                 const ParamValues& p);

// Largest accepted image: refused from the header, before any pixel is allocated.
constexpr long long kMaxImageSide = 16384;
constexpr long long kMaxImageTexels = 64ll * 1024 * 1024;

// Reads a height map through OpenImageIO (spec section 1): first stored row is j = 0;
// 8/16-bit integers map 0..max to [0,1]; float data is taken as is and must lie in [0,1].
// `channel` picks the height channel (default 0, the first: gray or red).
HeightField load_heightfield_file(const std::string& path, int channel = 0);

// Writes a single-channel float or 16-bit image (by extension), first row j = 0.
void save_heightfield_file(const HeightField& hf, const std::string& path);

}  // namespace pxh

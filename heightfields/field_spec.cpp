#include "heightfields/field_spec.h"

#include <exception>

#include "harness/core/error.h"
#include "heightfields/heightfields.h"
#include "heightfields/scanned.h"

namespace pxh {

std::string heightfield_file_problem(const std::string& file, std::string reason) {
    if (reason.rfind(file + ": ", 0) == 0) reason = reason.substr(file.size() + 2);
    return "heightfield file '" + file + "' (paths are relative to the experiment file): " + reason;
}

HeightField make_heightfield(const HeightfieldSpec& spec) {
    HeightField hf;
    if (!spec.generator.empty()) {
        hf = generate_heightfield(*find_generator(spec.generator), spec.width, spec.height,
                                  spec.gen_params);
        hf.validate(spec.where);
    } else if (!spec.scan.empty()) {
        hf = load_scan(spec.scan, spec.where);
    } else {
        try {
            hf = load_heightfield_file(spec.file, spec.channel);
        } catch (const std::exception& e) {
            throw InputError(spec.where, heightfield_file_problem(spec.file, e.what()));
        }
    }
    hf.name = spec.name;
    return hf;
}

FieldSize field_size(const HeightfieldSpec& spec) {
    if (!spec.generator.empty()) return {size_t(spec.width), size_t(spec.height), false};
    if (!spec.scan.empty()) {
        for (const auto& sc : list_scans())
            if (sc.name == spec.scan)  // as tiled when loaded (mirrored: 2W x 2H)
                return {size_t(sc.tile_width), size_t(sc.tile_height), true};
    } else {
        // Through pxh's hardened loader (never OpenImageIO on the raw file: a hostile header
        // can make a library allocate gigabytes); bounded by the image limits, freed at once.
        try {
            const HeightField hf = load_heightfield_file(spec.file, spec.channel);
            return {size_t(hf.width), size_t(hf.height), false};
        } catch (const std::exception&) {
        }
    }
    // Unknown (the run will refuse it): the largest field the loader accepts.
    return {size_t(kMaxImageSide), size_t(kMaxImageTexels / kMaxImageSide), false};
}

}  // namespace pxh

// A height field as an experiment names it (generator, image file or imported scan, with its
// scale and bias), and building it: the height fields' side of the experiment's
// [[heightfields]] entries (harness/experiment reads them).
#pragma once
#include <cmath>
#include <cstddef>
#include <string>

#include "harness/core/params.h"
#include "harness/scene/heightfield.h"

namespace pxh {

struct HeightfieldSpec {
    std::string name;          // as reported in results: unique within a run (one name, one field)
    std::string generator;     // either a generator ...
    std::string file;          // ... or an image file (resolved path)
    std::string file_written;  // the file's path as written in the experiment
    std::string scan;          // ... or an imported scan (heightfields/scanned/NAME)
    int width = 256, height = 256;
    int channel = 0;
    ParamValues gen_params;
    double scale = 0.05, bias = 1.0;
    // The base surface it displaces (harness/scene/base_surface.h) and its radius (tiles; NaN
    // on the plane).
    std::string base = "plane";
    double radius = NAN;
    std::string where;  // file:line of the entry, for errors
    // What identifies the field (results column heightfield_id), one line:
    //   generator:NAME WxH [canonical resolved parameters]
    //   file:PATH channel:C sha256:HEX   (PATH as written, relative to the experiment file)
    //   scan:NAME sha256:HEX             (of the committed heightfields/scanned/NAME.png)
    std::string identity;
    std::string source_path, source_sha256;  // files and scans: the image read and its sha256
};

// "heightfield file 'PATH' (paths are relative to the experiment file): REASON", REASON being
// the loader's message without its leading "PATH: ".
std::string heightfield_file_problem(const std::string& file, std::string reason);

// Materialises a height field (generates or loads); throws InputError. Errors from an image
// file read "EXPERIMENT:LINE: heightfield file 'PATH' (paths are relative to the experiment
// file): REASON".
HeightField make_heightfield(const HeightfieldSpec& spec);

// Width and height of a field before it is built (files: from the header; the loader's limit
// when unreadable).
struct FieldSize {
    size_t width, height;
    bool mask;  // a filled-hole mask (scans)
};
FieldSize field_size(const HeightfieldSpec& spec);

}  // namespace pxh

// `pxh list methods|heightfields`: what an experiment file can name.
#include <cmath>
#include <iostream>
#include <memory>

#include "harness/commands/commands.h"
#include "harness/core/params.h"
#include "heightfields/heightfields.h"
#include "heightfields/scanned.h"
#include "methods/method.h"

namespace pxh {
namespace {

void list_methods() {
    for (const auto& m : all_methods()) {
        std::cout << m.name << "  -- " << m.summary << "\n    source: " << m.citation << "\n";
        if (!m.engine_version.empty()) std::cout << "    follows: " << m.engine_version << "\n";
        if (m.exact_on_flat) std::cout << "    exact on flat fields\n";
        if (!std::isnan(m.required_bias))
            std::cout << "    needs bias = " << format_number(m.required_bias) << " ("
                      << m.bias_reason << ")\n";
        for (const auto& p : m.params) std::cout << "    " << describe_param(p) << "\n";
    }
}

std::string tiling_words(const std::string& rule) {
    if (rule == "mirror") return "mirrored";
    if (rule == "pole") return "continued over the poles";
    return rule;
}

void list_heightfields() {
    for (const auto& g : all_generators()) {
        std::cout << g.name << "  -- " << g.summary << "\n";
        for (const auto& p : g.params) std::cout << "    " << describe_param(p) << "\n";
    }
    for (const auto& s : list_scans())
        std::cout << "scan:" << s.name << "  -- " << s.description << "\n    measured, " << s.width
                  << " x " << s.height << ", tiles as " << s.tile_width << " x " << s.tile_height
                  << " (x " << tiling_words(s.tiling_x) << ", y " << tiling_words(s.tiling_y) << ")"
                  << "; use scan = \"" << s.name << "\" (provenance: heightfields/scanned/"
                  << s.name << ".json)\n";
    std::cout << "(any image file: file = \"path\" in a [[heightfields]] entry; PNG, TIFF, EXR, "
                 "PFM, ... through OpenImageIO)\n";
}

}  // namespace

Command add_list_command(CLI::App& app) {
    auto* list = app.add_subcommand(
        "list", "list registered methods, or height fields (generators and imported scans)");
    auto what = std::make_shared<std::string>();
    list->add_option("what", *what, "methods | heightfields")
        ->required()
        ->check(CLI::IsMember({"methods", "heightfields"}));
    return {list, [what] {
                if (*what == "methods") list_methods();
                else list_heightfields();
                return 0;
            }};
}

}  // namespace pxh

// Fuzz target: experiment files (TOML) through pxh::parse_experiment, as `pxh run` reads them,
// then the procedural generators for the small generated fields the file asks for (their
// parameters come from the file too). Image files and scans named by the file are not loaded
// (the image target covers the loader).
#include <exception>
#include <string>

#include "fuzz/fuzz_target.h"
#include "harness/experiment/experiment.h"

PXH_FUZZ_TARGET(experiment) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        const pxh::Experiment ex = pxh::parse_experiment(text, "/fuzz/experiment.toml");
        // Generating is cheap only for small fields: bound the work per input (at most 8
        // fields of at most 64 x 64 texels).
        int generated = 0;
        for (const auto& hs : ex.heightfields)
            if (!hs.generator.empty() && (long long)hs.width * hs.height <= 64 * 64 &&
                generated++ < 8)
                (void)pxh::make_heightfield(hs);
    } catch (const std::exception&) {
        // Refused input (InputError) is the expected outcome for most inputs.
    }
    return 0;
}

// pxh's WGSL plug-ins (docs/guide/plugin-shaders.md, "HLSL and WGSL"): the WGSL file argv[2]
// translated by naga (npm naga-wasm, pinned in package.json) to a GLSL 4.50 fragment shader
// written to argv[3], entry point `main`. On a parse or validation error: naga's report on
// stdout, exit 1.
import { readFileSync, writeFileSync } from "node:fs";
import { translate, NagaError, nagaVersion } from "naga-wasm";

if (process.argv[2] === "--version") {
    console.log(`naga ${nagaVersion}`);
    process.exit(0);
}
const source = readFileSync(process.argv[2], "utf8");
try {
    const glsl = translate({
        from: "wgsl",
        to: "glsl",
        source,
        options: { version: "450", stage: "fragment", entryPoint: "main" },
    });
    writeFileSync(process.argv[3], glsl);
} catch (error) {
    if (error instanceof NagaError) {
        console.log(error.formatted || error.message);
        process.exit(1);
    }
    throw error;
}

// A web engine's parallax chunk with a string mode and chunk parameters ({NAME}, filled in by the
// engine before compiling), as a WebGL engine ships it: texture2DBias / texture2DLod on the
// height map, the view vector in a tangent frame whose y runs along -v. Written for pxh in the
// style of PlayCanvas's StandardMaterial chunk parallaxPS (npm playcanvas@2.23.3,
// build/playcanvas.mjs: getParallax, its OFFSET and OCCLUSION modes; read for the facts, not
// copied). pxh runs this text unchanged; modes.toml says how.
uniform float material_heightMapFactor;
uniform float material_heightMapBase;
#if PARALLAX_MODE == OCCLUSION
uniform float material_parallaxSamples;
const float kMaxSlope = 5.0;       // the march is at most 5 s long
const float kTexelsPerStep = 2.0;  // one step per 2 texels of the level read
const float kFadeFrom = 1.0;       // the offset fades out below 3 texels of march
const float kFadeTo = 3.0;
const int kRefine = 5;             // bisection taps after the crossing
#endif

void getParallax() {
    float scale = material_heightMapFactor;
    vec3 viewDirT = normalize(dViewDirW * dTBN);
    vec2 viewUv = vec2(viewDirT.x, -viewDirT.y);
#if PARALLAX_MODE == OCCLUSION
    vec2 march = -scale * viewUv / max(viewDirT.z, 0.0001);
    float marchLength = length(march);
    float longest = scale * kMaxSlope;
    vec2 span = marchLength > longest ? march * (longest / marchLength) : march;
    float planeDepth = 1.0 - material_heightMapBase;
    vec2 entry = {HEIGHT_UV} - span * planeDepth;
    vec2 texels = vec2(textureSize({HEIGHT_MAP}, 0));
    vec2 dx = dFdx({HEIGHT_UV} * texels);
    vec2 dy = dFdy({HEIGHT_UV} * texels);
    float lod = max(0.0, 0.5 * log2(max(dot(dx, dx), dot(dy, dy))));
    float marchTexels = length(span * texels) / exp2(lod);
    float fade = clamp((marchTexels - kFadeFrom) / (kFadeTo - kFadeFrom), 0.0, 1.0);
    dUvOffset = vec2(0.0);
    if (fade > 0.0) {
        float steps = clamp(marchTexels / kTexelsPerStep, 1.0, material_parallaxSamples);
        float stepSize = 1.0 / steps;
        float ray = 0.0;
        float field = 1.0 - texture2DLod({HEIGHT_MAP}, entry, lod).{HEIGHT_CHANNEL};
        float rayBefore = ray;
        for (float i = 0.0; i < steps; i += 1.0) {
            if (ray >= field) break;
            rayBefore = ray;
            ray += stepSize;
            field = 1.0 - texture2DLod({HEIGHT_MAP}, entry + span * ray, lod).{HEIGHT_CHANNEL};
        }
        float hit = ray;
        if (ray >= field) {
            float half_step = (ray - rayBefore) * 0.5;
            hit = ray - half_step;
            for (int k = 0; k < kRefine; k++) {
                half_step *= 0.5;
                float there = 1.0 - texture2DLod({HEIGHT_MAP}, entry + span * hit, lod).{HEIGHT_CHANNEL};
                hit += hit >= there ? -half_step : half_step;
            }
        }
        dUvOffset = span * ((clamp(hit, 0.0, 1.0) - planeDepth) * fade);
    }
#else
    float h = texture2DBias({HEIGHT_MAP}, {HEIGHT_UV}, 0.0).{HEIGHT_CHANNEL};
    dUvOffset = (h - material_heightMapBase) * scale * viewUv;
#endif
}

// Engine presets for Unity (built-in/URP ParallaxOffset, HDRP PerPixelDisplacement),
// jMonkeyEngine (Parallax.glsllib), OGRE (RTSS normal_map parallax / parallax_occlusion) and the
// DirectX SDK ParallaxOcclusionMapping sample: named settings of the parametric marcher
// (methods/march/march.h). The engine's height scale is the experiment's scale s (conversions in
// README); each engine fixes the reference plane, so each preset requires its bias. LOD fades
// (HDRP's _PPDLodThreshold, the DirectX sample's g_nLODThreshold) are left off: the orthographic
// scene defines no screen footprint. Literal transcriptions of the engines' loops, and the tests
// that compare them with these presets: tests/engines/literal_unity_jme_ogre_dx.h,
// tests/methods/engines_unity_jme_ogre_dx_test.cpp.
#include "methods/march/march.h"

namespace pxh {
namespace {

// ParallaxOffset: h = h _Parallax - _Parallax / 2; v = normalize(viewDir); v.z += 0.42;
// offset = h v.xy / v.z.  In pxh terms uv = P + s (h - 0.5) V.xy / (V.z + 0.42).
struct UnityParallaxOffset {
    static MethodInfo info() {
        MethodInfo m{"unity_parallax_offset",
                     "Unity built-in/URP ParallaxOffset: TwoTailsGames/Unity-Built-in-Shaders "
                     "CGIncludes/UnityStandardUtils.cginc ParallaxOffset1Step, UnityCG.cginc "
                     "ParallaxOffset, UnityStandardInput.cginc Parallax @ 6a63f93bc1f2 (Unity "
                     "2019.4.1); URP Unity-Technologies/Graphics universal/Shaders/LitInput.hlsl "
                     "@ 3b0efc39f87e; s = _Parallax (0.02 built-in, 0.005 URP)",
                     "one fetch: uv = P + s (h - 0.5) V.xy / (V.z + 0.42) (softened offset)",
                     {},
                     false,
                     360};
        m.required_bias = 0.5;
        m.bias_reason = "ParallaxOffset centres heights on 0.5 (h _Parallax - _Parallax / 2)";
        return m;
    }
    static MarchConfig config(const ParamValues&, const std::string&) {
        MarchConfig c;
        c.search = MarchConfig::Offset;
        c.offset_form = MarchConfig::OffSoft;
        c.offset_soften = 0.42;
        return c;
    }
};
PXH_REGISTER_PRESET(UnityParallaxOffset);

// ParallaxOcclusionMapping (secant branch): numSteps = int(lerp(_PPDMinSamples, _PPDMaxSamples,
// saturate(FastACosPos(normalize(s V.xy, V.z).z) 2/pi))); layer 0 fetched, layers 1.. tested
// (height > rayHeight), one layer fetched past the bottom; regula falsi, at most 3 probes,
// tolerance 0.01, the last probe's offset returned.
struct HdrpPom {
    static MethodInfo info() {
        MethodInfo m{
            "hdrp_pom",
            "Unity HDRP Lit pixel displacement: Unity-Technologies/Graphics "
            "render-pipelines.core/ShaderLibrary/PerPixelDisplacement.hlsl @ c8df1d81db96 "
            "(ParallaxOcclusionMapping), high-definition/Runtime/Material/Lit/"
            "LitDataDisplacement.hlsl @ d679af29c7a2 (ApplyPerPixelDisplacement), Lit.shader "
            "@ ba62a5986427 (defaults); s = _HeightPoMAmplitude / 100 (2 cm: 0.02) for a 1 m "
            "primitive at tiling 1",
            "POM with an angle-of-the-scaled-ray layer count, regula falsi (3 probes, "
            "tolerance 0.01) returning the last probe; LOD fade off",
            {ParamSpec::integer("_PPDMinSamples", 5, 1, 64, "layers head-on (Lit.shader: 5)"),
             ParamSpec::integer("_PPDMaxSamples", 15, 1, 64,
                                "layers when the s-scaled ray is grazing (Lit.shader: 15)")},
            true,
            361};
        m.required_bias = 1.0;
        m.bias_reason = "HDRP pixel displacement goes inward only (height 1 at the polygon)";
        return m;
    }
    static MarchConfig config(const ParamValues& p, const std::string&) {
        MarchConfig c;
        c.count = MarchConfig::AngleScaled;
        c.layers_min = p.get_int("_PPDMinSamples");
        c.layers_max = p.get_int("_PPDMaxSamples");
        c.first = MarchConfig::FirstSample;  // prevHeight at offset 0 (never a hit: h <= 1)
        c.compare = MarchConfig::Lt;         // currHeight > rayHeight
        c.extra_layers = 1;                  // layer numSteps + 1 is fetched, below the slab
        c.on_miss = MarchConfig::MissRefine;
        c.refine = MarchConfig::Secant;
        c.iterations = 3;
        c.tolerance = 0.01;
        return c;
    }
};
PXH_REGISTER_PRESET(HdrpPom);

// classicParallaxOffset: h = (h s - 0.6 s) normView.z; uv = P + h normView.xy.
struct JmeParallax {
    static MethodInfo info() {
        MethodInfo m{"jme_parallax",
                     "jMonkeyEngine classic parallax: jMonkeyEngine/jmonkeyengine "
                     "jme3-core/src/main/resources/Common/ShaderLib/Parallax.glsllib @ "
                     "7277b5d8013f (classicParallaxOffset), Lighting.j3md @ 68c082c13ded; "
                     "s = ParallaxHeight (0.05)",
                     "one fetch: uv = P + s (h - 0.6) V.z V.xy (offset times V.z, largest at 45 "
                     "degrees)",
                     {},
                     false,
                     362};
        m.required_bias = 0.6;
        m.bias_reason = "classicParallaxOffset adds heightBias = -0.6 ParallaxHeight";
        return m;
    }
    static MarchConfig config(const ParamValues&, const std::string&) {
        MarchConfig c;
        c.search = MarchConfig::Offset;
        c.offset_form = MarchConfig::OffSinCos;
        return c;
    }
};
PXH_REGISTER_PRESET(JmeParallax);

// steepParallaxOffset: n = mix(6, 1000 s, 1 - V.z) (real), layers 1 .. ceil(n), stop after the
// first height > bound; the previous height of layer 1 is 0 (fPrevHeight takes the initial
// fCurrHeight = 0.0); line intersection of the last two (bound, height) pairs, no guard.
struct JmeSteep {
    static MethodInfo info() {
        MethodInfo m{"jme_steep",
                     "jMonkeyEngine steep parallax: jMonkeyEngine/jmonkeyengine "
                     "jme3-core/src/main/resources/Common/ShaderLib/Parallax.glsllib @ "
                     "7277b5d8013f (steepParallaxOffset, SteepParallax true); s = 0.3 "
                     "ParallaxHeight (0.015)",
                     "POM with n = mix(6, 1000 s, 1 - V.z) layers and height 0 as the previous "
                     "sample of layer 1 (P is never sampled)",
                     {},
                     false,
                     363};
        m.required_bias = 1.0;
        m.bias_reason = "steepParallaxOffset starts at bound 1.0 at the polygon";
        return m;
    }
    static MarchConfig config(const ParamValues&, const std::string&) {
        MarchConfig c;
        c.count = MarchConfig::MixScaled;
        c.layers_min = 6;
        c.layers_max = 1000;
        c.first = MarchConfig::FirstBottom;
        c.compare = MarchConfig::Lt;
        c.on_miss = MarchConfig::MissRefine;
        c.refine = MarchConfig::Lerp;
        c.clamp_weight = false;
        return c;
    }
};
PXH_REGISTER_PRESET(JmeSteep);

// SGX_Generate_Parallax_Texcoord without POM_LAYER_COUNT: uv = P - eyeVec.xy / eyeVec.z
// (1 - a) heightScale: pxh parallax with b = 1.
struct OgreParallax {
    static MethodInfo info() {
        MethodInfo m{"ogre_parallax",
                     "OGRE RTSS normal_map parallax: OGRECave/ogre "
                     "Media/RTShaderLib/SGXLib_NormalMap.glsl (SGX_Generate_Parallax_Texcoord), "
                     "Components/RTShaderSystem/src/OgreShaderExNormalMapLighting.cpp @ "
                     "3e955a168617; s = height_scale (0.04)",
                     "one fetch: uv = P + s (h - 1) V.xy / V.z (depth = 1 - normal map alpha)",
                     {},
                     true,
                     364};
        m.required_bias = 1.0;
        m.bias_reason = "OGRE reads depth = 1 - alpha below the polygon";
        return m;
    }
    static MarchConfig config(const ParamValues&, const std::string&) {
        MarchConfig c;
        c.search = MarchConfig::Offset;
        c.offset_form = MarchConfig::OffTan;
        return c;
    }
};
PXH_REGISTER_PRESET(OgreParallax);

// SGX_Generate_Parallax_Texcoord with POM_LAYER_COUNT=32: step eyeVec.xy s / 32 (no division by
// eyeVec.z); a dead fetch at P; the sample at P - k delta compared with layer depth (k - 1)/32;
// the interpolation re-fetches the previous layer; after 32 layers without a break it
// interpolates with the counter's final (unlagged) depths; no guard on 0/0.
struct OgrePom {
    static MethodInfo info() {
        MethodInfo m{"ogre_pom",
                     "OGRE RTSS normal_map parallax_occlusion: OGRECave/ogre "
                     "Media/RTShaderLib/SGXLib_NormalMap.glsl (SGX_Generate_Parallax_Texcoord, "
                     "POM_LAYER_COUNT), OgreShaderExNormalMapLighting.cpp @ 3e955a168617; "
                     "s = height_scale (0.04)",
                     "POM with 32 layers, a sin(theta) step and a one-step lag in the "
                     "comparison",
                     {},
                     false,
                     365};
        m.required_bias = 1.0;
        m.bias_reason = "OGRE reads depth = 1 - alpha below the polygon";
        return m;
    }
    static MarchConfig config(const ParamValues&, const std::string&) {
        MarchConfig c;
        c.count = MarchConfig::Fixed;
        c.layers = 32;  // POM_LAYER_COUNT
        c.step = MarchConfig::StepSin;
        c.first = MarchConfig::FirstSample;  // the dead fetch at P (never a hit with the lag)
        c.lag = true;
        c.compare = MarchConfig::Lt;  // currentLayerDepth > currentDepthMapValue
        c.on_miss = MarchConfig::MissRefine;
        c.refine = MarchConfig::Lerp;
        c.refetch = true;
        c.clamp_weight = false;
        return c;
    }
};
PXH_REGISTER_PRESET(OgrePom);

// RenderScenePS: nNumSteps = (int)lerp(g_nMaxSamples, g_nMinSamples, V.z); layers 1 .. n,
// fPrevHeight = 1.0 before layer 1; stop at the first height > bound; line intersection, and
// fParallaxAmount = 0 (the bottom point) when no layer was crossed.
struct DxsdkPom {
    static MethodInfo info() {
        MethodInfo m{
            "dxsdk_pom",
            "DirectX SDK ParallaxOcclusionMapping sample (Tatarchuk 2006): "
            "walbourn/directx-sdk-legacy-samples Direct3D/ParallaxOcclusionMapping/"
            "ParallaxOcclusionMapping.fx (RenderSceneVS, RenderScenePS) and .cpp @ f35ea7637d51; "
            "s = g_fHeightMapScale (0.02, Stones)",
            "POM with n = int(lerp(50, 8, V.z)) layers and height 1 as the previous sample of "
            "layer 1 (P is never sampled); LOD fade off",
            {ParamSpec::integer("g_nMinSamples", 8, 1, 130, "layers head-on (sample: 8)"),
             ParamSpec::integer("g_nMaxSamples", 50, 1, 130, "layers at grazing (Stones: 50)")},
            false,
            366};
        m.required_bias = 1.0;
        m.bias_reason = "the sample's bound 1.0 is the polygon, heights go inward";
        return m;
    }
    static MarchConfig config(const ParamValues& p, const std::string&) {
        MarchConfig c;
        c.count = MarchConfig::MixTrunc;
        c.layers_min = p.get_int("g_nMinSamples");
        c.layers_max = p.get_int("g_nMaxSamples");
        c.first = MarchConfig::FirstTop;
        c.compare = MarchConfig::Lt;
        c.on_miss = MarchConfig::MissLast;
        c.refine = MarchConfig::Lerp;
        c.clamp_weight = false;
        return c;
    }
};
PXH_REGISTER_PRESET(DxsdkPom);

}  // namespace
}  // namespace pxh

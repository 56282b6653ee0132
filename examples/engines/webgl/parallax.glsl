// A web engine's parallax chunk, as a WebGL engine ships it: GLSL ES 1.0 style (texture2D),
// a depth map (bumpMap.r = 1 - h), engine uniform names, the mode chosen by #define. Written
// for pxh in the style of three.js's ParallaxShader (mrdoob/three.js
// examples/jsm/shaders/ParallaxShader.js @ 05578ec7204d317789959d28ce057ff8c1711d8e, npm
// three@0.131.3: its parallaxMap(V) and USE_*_PARALLAX modes; read for the facts, not copied).
// pxh runs this text unchanged; examples/engines/webgl/experiment.toml says how.
uniform sampler2D bumpMap;
uniform float parallaxScale;
uniform float parallaxMinLayers;
uniform float parallaxMaxLayers;

vec2 parallaxMap(in vec3 V) {
#ifdef USE_BASIC_PARALLAX
    float initialHeight = texture2D(bumpMap, vUv).r;
    // No division by V.z: the offset is limited (Welsh 2004).
    vec2 texCoordOffset = V.xy * parallaxScale * initialHeight;
    return vUv - texCoordOffset;
#else
    float numLayers = mix(parallaxMaxLayers, parallaxMinLayers, abs(dot(vec3(0.0, 0.0, 1.0), V)));
    float layerHeight = 1.0 / numLayers;
    float currentLayerHeight = 0.0;
    vec2 dtex = V.xy * parallaxScale / V.z / numLayers;
    vec2 currentTextureCoords = vUv;
    float heightFromTexture = texture2D(bumpMap, currentTextureCoords).r;
    // A WebGL 1 loop needs a constant bound.
    for (int i = 0; i < 30; i += 1) {
        if (heightFromTexture <= currentLayerHeight) break;
        currentLayerHeight += layerHeight;
        currentTextureCoords -= dtex;
        heightFromTexture = texture2D(bumpMap, currentTextureCoords).r;
    }
#ifdef USE_STEEP_PARALLAX
    return currentTextureCoords;
#elif defined(USE_RELIEF_PARALLAX)
    vec2 deltaTexCoord = dtex / 2.0;
    float deltaHeight = layerHeight / 2.0;
    currentTextureCoords += deltaTexCoord;
    currentLayerHeight -= deltaHeight;
    const int numSearches = 5;
    for (int i = 0; i < numSearches; i += 1) {
        deltaTexCoord /= 2.0;
        deltaHeight /= 2.0;
        heightFromTexture = texture2D(bumpMap, currentTextureCoords).r;
        if (heightFromTexture > currentLayerHeight) {  // below the surface
            currentTextureCoords -= deltaTexCoord;
            currentLayerHeight += deltaHeight;
        } else {
            currentTextureCoords += deltaTexCoord;
            currentLayerHeight -= deltaHeight;
        }
    }
    return currentTextureCoords;
#else  // occlusion: interpolate between the last two layers
    vec2 prevTCoords = currentTextureCoords + dtex;
    float nextH = heightFromTexture - currentLayerHeight;
    float prevH = texture2D(bumpMap, prevTCoords).r - currentLayerHeight + layerHeight;
    float weight = nextH / (nextH - prevH);
    return prevTCoords * weight + currentTextureCoords * (1.0 - weight);
#endif
#endif
}

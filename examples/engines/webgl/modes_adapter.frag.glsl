// pxh's side of the chunk: the engine's globals it reads and writes, set from pxh's sample.
vec3 dViewDirW;
mat3 dTBN;
vec2 dUvOffset;
vec2 vUv0;

#include <parallaxPS>

vec2 pxh_method(vec2 P) {
    vUv0 = P;
    dViewDirW = pxh_V;
    dTBN = mat3(1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0);  // the frame's y along -v
    getParallax();
    return vUv0 + dUvOffset;
}

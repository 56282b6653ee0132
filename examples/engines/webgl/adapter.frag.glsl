// pxh's side of the web engine's chunk: the engine's varying vUv is the sample point, its
// tangent-space view vector is pxh_V. The chunk itself is included as it ships.
vec2 vUv;

#include "parallax.glsl"

vec2 pxh_method(vec2 P) {
    vUv = P;
    return parallaxMap(pxh_V);
}

// An engine's POM shader, plugged into pxh without recompiling (README: "Gate your engine's
// shader in CI"). pxh prepends methods/common.glsl: pxh_V (the view vector, unit, toward the
// eye), pxh_z(uv) (the surface height z = s (h - b) at uv: one counted fetch), pxh_z_top(),
// u_scale (s), u_bias (b), u_size (texels). Define vec2 pxh_method(vec2 P): the uv to shade.
uniform float p_steps;  // from the experiment's `uniforms` table

vec2 pxh_method(vec2 P) {
    vec2 dir = pxh_V.xy / pxh_V.z;
    float dz = u_scale / p_steps;
    vec2 duv = -dir * dz;
    float z0 = pxh_z_top();
    vec2 uv = P + dir * z0;
    float z = z0;
    float g_prev = 0.0;
    float g = z - pxh_z(uv);
    int k = 0;
    while (g > 0.0 && k < int(ceil(p_steps))) {  // bounded: at most ceil(n) + 1 fetches
        k += 1;
        uv += duv;
        z -= dz;
        g_prev = g;
        g = z - pxh_z(uv);
    }
    if (k == 0 || g > 0.0) return uv;
    float w = g / (g - g_prev);  // the crossing between layers k-1 and k
    return uv - duv * w;
}

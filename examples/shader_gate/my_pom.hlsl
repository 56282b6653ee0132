// my_pom.frag.glsl written in HLSL: the same POM, sample for sample (docs/guide/plugin-shaders.md,
// "HLSL and WGSL"). pxh compiles methods/common.hlsl before it: pxh_V, pxh_z(uv) (one counted
// fetch), pxh_z_top(), u_scale, u_bias, u_size, as in GLSL. Define float2 pxh_method(float2 P).
float p_steps;  // from the experiment's `uniforms` table

float2 pxh_method(float2 P) {
    float2 dir = pxh_V.xy / pxh_V.z;
    float dz = u_scale / p_steps;
    float2 duv = -dir * dz;
    float z0 = pxh_z_top();
    float2 uv = P + dir * z0;
    float z = z0;
    float g_prev = 0.0;
    float g = z - pxh_z(uv);
    int k = 0;
    [loop] while (g > 0.0 && k < int(ceil(p_steps))) {  // at most ceil(n) + 1 fetches
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

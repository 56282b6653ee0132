// Bisection over the whole slab (methods/binary/binary.cpp).
uniform int p_iterations;
vec2 pxh_method(vec2 P) {
    vec2 dir = pxh_V.xy * (1.0 / pxh_V.z);
    float z0 = pxh_z_top();
    vec2 uv0 = P + dir * z0;
    vec2 duv = dir * (-u_scale);
    float lo = 0.0, hi = 1.0;
    for (int i = 0; i < p_iterations; ++i) {
        float mid = (lo + hi) * 0.5;
        float g = (z0 - u_scale * mid) - pxh_z(uv0 + duv * mid);
        if (g > 0.0) lo = mid; else hi = mid;
    }
    float t = (lo + hi) * 0.5;
    pxh_write_hit(z0 - u_scale * t);
    return uv0 + duv * t;
}

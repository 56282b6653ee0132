// Risser, Shah, Pattanaik, JGT 12(3) 2007 (methods/secant/secant.cpp): layer search, then
// false-position steps on [k-1, k]; the last secant point is returned unprobed.
uniform int p_iterations;
float pxh_secant_point(float xa, float ga, float xb, float gb) {
    float d = ga - gb;
    if (!(d > 0.0)) return xb;
    float w = clamp(ga / d, 0.0, 1.0);
    return xa + (xb - xa) * w;
}
vec2 pxh_method(vec2 P) {
    PxhLayers r = pxh_layer_search(P);
    pxh_write_hit(pxh_z_at(r, float(r.k)));
    if (r.k == 0 || !r.crossed) return pxh_uv_at(r, float(r.k));
    float xa = float(r.k - 1), ga = r.g_prev, xb = float(r.k), gb = r.g_k;
    for (int i = 1; i < p_iterations; ++i) {
        float x = pxh_secant_point(xa, ga, xb, gb);
        float g = pxh_z_at(r, x) - pxh_z(pxh_uv_at(r, x));
        if (g > 0.0) {
            xa = x;
            ga = g;
        } else {
            xb = x;
            gb = g;
        }
    }
    float x = pxh_secant_point(xa, ga, xb, gb);
    pxh_write_hit(pxh_z_at(r, x));
    return pxh_uv_at(r, x);
}

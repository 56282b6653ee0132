// Pixel-offset paper sec. 3.2.2 (pixel offset translation), from the slab bottom.
uniform int p_max_steps;
vec2 pxh_method(vec2 P) {
    float vxy = sqrt(pxh_V.x * pxh_V.x + pxh_V.y * pxh_V.y);
    if (vxy == 0.0) return P;
    float texel = 1.0 / float(u_size.x);
    vec2 q0 = P + pxh_V.xy * (pxh_z_bot() / pxh_V.z);
    vec2 stp = pxh_V.xy * (texel / vxy);
    float rise = texel * pxh_V.z / vxy;
    float zb = pxh_z_bot();
    float need = ceil(u_scale * float(u_size.x) * vxy / pxh_V.z) + 1.0;
    int kmax = int(min(need, float(p_max_steps)));
    int k = 0;
    vec2 q = q0;
    while (zb + float(k) * rise < pxh_z(q) && k < kmax) {
        k += 1;
        q = q0 + stp * float(k);
    }
    pxh_write_hit(zb + float(k) * rise);
    return q;
}

// Contact refinement (methods/contact/contact.cpp): layer search, then sub-layers of 1/n from
// layer k-1 to the first at or below the surface; optionally pom's interpolation.
uniform bool p_lerp;
vec2 pxh_method(vec2 P) {
    PxhLayers r = pxh_layer_search(P);
    pxh_write_hit(pxh_z_at(r, float(r.k)));
    if (r.k == 0 || !r.crossed) return pxh_uv_at(r, float(r.k));
    float base = float(r.k - 1), sub = 1.0 / r.n;
    int jmax = int(ceil(r.n)) - 1;
    float xa = base, ga = r.g_prev, xb = float(r.k), gb = r.g_k;
    for (int j = 1; j <= jmax; ++j) {
        float x = base + sub * float(j);
        float g = pxh_z_at(r, x) - pxh_z(pxh_uv_at(r, x));
        if (!(g > 0.0)) {
            xb = x;
            gb = g;
            break;
        }
        xa = x;
        ga = g;
    }
    pxh_write_hit(pxh_z_at(r, xb));
    if (!p_lerp) return pxh_uv_at(r, xb);
    float denom = gb - ga;
    if (!(denom < 0.0)) return pxh_uv_at(r, xb);
    float w = clamp(gb / denom, 0.0, 1.0);
    pxh_write_hit(pxh_z_at(r, xa) * w + pxh_z_at(r, xb) * (1.0 - w));
    return pxh_uv_at(r, xa) * w + pxh_uv_at(r, xb) * (1.0 - w);
}

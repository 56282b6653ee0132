// Policarpo et al. 2005; tutorial "Relief Parallax Mapping": bisection on [k-1, k].
uniform int p_binary_steps;
vec2 pxh_method(vec2 P) {
    PxhLayers r = pxh_layer_search(P);
    if (r.k == 0) {
        pxh_write_hit(r.z0);
        return r.uv0;
    }
    float lo = float(r.k - 1), hi = float(r.k);
    for (int i = 0; i < p_binary_steps; ++i) {
        float mid = (lo + hi) * 0.5;
        float g = pxh_z_at(r, mid) - pxh_z(pxh_uv_at(r, mid));
        if (g > 0.0) lo = mid; else hi = mid;
    }
    float x = (lo + hi) * 0.5;
    pxh_write_hit(pxh_z_at(r, x));
    return pxh_uv_at(r, x);
}

// Tatarchuk 2006; tutorial "Parallax Occlusion Mapping".
vec2 pxh_method(vec2 P) {
    PxhLayers r = pxh_layer_search(P);
    vec2 uv_k = pxh_uv_at(r, float(r.k));
    pxh_write_hit(pxh_z_at(r, float(r.k)));
    if (r.k == 0 || !r.crossed) return uv_k;
    float denom = r.g_k - r.g_prev;
    if (!(denom < 0.0)) return uv_k;
    float w = clamp(r.g_k / denom, 0.0, 1.0);
    pxh_write_hit(pxh_z_at(r, float(r.k - 1)) * w + pxh_z_at(r, float(r.k)) * (1.0 - w));
    return pxh_uv_at(r, float(r.k - 1)) * w + uv_k * (1.0 - w);
}

// McGuire 2005; tutorial "Steep Parallax Mapping": uv_k.
vec2 pxh_method(vec2 P) {
    PxhLayers r = pxh_layer_search(P);
    pxh_write_hit(pxh_z_at(r, float(r.k)));
    return pxh_uv_at(r, float(r.k));
}

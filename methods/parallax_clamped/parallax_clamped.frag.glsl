// Cg wikibook "Projection of Bumpy Surfaces": P + clamp(z(P) V.xy / V.z, -m, +m).
uniform bool p_max_offset_is_scale;  // max_offset = "scale": m = s
uniform float p_max_offset;
vec2 pxh_method(vec2 P) {
    float m = p_max_offset_is_scale ? u_scale : p_max_offset;
    vec2 off = pxh_V.xy * (pxh_z(P) / pxh_V.z);
    return P + clamp(off, vec2(-m), vec2(m));
}

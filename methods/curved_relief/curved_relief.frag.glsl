// Oliveira & Policarpo 2005, curved relief mapping (methods/curved_relief/curved_relief.cpp):
// the ray bent by the base's quadric, linear + binary search, discard past the silhouette.
uniform int p_steps;
uniform int p_binary_steps;
float pxh_cr_q;
vec2 pxh_cr_uv(vec2 P, float l) { return P - pxh_V.xy * l; }
bool pxh_cr_above(vec2 P, float l) {
    return -pxh_V.z * l + pxh_cr_q * l * l > pxh_z(pxh_cr_uv(P, l));
}
vec2 pxh_method(vec2 P) {
    vec3 V = pxh_V;
    pxh_cr_q = 0.5 * (u_curvature.x * V.x * V.x + u_curvature.y * V.y * V.y);
    float q = pxh_cr_q;
    float zt = pxh_z_top(), zb = -u_scale * u_bias;
    float l0 = -2.0 * zt / (V.z + sqrt(max(V.z * V.z + 4.0 * q * zt, 0.0)));
    float l_end = 50.0;
    float disc = V.z * V.z + 4.0 * q * zb;
    if (disc >= 0.0) l_end = min(l_end, -2.0 * zb / (V.z + sqrt(disc)));
    if (q > 0.0) l_end = min(l_end, (V.z + sqrt(V.z * V.z + 4.0 * q * zt)) / (2.0 * q));
    float size = (l_end - l0 + 0.001) / float(p_steps);
    float l = l0;
    for (int i = 0; i < p_steps; ++i)
        if (pxh_cr_above(P, l)) l += size;
    for (int i = 0; i < p_binary_steps; ++i) {
        size *= 0.5;
        if (pxh_cr_above(P, l)) l += size;
        else l -= size;
    }
    if (l > l_end) discard;
    pxh_write_hit(-V.z * l);  // the eye ray's point at l (curved_relief.cpp)
    return pxh_cr_uv(P, l);
}

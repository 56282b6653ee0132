// three.js PR 33953's silhouette POM, curvedSilhouette mode (methods/silhouette_pom/
// silhouette_pom.cpp): POM against the relief bent by the base's curvature, discard on a miss.
uniform int p_min_layers;
uniform int p_max_layers;
uniform int p_chase;
uniform float p_miss_tol;
vec2 pxh_sp_P;
vec2 pxh_sp_bend;
float pxh_sp_D(vec2 uv) {
    vec2 d = uv - pxh_sp_P;
    return 1.0 - pxh_height(uv) + pxh_sp_bend.x * d.x * d.x + pxh_sp_bend.y * d.y * d.y;
}
vec2 pxh_method(vec2 P) {
    vec3 V = pxh_V;
    float s = u_scale;
    float a = clamp(abs(V.z), 0.0, 1.0);
    float n = float(p_max_layers) + float(p_min_layers - p_max_layers) * a;
    float dL = 1.0 / n;
    float vz = max(abs(V.z), 0.05);
    vec2 shift = V.xy / vz * s;
    vec2 duv = shift / n;
    float two_s = max(2.0 * s, 1e-4);
    pxh_sp_bend = vec2(min(u_curvature.x / two_s, 6.0), min(u_curvature.y / two_s, 6.0));
    pxh_sp_P = P;
    vec2 uv = P + shift * (1.0 - u_bias);
    float L = 0.0, d = pxh_sp_D(uv);
    for (int i = 0; i < p_max_layers && L < d; ++i) {
        uv -= duv;
        L += dL;
        d = pxh_sp_D(uv);
    }
    for (int i = 0; i < p_chase && L < d; ++i) {
        uv -= duv * 4.0;
        L += 4.0 * dL;
        d = pxh_sp_D(uv);
    }
    vec2 prev = uv + duv;
    float after = L - d, before = pxh_sp_D(prev) - (L - dL);
    float w = clamp(after / max(after + before, 1e-4), 0.0, 1.0);
    if (d - L > p_miss_tol) discard;
    pxh_write_hit(s * (1.0 - u_bias - (L - w * dL)));  // its line's height (silhouette_pom.cpp)
    return uv + (prev - uv) * w;
}

// Policarpo and Oliveira 2007, relaxed cone stepping (methods/relaxed_cone/relaxed_cone.cpp).
uniform sampler2D r_relaxed;  // rgba32f, linear, repeat: (h, book, ban, ban_min ratio)
uniform int p_cone_steps;
uniform int p_binary_steps;
uniform int p_cones;  // 0 book, 1 ban, 2 ban_min

vec2 pxh_method(vec2 P) {
    vec2 D = pxh_V.xy * (1.0 / pxh_V.z);
    vec2 uv0 = P + D * pxh_z_top();
    vec2 m = D * (-u_scale);
    float dist = sqrt(m.x * m.x + m.y * m.y);
    float t = 0.0;
    for (int i = 0; i < p_cone_steps; ++i) {
        vec4 tex = pxh_texture(r_relaxed, uv0 + m * t, 0);
        float gap = clamp(1.0 - t - tex.r, 0.0, 1.0);
        float ratio = p_cones == 0 ? tex.g : (p_cones == 1 ? tex.b : tex.a);
        t = t + ratio * gap / (dist + ratio);
    }
    float range = t * 0.5;
    float tb = range;
    for (int i = 0; i < p_binary_steps; ++i) {
        vec4 tex = pxh_texture(r_relaxed, uv0 + m * tb, 0);
        range = range * 0.5;
        if (tb < 1.0 - tex.r) tb = tb + range; else tb = tb - range;
    }
    pxh_write_hit(pxh_z_top() - u_scale * tb);
    return uv0 + m * tb;
}

// Dummer 2006, cone step mapping; the step loop of Ban et al. 2024 (methods/cone/cone.cpp).
uniform sampler2D r_cone;  // rgba32f, linear, repeat: (h, dummer, dummer_min, bilinear ratio)
uniform int p_steps;
uniform int p_map;       // 0 dummer, 1 dummer_min, 2 bilinear
uniform int p_min_step;  // 0 texel, 1 cell, 2 none
uniform int p_refine;    // 0 none, 1 linear, 2 binary (Ban et al. 2024, Refinement.slang)
uniform int p_refine_steps;

bool pxh_cone_to_border(vec2 p, vec2 m, out float d) {
    bool any = false;
    d = 0.0;
    if (m.x != 0.0) {
        float i0 = floor(p.x * float(u_size.x) - 0.5);
        float wall = (i0 + (m.x > 0.0 ? 1.5 : 0.5)) / float(u_size.x);
        d = (wall - p.x) / m.x;
        any = true;
    }
    if (m.y != 0.0) {
        float j0 = floor(p.y * float(u_size.y) - 0.5);
        float wall = (j0 + (m.y > 0.0 ? 1.5 : 0.5)) / float(u_size.y);
        float dy = (wall - p.y) / m.y;
        d = any ? min(d, dy) : dy;
        any = true;
    }
    return any;
}

// The chord refinement on [t0, t1] (cone.cpp, refine_linear).
float pxh_cone_refine_linear(vec2 uv0, vec2 m, float t0, float t1) {
    float h0 = pxh_texture(r_cone, uv0 + m * t0, 0).r;
    float h1 = pxh_texture(r_cone, uv0 + m * t1, 0).r;
    float dt = t1 - t0;
    float num = dt + t0 * h1 - t1 * h0;
    float den = dt + h1 - h0;
    float t = den != 0.0 ? num / den : (num > 0.0 ? t1 : t0);
    return min(max(t, t0), t1);
}

// Bisections from the midpoint (cone.cpp, refine_binary).
float pxh_cone_refine_binary(vec2 uv0, vec2 m, float t0, float t1) {
    float th = 0.5 * (t0 + t1);
    for (int i = 0; i < p_refine_steps; ++i) {
        float fh = pxh_texture(r_cone, uv0 + m * th, 0).r;
        if (fh > 1.0 - th)
            t1 = th;
        else
            t0 = th;
        th = 0.5 * (t0 + t1);
    }
    return th;
}

vec2 pxh_method(vec2 P) {
    vec2 D = pxh_V.xy * (1.0 / pxh_V.z);
    vec2 uv0 = P + D * pxh_z_top();
    vec2 m = D * (-u_scale);
    float dist = sqrt(m.x * m.x + m.y * m.y);
    float dsz = 1.0 / sqrt(1.0 + dist * dist);
    float t = 0.0;
    float t_last = 0.0;
    vec2 q = uv0;
    vec4 tex = pxh_texture(r_cone, q, 0);
    // until less than 2^-20 above the surface (cone.cpp, kConverged)
    for (int k = 0; k < p_steps && 1.0 - t - tex.r > 9.5367431640625e-7; ++k) {
        t_last = t;
        float ratio = p_map == 0 ? tex.g : (p_map == 1 ? tex.b : tex.a);
        float cone = ratio * (1.0 - t - tex.r) / (dist + ratio);
        float w = 0.0;
        if (p_min_step == 0) {
            w = dsz / float(u_size.x);
        } else if (p_min_step == 1) {
            float b;
            if (pxh_cone_to_border(q, m, b)) w = b + 1e-5 * dsz;
        }
        t = t + max(w, cone);
        q = uv0 + m * t;
        tex = pxh_texture(r_cone, q, 0);
    }
    if (p_refine == 1) t = pxh_cone_refine_linear(uv0, m, t_last, t);
    else if (p_refine == 2) t = pxh_cone_refine_binary(uv0, m, t_last, t);
    pxh_write_hit(pxh_z_top() - u_scale * t);
    if (p_refine == 1 || p_refine == 2) return uv0 + m * t;
    return q;
}

// The parametric marcher (methods/march/march.h): the same operations in the same order.
// @pxh-declarations: the knobs' uniforms, generated from methods/march/knobs.h

float pm_fast_acos_pos(float x) {
    float p = (0.0468878 * x - 0.203471) * x + 1.570796;
    return p * sqrt(1.0 - x);
}

float pm_layer_count(float texels) {
    float vz = pxh_V.z, lo = pm_layers_min, hi = pm_layers_max;
    if (pm_count == 0) return pm_layers;
    if (pm_count == 6) return clamp(texels / pm_texels_per_step, 1.0, hi);
    if (pm_count == 2) return trunc(hi + (lo - hi) * vz);
    if (pm_count == 3) return hi + (-vz) * (lo - hi);
    if (pm_count == 4) {
        vec2 xy = pxh_V.xy * u_scale;
        float zn = vz / sqrt(xy.x * xy.x + xy.y * xy.y + vz * vz);
        float a = clamp(pm_fast_acos_pos(abs(zn)) * 0.636619772, 0.0, 1.0);
        return trunc(lo + (hi - lo) * a);
    }
    if (pm_count == 5) {
        float a = 1.0 - vz;
        return lo * (1.0 - a) + (hi * u_scale) * a;
    }
    float a = abs(vz);
    return hi * (1.0 - a) + lo * a;
}

vec2 pm_direction() {
    vec2 d = pxh_V.xy;
    if (pm_mirror_v) d.y = -d.y;
    if (pm_step == 0) d = d * (1.0 / pxh_V.z);
    if (pm_max_slope > 0.0) {
        float len = sqrt(d.x * d.x + d.y * d.y), cap = pm_max_slope;
        if (len > cap) d = d * (cap / len);
    }
    return d;
}

float pm_texels(vec2 d, float L) {
    float x = u_scale * d.x * float(u_size.x), y = u_scale * d.y * float(u_size.y);
    return sqrt(x * x + y * y) / exp2(L);
}

int pm_kmax(float n, int extra, int max_steps, int first) {
    float kmax = ceil(n) + float(extra);
    if (!(kmax < 1e6)) kmax = 1e6;
    int k = int(max(kmax, 0.0));
    if (max_steps > 0) k = min(k, max_steps);
    return first == 0 ? k : max(k, 1);
}

// The march's state, shared by the search and its refinements.
vec2 pm_uv0, pm_duv;
float pm_z0, pm_dz, pm_lag_k, pm_n;
// The layered search's answer height z_m on its own line (march.h: MethodHit::z), and the
// surface height HDRP's depth offset reads (the last probe's, at the unfaded uv: engine_z).
float pm_zm = 0.0, pm_engine_z = 0.0;
bool pm_engine_z_set = false;
vec2 pm_uv_at(float x) { return pm_uv0 + pm_duv * x; }
float pm_ray_z(float x) { return pm_z0 - pm_dz * x; }
vec2 pm_answer(float x) {
    float xc = pm_clamp_depth ? clamp(x, 0.0, pm_n) : x;
    pm_zm = pm_ray_z(xc);
    return pm_uv_at(xc);
}
float pm_g(float x, float zs) { return pm_ray_z(x - pm_lag_k) - zs; }
bool pm_hit(float g) { return pm_compare == 1 ? g < 0.0 : g <= 0.0; }

vec2 pm_offset(vec2 P, vec2 d) {
    float z = pxh_z(P);
    if (pm_offset_form == 1) return P + d * z;
    if (pm_offset_form == 2) return P + d * (z / (pxh_V.z + pm_offset_soften));
    if (pm_offset_form == 3) return P + d * (z * pxh_V.z);
    return P + d * (z / pxh_V.z);
}

vec2 pm_bisect(int k, float gk) {
    float x = float(k), stp = 1.0, g = gk;
    for (int i = 0; i <= pm_iterations; ++i) {
        stp = stp * 0.5;
        if (g > 0.0) x = x + stp;
        else if (g < 0.0 || pm_tie == 0) x = x - stp;
        if (i < pm_iterations) g = pm_g(x, pxh_z(pm_uv_at(x)));
    }
    if (pm_probe_last) pxh_z(pm_uv_at(x));
    return pm_answer(x);
}

vec2 pm_secant(int k, float gk, float zs_prev, bool has_prev) {
    float s = u_scale, b = u_bias;
    if (!has_prev) zs_prev = pxh_z(pm_uv_at(float(k - 1)));
    float xp = float(k - 1) - pm_lag_k, xk = float(k) - pm_lag_k;
    float r0 = pm_ray_z(xp) / s + b, d0 = pm_g(float(k - 1), zs_prev) / s;
    float r1 = pm_ray_z(xk) / s + b, d1 = gk / s;
    float x = float(k);
    for (int i = 0; i < pm_iterations; ++i) {
        float ih = (r0 * d1 - r1 * d0) / (d1 - d0);
        x = (pm_z0 - s * (ih - b)) / pm_dz;
        float delta = ih - pxh_height(pm_uv_at(x));
        if (abs(delta) <= pm_tolerance) break;
        if (delta < 0.0) {
            r1 = ih;
            d1 = delta;
        } else {
            r0 = ih;
            d0 = delta;
        }
    }
    return pm_answer(x);
}

vec2 pm_contact(int k, float n, float zs_prev, bool has_prev) {
    float base = float(k - 1), sub = 1.0 / n;
    if (!has_prev) zs_prev = pxh_z(pm_uv_at(base));
    float x = base, g = pm_g(base, zs_prev);
    int jmax = pm_kmax(n, 0, 0, 0) + 1;
    for (int j = 1; !pm_hit(g) && j <= jmax; ++j) {
        x = base + sub * float(j);
        g = pm_g(x, pxh_z(pm_uv_at(x)));
    }
    return pm_answer(x);
}

// march_search (methods/march/march.h)
vec2 pm_march_search(vec2 P) {
    vec2 d = pxh_V.xy;
    if (pm_mirror_v) d.y = -d.y;
    if (pm_search == 0) return pm_offset(P, d);
    float s = u_scale, b = u_bias;
    d = pm_direction();
    float texels = pm_count == 6 ? pm_texels(d, max(pxh_lod(), 0.0)) : 0.0;
    float n = pm_layer_count(texels);
    pm_n = n;
    pm_dz = s / n;
    pm_duv = d * (-pm_dz);
    pm_z0 = pxh_z_top();
    pm_uv0 = P + d * pm_z0;
    pm_lag_k = pm_lag ? 1.0 : 0.0;
    int kmax = pm_kmax(n, pm_extra_layers, pm_max_steps, pm_first);

    int k = 0;
    float zs = 0.0, zs_prev = 0.0;
    bool has_prev = false;
    if (pm_first == 0) {
        zs = pxh_z(pm_uv0);
    } else {
        zs_prev = s * ((pm_first == 1 ? 1.0 : 0.0) - b);
        has_prev = true;
        k = 1;
        zs = pxh_z(pm_uv_at(1.0));
    }
    while (!pm_hit(pm_g(float(k), zs)) && k < kmax) {
        k += 1;
        zs_prev = zs;
        has_prev = true;
        zs = pxh_z(pm_uv_at(float(k)));
    }
    if (!pm_hit(pm_g(float(k), zs))) {
        if (pm_on_miss == 0) return pm_answer(float(k));
        if (pm_on_miss == 1) return pm_answer(float(k + 1));
        pm_lag_k = 0.0;
    }
    if (pm_refine == 0) return pm_answer(float(k));
    if (k == 0 && !pm_refine_at_k0) return pm_answer(0.0);
    float gk = pm_g(float(k), zs);
    if (pm_refine == 1) {
        if (!has_prev || pm_refetch) zs_prev = pxh_z(pm_uv_at(float(k - 1)));
        float gp = pm_g(float(k - 1), zs_prev);
        float denom = gk - gp;
        float w = gk / denom;
        if (pm_clamp_weight) {
            if (!(denom < 0.0)) {
                pm_zm = pm_ray_z(float(k));
                return pm_uv_at(float(k));
            }
            w = clamp(w, 0.0, 1.0);
        }
        pm_zm = pm_ray_z(float(k - 1)) * w + pm_ray_z(float(k)) * (1.0 - w);
        return pm_uv_at(float(k - 1)) * w + pm_uv_at(float(k)) * (1.0 - w);
    }
    if (pm_refine == 2) return pm_bisect(k, gk);
    if (pm_refine == 3) return pm_secant(k, gk, zs_prev, has_prev);
    if (pm_refine == 4) return pm_contact(k, n, zs_prev, has_prev);
    return pm_answer(float(k));
}

int pm_full_fetches(float L) {
    if (pm_search == 0) return 1;
    float texels = pm_count == 6 ? pm_texels(pm_direction(), L) : 0.0;
    int kmax = pm_kmax(pm_layer_count(texels), pm_extra_layers, pm_max_steps, pm_first);
    return (pm_first == 0 ? 1 : 0) + kmax;
}

// march (methods/march/march.h): the search, pad_fetches and the level-of-detail rule on
// L = max(lambda, 0).
vec2 pm_march(vec2 P) {
    float L = max(pxh_lod(), 0.0);
    float t = pm_lod_threshold;
    pm_zm = 0.0;  // P itself (the search not run)
    if (pm_lod_fade == 2 && L > t) return P;
    float f = 1.0;
    if (pm_lod_fade == 3) {
        float m = pm_texels(pm_direction(), L);
        float lo = pm_fade_texels_min, hi = pm_fade_texels_max;
        f = clamp((m - lo) / (hi - lo), 0.0, 1.0);
        if (!(f > 0.0)) return P;
    }
    int fetched_before = pxh_fetches;
    vec2 uv = pm_march_search(P);
    if (pm_pad_fetches) {
        int full = pm_full_fetches(L);
        while (pxh_fetches - fetched_before < full) pxh_height(uv);
    }
    if (pm_lod_fade == 1) f = 1.0 - clamp(L - t, 0.0, 1.0);
    bool layered = pm_search != 0;
    if (pm_lod_fade == 1 || pm_lod_fade == 3) {
        if (f < 1.0) {
            if (pm_depth_offset == 1) {
                pm_engine_z = u_scale * (pxh_height_uncounted(uv) - u_bias);
                pm_engine_z_set = true;
            }
            uv = P + (uv - P) * f;
            if (layered) pm_zm = pm_zm * f;
        }
    } else if (pm_lod_fade == 2 && L > t - 1.0) {
        float frac = L - floor(L);
        uv = uv + (P - uv) * frac;
        if (layered) pm_zm = pm_zm - pm_zm * frac;
    }
    return uv;
}

// march_engine_depth (methods/march/march.h): the depth the engine writes (depth = engine).
float pm_engine_depth(vec2 P, vec2 uv) {
    vec3 V = pxh_V, f = pxh_depth_axis;
    float vf = dot(V, f);
    float z_surface = u_scale * (pxh_height_uncounted(uv) - u_bias);
    float z_line = pm_search == 0 ? z_surface : pm_zm;
    float z_engine = pm_engine_z_set ? pm_engine_z : z_surface;
    if (pm_depth_offset == 1) return -vf * (pxh_z_top() - z_engine) / max(V.z, 1e-4);
    if (pm_depth_offset == 2) {
        if (pm_search == 0) return dot(vec3(uv - P, 0.0), f);
        if (z_line > 0.0) return 0.0;
        return dot(vec3(uv - P, z_line), f);
    }
    if (pm_depth_offset == 3) return max(-z_line / V.z, 0.0);
    if (pm_depth_offset == 4) return max(-z_line / V.z * -vf, 0.0);
    return 0.0;
}

vec2 pxh_method(vec2 P) {
    vec2 uv = pm_march(P);
    if (pm_search != 0) pxh_write_hit(pm_zm);
    if (u_depth_mode == 2) pxh_write_engine_depth(pm_engine_depth(P, uv));
    return uv;
}

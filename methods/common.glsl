// pxh common GLSL: uniforms, counted height fetches, the shared layer search, the shadow
// march, and main(). The harness prepends "#version 450 core" and the method's file follows.
// Every function mirrors the CPU reference's operation order (methods/*.h, methods/*/*.cpp).

layout(location = 0) out vec4 pxh_out_uv;      // uv.x, uv.y, fetches, 1 (written)
layout(location = 1) out vec4 pxh_out_shadow;  // hard, soft light factor (1 lit, 0 shadowed),
                                               // the written depth as computed (tiles)

uniform sampler2D u_height;  // GL_LINEAR + GL_REPEAT
uniform float u_scale;       // s
uniform float u_bias;        // b
uniform vec3 u_view;         // V, toward the eye, of a view whose rays are parallel
uniform vec2 u_curvature;    // the base's normal curvatures along T, Bt (conventions section 12)
uniform bool u_view_per_sample;  // true: each sample's own V, from u_view_map
uniform sampler2D u_view_map;    // per-sample V (xyz); texel (i, j) is sample j N + i
uniform ivec2 u_size;        // W, H
uniform float u_samples;     // N
uniform int u_light_on;
uniform vec3 u_light;        // L, toward the light
uniform float u_shadow_layers_min;
uniform float u_shadow_layers_max;
// The depth it writes (methods/depth.h, docs/conventions.md section 11): gl_FragDepth =
// 0.5 + depth(X_w) / u_depth_span, depth(X) = (X - P) . u_depth_axis in tiles.
uniform int u_depth_mode;    // 0 base (X_w = P), 1 hit (X_w = (uv, z_m)), 2 engine
uniform int u_hit_height;    // z_m where pxh_write_hit was not called: 0, 1 the surface at uv, 2 P
uniform vec3 u_depth_axis;   // f: the perspective camera's forward vector, -V for parallel rays
uniform float u_depth_span;
// A curved base's view (docs/conventions.md section 12): f per sample in its tangent frame.
uniform bool u_depth_axis_per_sample;  // true: the axis from u_axis_map
uniform sampler2D u_axis_map;          // (f . T, f . Bt, f . N); texel (i, j) is sample j N + i
// What a program has beyond the orthographic grid at level 0: the harness defines these in a
// generated preamble only when the row needs them (none of them: the grid program as always).
//   PXH_POINT_MAP     each sample's P and inside flag per pixel (a perspective view)
//   PXH_LOD_MAP       each sample's lambda per pixel (lod = level, or a shader calling pxh_lod)
//   PXH_LOD_LEVEL     every height fetch at the sample's lambda (textureLod)
//   PXH_LOD_GRAD      every height fetch with the sample's footprint (textureGrad)
//   PXH_LOD_IMPLICIT  every height fetch with the hardware's derivatives (texture)
#if defined(PXH_POINT_MAP)
uniform sampler2D u_point_map;  // P (xy), inside (z: 1 inside, 0 outside); texel (i, j): j N + i
#endif
#if defined(PXH_LOD_MAP)
uniform sampler2D u_lod_map;  // lambda (r32f), texel (i, j) is sample j N + i
#endif
#if defined(PXH_LOD_GRAD)
uniform sampler2D u_grad_map;  // the footprint: dP/di (xy), dP/dj (zw), texel (i, j): j N + i
#endif

int pxh_fetches = 0;
vec3 pxh_V;  // this sample's V (unit, toward the eye): what a method reads; set by main()
vec3 pxh_depth_axis;  // this sample's depth axis (u_depth_axis or its u_axis_map texel)
#if defined(PXH_LOD_MAP)
float pxh_lambda;  // this sample's lambda; set by main()
// The sample's level of detail: log2 of its footprint's texels per pixel (may be negative).
float pxh_lod() { return pxh_lambda; }
#endif
#if defined(PXH_LOD_GRAD)
vec4 pxh_footprint;  // this sample's dP/di (xy), dP/dj (zw); set by main()
#endif

float pxh_height(vec2 uv) {
    pxh_fetches += 1;
#if defined(PXH_LOD_LEVEL)
    return textureLod(u_height, uv, pxh_lambda).r;
#elif defined(PXH_LOD_GRAD)
    return textureGrad(u_height, uv, pxh_footprint.xy, pxh_footprint.zw).r;
#elif defined(PXH_LOD_IMPLICIT)
    return texture(u_height, uv).r;
#else
    return textureLod(u_height, uv, 0.0).r;
#endif
}
float pxh_z(vec2 uv) { return u_scale * (pxh_height(uv) - u_bias); }

// The height at an explicit texture level lod (one counted fetch, whatever the row's lod mode):
// what an engine's textureLod / texture2DLod on its height sampler reads (a plug-in's
// height_sampler). Levels above 0 exist where the row's lod is not base.
float pxh_height_lod(vec2 uv, float lod) {
    pxh_fetches += 1;
    return textureLod(u_height, uv, lod).r;
}
// The height with explicit derivatives (one counted fetch): an engine's textureGrad.
float pxh_height_grad(vec2 uv, vec2 dx, vec2 dy) {
    pxh_fetches += 1;
    return textureGrad(u_height, uv, dx, dy).r;
}
// The height texture's size at level lod (no fetch): an engine's textureSize.
ivec2 pxh_height_size(int lod) { return max(u_size >> lod, ivec2(1)); }
// A method resource (methods/resource.h: `uniform sampler2D r_NAME;` in the method's file),
// at mip level `level`, with the filter and wrap the resource declares; counted like heights.
vec4 pxh_texture(sampler2D r, vec2 uv, int level) {
    pxh_fetches += 1;
    return textureLod(r, uv, float(level));
}
float pxh_z_top() { return u_scale * (1.0 - u_bias); }
float pxh_z_bot() { return -u_scale * u_bias; }

// ---- Layer search (methods/layered.h) ----
uniform bool p_layers_adaptive;  // true: n = mix(n_max, n_min, |V.z|); false: n = p_layers
uniform float p_layers;
uniform float p_layers_min;
uniform float p_layers_max;

struct PxhLayers {
    float n;
    vec2 uv0, duv;
    float z0, dz;
    int k;
    float g_prev, g_k;
    bool crossed;
};

float pxh_layer_count() {
    if (!p_layers_adaptive) return p_layers;
    float a = abs(pxh_V.z);
    return p_layers_max * (1.0 - a) + p_layers_min * a;
}

vec2 pxh_uv_at(PxhLayers r, float layer) { return r.uv0 + r.duv * layer; }
float pxh_z_at(PxhLayers r, float layer) { return r.z0 - r.dz * layer; }

// The search with n layers given (a plug-in's own count: it needs no p_layers* uniform).
PxhLayers pxh_layer_search_n(vec2 P, float n) {
    PxhLayers r;
    r.n = n;
    vec2 dir = pxh_V.xy * (1.0 / pxh_V.z);
    r.dz = u_scale / r.n;
    r.duv = dir * (-r.dz);
    r.z0 = pxh_z_top();
    r.uv0 = P + dir * r.z0;
    int kmax = int(ceil(r.n));
    r.g_prev = 0.0;
    r.g_k = r.z0 - pxh_z(r.uv0);
    r.k = 0;
    while (r.g_k > 0.0 && r.k < kmax) {
        r.k += 1;
        r.g_prev = r.g_k;
        r.g_k = pxh_z_at(r, float(r.k)) - pxh_z(pxh_uv_at(r, float(r.k)));
    }
    r.crossed = !(r.g_k > 0.0);
    return r;
}

// The search with the method's p_layers* uniforms (n = pxh_layer_count()).
PxhLayers pxh_layer_search(vec2 P) { return pxh_layer_search_n(P, pxh_layer_count()); }

// ---- Self-shadowing (methods/shadow.h): hard and soft light factors at uv ----
vec2 pxh_shadow(vec2 uv) {
    vec3 L = u_light;
    if (!(L.z > 0.0)) return vec2(0.0, 0.0);
    float z0 = pxh_z(uv);
    float a = abs(L.z);
    float n = u_shadow_layers_max * (1.0 - a) + u_shadow_layers_min * a;
    float dz = (pxh_z_top() - z0) / n;
    vec2 duv = L.xy * (dz / L.z);
    float worst = 0.0;
    bool below = false;
    int count = int(ceil(n));
    for (int i = 1; i < count; ++i) {
        float zi = z0 + float(i) * dz;
        float surf = pxh_z(uv + duv * float(i));
        if (zi < surf) {
            below = true;
            worst = max(worst, (surf - zi) / u_scale * (1.0 - float(i) / n));
        }
    }
    return below ? vec2(0.0, 1.0 - worst) : vec2(1.0, 1.0);
}

// ---- The written depth (methods/depth.h) ----
// The hit's height z_m (`depth = "hit"`): a search calls pxh_write_hit(z) with the height of its
// answer (z = s (h - b) units, the polygon at 0), the value it computed itself (every built-in
// search, as its C++ twin returns MethodHit::z); a single-step method does not, and z_m is the
// surface's at uv (not counted); a plug-in that does not writes the polygon's depth (X_w = P).
float pxh_hit_z = 0.0;
bool pxh_hit_written = false;
void pxh_write_hit(float z) {
    pxh_hit_z = z;
    pxh_hit_written = true;
}
// The `engine` mode: a method whose engine writes a depth offset passes depth(X_w) here.
float pxh_engine_depth = 0.0;
void pxh_write_engine_depth(float depth) { pxh_engine_depth = depth; }

// The height at uv as pxh_height samples it, not counted (what the harness reads, not the
// method).
float pxh_height_uncounted(vec2 uv) {
    int before = pxh_fetches;
    float h = pxh_height(uv);
    pxh_fetches = before;
    return h;
}

float pxh_written_depth(vec2 P, vec2 uv) {
    if (u_depth_mode == 0) return 0.0;
    if (u_depth_mode == 2) return pxh_engine_depth;
    float z = pxh_hit_z;
    if (!pxh_hit_written) {
        if (u_hit_height == 2) return 0.0;
        z = u_scale * (pxh_height_uncounted(uv) - u_bias);
    }
    return dot(vec3(uv - P, z), pxh_depth_axis);
}

vec2 pxh_method(vec2 P);  // the method's file defines it

void main() {
#if defined(PXH_POINT_MAP)
    vec4 point = texelFetch(u_point_map, ivec2(gl_FragCoord.xy), 0);
    if (point.z == 0.0) discard;  // outside the view: masked (counted as outside, not discarded)
    vec2 P = point.xy;
#else
    vec2 P = gl_FragCoord.xy / u_samples;
#endif
    pxh_V = u_view_per_sample ? texelFetch(u_view_map, ivec2(gl_FragCoord.xy), 0).xyz : u_view;
    pxh_depth_axis = u_depth_axis_per_sample
                         ? texelFetch(u_axis_map, ivec2(gl_FragCoord.xy), 0).xyz
                         : u_depth_axis;
#if defined(PXH_LOD_MAP)
    pxh_lambda = texelFetch(u_lod_map, ivec2(gl_FragCoord.xy), 0).r;
#endif
#if defined(PXH_LOD_GRAD)
    pxh_footprint = texelFetch(u_grad_map, ivec2(gl_FragCoord.xy), 0);
#endif
    vec2 uv = pxh_method(P);
    float fetches = float(pxh_fetches);
    float depth = pxh_written_depth(P, uv);
    gl_FragDepth = 0.5 + depth / u_depth_span;  // GL clamps it to [0, 1]
    vec2 shadow = u_light_on != 0 ? pxh_shadow(uv) : vec2(1.0);
    pxh_out_uv = vec4(uv, fetches, 1.0);  // alpha 1: written (the targets clear to alpha 0)
    pxh_out_shadow = vec4(shadow, depth, 0.0);  // z: the depth as computed (not clamped)
}

// my_pom.frag.glsl written in WGSL: the same POM, sample for sample (docs/guide/plugin-shaders.md,
// "HLSL and WGSL"). pxh puts methods/common.wgsl after it: pxh_V, pxh_z(uv) (one counted fetch),
// pxh_z_top(), u_scale, u_bias, u_size, as in GLSL. Its uniforms are the fields of a uniform
// struct (f32, i32; u32 is set as an int). Define fn pxh_method(P: vec2<f32>) -> vec2<f32>.
struct Params { p_steps: f32 }
@group(0) @binding(0) var<uniform> params: Params;  // from the experiment's `uniforms` table

fn pxh_method(P: vec2<f32>) -> vec2<f32> {
    let dir = pxh_V.xy / pxh_V.z;
    let dz = u_scale / params.p_steps;
    let duv = -dir * dz;
    let z0 = pxh_z_top();
    var uv = P + dir * z0;
    var z = z0;
    var g_prev = 0.0;
    var g = z - pxh_z(uv);
    var k = 0;
    while (g > 0.0 && k < i32(ceil(params.p_steps))) {  // at most ceil(n) + 1 fetches
        k += 1;
        uv += duv;
        z -= dz;
        g_prev = g;
        g = z - pxh_z(uv);
    }
    if (k == 0 || g > 0.0) {
        return uv;
    }
    let w = g / (g - g_prev);  // the crossing between layers k-1 and k
    return uv - duv * w;
}

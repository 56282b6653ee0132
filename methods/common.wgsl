// pxh's interface for WGSL plug-ins (docs/guide/plugin-shaders.md, "HLSL and WGSL"): put after
// the plug-in's file (WGSL declarations may come in any order, so the file's lines keep their
// numbers), translated by naga. The bodies are stand-ins that only make the module valid: each
// of these functions and private variables is removed from naga's GLSL, and the code reaches
// methods/common.glsl's of the same name (pxh_height counts the fetch there). The plug-in
// defines fn pxh_method(P: vec2<f32>) -> vec2<f32>.
var<private> pxh_V: vec3<f32>;
var<private> u_scale: f32;
var<private> u_bias: f32;
var<private> u_size: vec2<i32>;
fn pxh_height(uv: vec2<f32>) -> f32 { return 0.0; }
fn pxh_height_lod(uv: vec2<f32>, lod: f32) -> f32 { return 0.0; }
fn pxh_height_grad(uv: vec2<f32>, dx: vec2<f32>, dy: vec2<f32>) -> f32 { return 0.0; }
fn pxh_height_size(lod: i32) -> vec2<i32> { return vec2<i32>(1, 1); }
fn pxh_z(uv: vec2<f32>) -> f32 { return 0.0; }
fn pxh_z_top() -> f32 { return 0.0; }
fn pxh_z_bot() -> f32 { return 0.0; }
fn pxh_lod() -> f32 { return 0.0; }
// The engine's height texture (height_sampler): textureSample, textureSampleBias,
// textureSampleLevel and textureSampleGrad on it become these.
fn pxh_engine_height(uv: vec2<f32>) -> vec4<f32> { return vec4<f32>(0.0); }
fn pxh_engine_height_bias(uv: vec2<f32>, bias: f32) -> vec4<f32> { return vec4<f32>(0.0); }
fn pxh_engine_height_lod(uv: vec2<f32>, lod: f32) -> vec4<f32> { return vec4<f32>(0.0); }
fn pxh_engine_height_grad(uv: vec2<f32>, dx: vec2<f32>, dy: vec2<f32>) -> vec4<f32> {
    return vec4<f32>(0.0);
}
@fragment
fn main(@builtin(position) pxh_frag: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(pxh_method(pxh_frag.xy), 0.0, 1.0);
}

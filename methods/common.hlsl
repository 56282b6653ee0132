// pxh's interface for HLSL plug-ins (docs/guide/plugin-shaders.md, "HLSL and WGSL"): compiled
// before the plug-in's file by glslang's HLSL front end. The bodies below are stand-ins that
// only make the file compile: after SPIRV-Cross each of these functions is removed from the GLSL,
// and the calls to it reach methods/common.glsl's function of the same name (pxh_height counts
// the fetch there), or its bridge below. The plug-in defines float2 pxh_method(float2 P).
float pxh_height(float2 uv) { return 0.0; }
float pxh_height_lod(float2 uv, float lod) { return 0.0; }
float pxh_height_grad(float2 uv, float2 dx, float2 dy) { return 0.0; }
int2 pxh_height_size(int lod) { return int2(1, 1); }
float pxh_z(float2 uv) { return 0.0; }
float pxh_z_top() { return 0.0; }
float pxh_z_bot() { return 0.0; }
float pxh_lod() { return 0.0; }
void pxh_write_hit(float z) {}
void pxh_write_engine_depth(float depth) {}
// The engine's height texture (height_sampler): NAME.Sample, SampleBias, SampleLevel,
// SampleGrad and Unity's SAMPLE_TEXTURE2D* macros on it become these.
float4 pxh_engine_height(float2 uv) { return float4(0.0, 0.0, 0.0, 0.0); }
float4 pxh_engine_height(float2 uv, float bias) { return float4(0.0, 0.0, 0.0, 0.0); }
float4 pxh_engine_height_lod(float2 uv, float lod) { return float4(0.0, 0.0, 0.0, 0.0); }
float4 pxh_engine_height_grad(float2 uv, float2 dx, float2 dy) { return float4(0.0, 0.0, 0.0, 0.0); }
// GLSL's globals, read through bridges (pxh_V is the sample's V, u_scale s, u_bias b,
// u_size the field's texels).
float3 pxh_hlsl_V() { return float3(0.0, 0.0, 1.0); }
float pxh_hlsl_scale() { return 0.0; }
float pxh_hlsl_bias() { return 0.0; }
int2 pxh_hlsl_size() { return int2(1, 1); }
#define pxh_V pxh_hlsl_V()
#define u_scale pxh_hlsl_scale()
#define u_bias pxh_hlsl_bias()
#define u_size pxh_hlsl_size()

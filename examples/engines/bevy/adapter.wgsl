// pxh's side: the material's parallax fields as a uniform (bound in the entry), P the uv, and
// Bevy's Vt, minus the toward-eye vector in a tangent frame whose B = -dP/dv (v down), where its
// (1, -1) flip cancels: (-V.x, V.y, -V.z) of pxh's V.
#import bevy_pbr::parallax_mapping parallaxed_uv

struct StandardMaterial {
    parallax_depth_scale: f32,
    max_parallax_layer_count: f32,
    max_relief_mapping_search_steps: u32,
}
@group(2) @binding(0) var<uniform> material: StandardMaterial;

fn pxh_method(P: vec2<f32>) -> vec2<f32> {
    let Vt = vec3<f32>(-pxh_V.x, pxh_V.y, -pxh_V.z);
    return parallaxed_uv(material.parallax_depth_scale, material.max_parallax_layer_count,
                         material.max_relief_mapping_search_steps, P, Vt);
}

// Bevy's StandardMaterial parallax in the style of bevy_pbr's render/parallax_mapping.wgsl
// (bevyengine/bevy @ 1cb1d0dc0fd5f4b3bd9c80ea3ec895c8955a4158), written for pxh from its
// description: a depth map (white = deep) read at level 0; layer_count =
// mix(max_layer_count, 1, |Vt.z|); the ray stepped by depth_scale / layer_count * Vt.xy * (1, -1)
// / |Vt.z| from the polygon down while the map is deeper than the ray, at most
// i32(layer_count) + 1 steps; then, with RELIEF_MAPPING, a bisection from the middle of the last
// step with max_steps probes, else (occlusion, Bevy's default) the previous layer fetched again
// and the uv interpolated between the two. naga_oil's directives as Bevy writes them.
#define_import_path bevy_pbr::parallax_mapping

#import bevy_pbr::pbr_bindings depth_map_texture, depth_map_sampler

fn sample_depth_map(uv: vec2<f32>) -> f32 {
    // Level 0 on purpose: no derivatives inside the loop.
    return textureSampleLevel(depth_map_texture, depth_map_sampler, uv, 0.0).r;
}

// Vt: from the camera to the fragment, in tangent space.
fn parallaxed_uv(depth_scale: f32, max_layer_count: f32, max_steps: u32,
                 original_uv: vec2<f32>, Vt: vec3<f32>) -> vec2<f32> {
    if max_layer_count < 1.0 {
        return original_uv;
    }
    var uv = original_uv;
    let view_steepness = abs(Vt.z);
    let layer_count = mix(max_layer_count, 1.0, view_steepness);
    let layer_depth = 1.0 / layer_count;
    var delta_uv = depth_scale * layer_depth * Vt.xy * vec2(1.0, -1.0) / view_steepness;

    // Steep search: while the map is deeper than the ray, one layer on.
    var current_layer_depth = 0.0;
    var texture_depth = sample_depth_map(uv);
    for (var i: i32 = 0; texture_depth > current_layer_depth && i <= i32(layer_count); i++) {
        current_layer_depth += layer_depth;
        uv += delta_uv;
        texture_depth = sample_depth_map(uv);
    }

#ifdef RELIEF_MAPPING
    // Relief: back to the middle of the last step, then max_steps halvings toward the surface.
    delta_uv *= 0.5;
    var delta_depth = 0.5 * layer_depth;
    uv -= delta_uv;
    current_layer_depth -= delta_depth;
    for (var i: u32 = 0u; i < max_steps; i++) {
        texture_depth = sample_depth_map(uv);
        delta_uv *= 0.5;
        delta_depth *= 0.5;
        if (texture_depth > current_layer_depth) {
            uv += delta_uv;
            current_layer_depth += delta_depth;
        } else {
            uv -= delta_uv;
            current_layer_depth -= delta_depth;
        }
    }
#else
    // Occlusion: interpolate with the previous layer, fetched again.
    let previous_uv = uv - delta_uv;
    let next_depth = texture_depth - current_layer_depth;
    let previous_depth = sample_depth_map(previous_uv) - current_layer_depth + layer_depth;
    let weight = next_depth / (next_depth - previous_depth);
    uv = mix(uv, previous_uv, weight);
#endif
    return uv;
}

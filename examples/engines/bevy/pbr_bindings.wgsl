// The bindings the parallax chunk imports (Bevy: bevy_pbr::pbr_bindings), the two it uses.
#define_import_path bevy_pbr::pbr_bindings

@group(2) @binding(1) var depth_map_texture: texture_2d<f32>;
@group(2) @binding(2) var depth_map_sampler: sampler;

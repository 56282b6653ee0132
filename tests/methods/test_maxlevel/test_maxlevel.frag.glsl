// test_maxlevel (tests/methods/test_maxlevel/test_maxlevel.cpp): a one-step offset to the
// level of the local maximum, read from precomputed textures.
uniform sampler2D r_maxmip;  // r32f, nearest, repeat, mip chain: cell max of the heights
uniform sampler2D r_zmap;    // rgba32f, linear, clamp: (s (h - b), h, 0, 1) per texel
uniform int p_level;
uniform int p_mode;          // 0 max, 1 mid, 2 zmap
vec2 pxh_method(vec2 P) {
    vec2 dir = pxh_V.xy * (1.0 / pxh_V.z);
    float z;
    if (p_mode == 2) {
        z = pxh_texture(r_zmap, P, p_level).r;
    } else {
        float m = pxh_texture(r_maxmip, P, p_level).r;
        if (p_mode == 1) m = (m + pxh_height(P)) * 0.5;
        z = u_scale * (m - u_bias);
    }
    return P + dir * z;
}

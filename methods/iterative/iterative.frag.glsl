// Iterative parallax mapping with slope information (methods/iterative/iterative.cpp):
// q = (uv, zeta) from (P, 0); k times q += (z(uv) - zeta) N_z V.
uniform sampler2D r_grad;  // rgba32f, linear, repeat: (dh/du, dh/dv, 0, 0)
uniform int p_iterations;
uniform bool p_slope;
vec2 pxh_method(vec2 P) {
    vec2 uv = P;
    float zeta = 0.0;
    for (int i = 0; i < p_iterations; ++i) {
        float z = pxh_z(uv);
        float nz = 1.0;
        if (p_slope) {
            vec4 g = pxh_texture(r_grad, uv, 0);
            float gx = u_scale * g.x, gy = u_scale * g.y;
            nz = 1.0 / sqrt(1.0 + gx * gx + gy * gy);
        }
        float d = (z - zeta) * nz;
        uv = uv + pxh_V.xy * d;
        zeta = zeta + pxh_V.z * d;
    }
    pxh_write_hit(zeta);
    return uv;
}

// qdm (Drobot, GPU Pro 2010, via FlightGear's transcription): the traversal and refinement of
// methods/qdm/qdm.h, the same operations in the same order, in float. One pxh_texture fetch of
// r_qdm per iteration, two pxh_height fetches in the refinement.
uniform sampler2D r_qdm;  // r32f, nearest, repeat, mip chain: max height per node
uniform int p_max_iterations;
uniform bool p_refine;
const float QDM_INF = uintBitsToFloat(0x7F800000u);  // +infinity

vec2 pxh_method(vec2 P) {
    vec2 dir = pxh_V.xy * (1.0 / pxh_V.z);
    vec2 p = P + dir * pxh_z_top();
    vec2 v = dir * (-u_scale);
    int W = u_size.x, H = u_size.y;
    float delta = 1.0 / float(2 * W) * u_scale;
    float sgx = v.x > 0.0 ? 1.0 : 0.0, sgy = v.y > 0.0 ? 1.0 : 0.0;
    vec2 p2 = p;
    float z2 = 0.0;
    int level = findMSB(max(W, H)), it = 0;
    while (level >= 0 && it < p_max_iterations) {
        float nodes_x = float(max(1, W >> level)), nodes_y = float(max(1, H >> level));
        float d = 1.0 - pxh_texture(r_qdm, p2, level).r;
        if (d > z2) {
            vec2 q = p + v * d;
            float nx = floor(p2.x * nodes_x), ny = floor(p2.y * nodes_y);
            float dn = d;
            if (nx != floor(q.x * nodes_x) || ny != floor(q.y * nodes_y)) {
                float bx = v.x != 0.0 ? ((nx + sgx) / nodes_x - p.x) / v.x : QDM_INF;
                float by = v.y != 0.0 ? ((ny + sgy) / nodes_y - p.y) / v.y : QDM_INF;
                dn = min(d, min(bx, by)) + delta;
                level += 1;
            }
            p2 = p + v * dn;
            z2 = dn;
        }
        level -= 1;
        it += 1;
    }
    pxh_write_hit(pxh_z_top() - u_scale * z2);
    if (!p_refine) return p2;
    float half_texel = 1.0 / float(2 * W);
    vec2 a = p2 - p;
    float len = sqrt(a.x * a.x + a.y * a.y) + half_texel * u_scale;
    float dA = z2 * (len - 2.0 * half_texel) / len;
    float dB = z2 * (len + 2.0 * half_texel) / len;
    vec2 pa = p + v * dA, pb = p + v * dB;
    float ea = abs(dA - (1.0 - pxh_height(pa)));
    float eb = abs(dB - (1.0 - pxh_height(pb)));
    if (!(ea + eb > 0.0)) return p2;
    float w = ea / (ea + eb);
    pxh_write_hit(pxh_z_top() - u_scale * (dA * (1.0 - w) + dB * w));
    return pa * (1.0 - w) + pb * w;
}

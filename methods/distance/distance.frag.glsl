// Donnelly 2005, GPU Gems 2 ch. 8 (methods/distance/distance.cpp): sphere tracing through the
// conservative distance map r_dist (an atlas of p_slices slices of u_size texels; nearest), the
// trilinear blend done here from 8 counted fetches.
uniform sampler2D r_dist;  // r32f, nearest: voxel units
uniform int p_iterations;
uniform int p_slices;
uniform int p_atlas_cols;

float pxh_voxel(int rows, int i, int j, int k) {
    int bx = k % p_atlas_cols, by = k / p_atlas_cols;
    float x = (float(bx * u_size.x + i) + 0.5) / float(p_atlas_cols * u_size.x);
    float y = (float(by * u_size.y + j) + 0.5) / float(rows * u_size.y);
    return pxh_texture(r_dist, vec2(x, y), 0).r;
}

float pxh_distance(vec2 uv, float Z) {
    int W = u_size.x, H = u_size.y, D = p_slices;
    int rows = (D + p_atlas_cols - 1) / p_atlas_cols;
    float X = (uv.x - floor(uv.x)) * float(W) - 0.5;
    float Y = (uv.y - floor(uv.y)) * float(H) - 0.5;
    float x0 = floor(X), y0 = floor(Y);
    float fx = X - x0, fy = Y - y0;
    int i0 = x0 < 0.0 ? W - 1 : int(x0), j0 = y0 < 0.0 ? H - 1 : int(y0);
    int i1 = i0 + 1 >= W ? 0 : i0 + 1, j1 = j0 + 1 >= H ? 0 : j0 + 1;
    float zc = clamp(Z - 0.5, 0.0, float(D - 1));
    int k0 = min(int(floor(zc)), D - 2);
    float fz = zc - float(k0);
    float s[2];
    for (int m = 0; m < 2; ++m) {
        int k = k0 + m;
        float t00 = pxh_voxel(rows, i0, j0, k);
        float t10 = pxh_voxel(rows, i1, j0, k);
        float t01 = pxh_voxel(rows, i0, j1, k);
        float t11 = pxh_voxel(rows, i1, j1, k);
        float a = t00 + (t10 - t00) * fx;
        float c = t01 + (t11 - t01) * fx;
        s[m] = a + (c - a) * fy;
    }
    return s[0] + (s[1] - s[0]) * fz;
}

vec2 pxh_method(vec2 P) {
    float D = float(p_slices);
    vec2 E = P + pxh_V.xy * (pxh_z_top() / pxh_V.z);
    float kz = pxh_V.z * D / u_scale;
    float ax = pxh_V.x * float(u_size.x), ay = pxh_V.y * float(u_size.y);
    float L = sqrt(ax * ax + ay * ay + kz * kz);
    float tau = 0.0;
    for (int it = 0; it < p_iterations; ++it) {
        vec2 uv = E - pxh_V.xy * tau;
        float Z = D - tau * kz;
        tau = tau + pxh_distance(uv, Z) / L;
    }
    pxh_write_hit(pxh_z_top() - pxh_V.z * tau);
    return E - pxh_V.xy * tau;
}

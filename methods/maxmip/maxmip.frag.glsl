// maxmip (Tevs, Ihrke, Seidel, I3D 2008): the traversal of methods/maxmip/maxmip.h, the same
// operations in the same order, in float. One pxh_texture fetch of r_maxmip per iteration.
uniform sampler2D r_maxmip;  // rgba32f, nearest, repeat, mip chain (level 0: cell corners)
uniform int p_max_iterations;
const float MM_INF = uintBitsToFloat(0x7F800000u);  // +infinity

int mm_floor_div(int a, int n) { return a >= 0 ? a / n : -((-a - 1) / n) - 1; }
int mm_nodes_at(int n, int L) { return max(1, n >> L); }
int mm_node_of(int l, int L, int n) { return min(l >> L, mm_nodes_at(n, L) - 1); }
int mm_node_end(int k, int L, int n) { return k == mm_nodes_at(n, L) - 1 ? n : (k + 1) << L; }

struct MmRay {
    float ex, ey, zt, vx, vy, vz, tau_max;
    float X0, Y0, dX, dY, inv_dX, inv_dY;
    int sx, sy;
};

MmRay mm_make_ray(vec2 P) {
    MmRay r;
    r.zt = pxh_z_top();
    r.vx = pxh_V.x;
    r.vy = pxh_V.y;
    r.vz = pxh_V.z;
    r.ex = P.x + pxh_V.x / pxh_V.z * r.zt;
    r.ey = P.y + pxh_V.y / pxh_V.z * r.zt;
    r.tau_max = u_scale / pxh_V.z;
    r.X0 = r.ex * float(u_size.x) - 0.5;
    r.Y0 = r.ey * float(u_size.y) - 0.5;
    r.dX = -pxh_V.x * float(u_size.x);
    r.dY = -pxh_V.y * float(u_size.y);
    r.inv_dX = r.dX != 0.0 ? 1.0 / r.dX : 0.0;
    r.inv_dY = r.dY != 0.0 ? 1.0 / r.dY : 0.0;
    r.sx = r.dX > 0.0 ? 1 : -1;
    r.sy = r.dY > 0.0 ? 1 : -1;
    return r;
}

vec2 mm_at(MmRay r, float tau) { return vec2(r.ex - tau * r.vx, r.ey - tau * r.vy); }

float mm_enter(MmRay r, int ci, int cj) {
    float t = 0.0;
    if (r.dX != 0.0) t = max(t, (float(r.sx > 0 ? ci : ci + 1) - r.X0) * r.inv_dX);
    if (r.dY != 0.0) t = max(t, (float(r.sy > 0 ? cj : cj + 1) - r.Y0) * r.inv_dY);
    return t;
}

float mm_first_root(float c0, float c1, float c2, float len) {
    if (c0 + (c1 + c2 * len) * len > 0.0 && (c2 <= 0.0 || c1 >= 0.0 || c1 + 2.0 * c2 * len <= 0.0))
        return -1.0;
    float best = -1.0;
    float scale = abs(c0) + abs(c1) * len + abs(c2) * len * len;
    float cand[2] = float[2](-1.0, -1.0);
    if (abs(c2) * len * len <= 1e-14 * scale) {
        if (c1 < 0.0) cand[0] = -c0 / c1;
    } else {
        float disc = c1 * c1 - 4.0 * c2 * c0;
        if (disc >= 0.0) {
            float root = sqrt(disc);
            float q = -0.5 * (c1 + (c1 >= 0.0 ? root : -root));
            if (q != 0.0) {
                cand[0] = q / c2;
                cand[1] = c0 / q;
            }
        }
    }
    for (int k = 0; k < 2; ++k) {
        float t = cand[k];
        if (t >= 0.0 && t <= len && (best < 0.0 || t < best)) best = t;
    }
    if (best < 0.0 && c0 + (c1 + c2 * len) * len <= 0.0) {
        float lo = 0.0, hi = len;
        for (int it = 0; it < 80; ++it) {
            float mid = 0.5 * (lo + hi);
            if (c0 + (c1 + c2 * mid) * mid > 0.0) lo = mid;
            else hi = mid;
        }
        best = hi;
    }
    return best;
}

float mm_solve_cell(MmRay r, vec4 f, int ci, int cj, float tau_out) {
    float tau_in = mm_enter(r, ci, cj);
    float fx0 = r.X0 + tau_in * r.dX - float(ci), fy0 = r.Y0 + tau_in * r.dY - float(cj);
    float A = f.y - f.x, B = f.z - f.x, C = f.x - f.y - f.z + f.w;
    float h0 = f.x + A * fx0 + B * fy0 + C * fx0 * fy0;
    float h1 = A * r.dX + B * r.dY + C * (fx0 * r.dY + fy0 * r.dX);
    float h2 = C * r.dX * r.dY;
    float c0 = (r.zt - tau_in * r.vz) - u_scale * (h0 - u_bias);
    if (c0 <= 0.0) return tau_in;
    float t = mm_first_root(c0, -r.vz - u_scale * h1, -u_scale * h2, tau_out - tau_in);
    return t >= 0.0 ? tau_in + t : -1.0;
}

// Unwrapped parent node (level L + 1) of cell (ci, cj).
ivec2 mm_parent(int ci, int cj, int L) {
    int W = u_size.x, H = u_size.y;
    int ti = mm_floor_div(ci, W), tj = mm_floor_div(cj, H);
    return ivec2(ti * mm_nodes_at(W, L + 1) + mm_node_of(ci - ti * W, L + 1, W),
                 tj * mm_nodes_at(H, L + 1) + mm_node_of(cj - tj * H, L + 1, H));
}

vec2 pxh_method(vec2 P) {
    MmRay r = mm_make_ray(P);
    int W = u_size.x, H = u_size.y, top = findMSB(max(W, H));
    float travel = r.tau_max * max(abs(r.dX), abs(r.dY));
    int L = clamp(findMSB(max(int(min(travel, 1e9)), 1)), 0, top);
    int ci = int(floor(r.X0)), cj = int(floor(r.Y0));
    float tau_cur = 0.0;
    float t_out = r.tau_max;
    bool done = false;
    for (int it = 0; !done && it < p_max_iterations; ++it) {
        int ti = mm_floor_div(ci, W), tj = mm_floor_div(cj, H);
        int nx = mm_node_of(ci - ti * W, L, W), ny = mm_node_of(cj - tj * H, L, H);
        int x0 = ti * W + (nx << L), x1 = ti * W + mm_node_end(nx, L, W);
        int y0 = tj * H + (ny << L), y1 = tj * H + mm_node_end(ny, L, H);
        float ex = r.dX != 0.0 ? (float(r.sx > 0 ? x1 : x0) - r.X0) * r.inv_dX : MM_INF;
        float ey = r.dY != 0.0 ? (float(r.sy > 0 ? y1 : y0) - r.Y0) * r.inv_dY : MM_INF;
        float tau_out = min(min(ex, ey), r.tau_max);
        vec2 uv = vec2((float(nx) + 0.5) / float(mm_nodes_at(W, L)),
                       (float(ny) + 0.5) / float(mm_nodes_at(H, L)));
        vec4 f = pxh_texture(r_maxmip, uv, L);
        float z_block = u_scale * (max(max(f.x, f.y), max(f.z, f.w)) - u_bias);
        if (r.zt - tau_out * r.vz <= z_block) {
            if (L > 0) {
                float t_cross = (r.zt - z_block) / r.vz;
                if (t_cross > tau_cur) {
                    tau_cur = t_cross;
                    ci = clamp(int(floor(r.X0 + t_cross * r.dX)), x0, x1 - 1);
                    cj = clamp(int(floor(r.Y0 + t_cross * r.dY)), y0, y1 - 1);
                }
                L -= 1;
                continue;
            }
            float t = mm_solve_cell(r, f, ci, cj, tau_out);
            if (t >= 0.0) {
                t_out = t;
                done = true;
                continue;
            }
        }
        if (tau_out >= r.tau_max) {
            done = true;
            continue;
        }
        tau_cur = tau_out;
        int nci = ci, ncj = cj;
        if (ex <= ey) {
            nci = r.sx > 0 ? x1 : x0 - 1;
            if (L > 0) ncj = clamp(int(floor(r.Y0 + ex * r.dY)), y0, y1 - 1);
        } else {
            ncj = r.sy > 0 ? y1 : y0 - 1;
            if (L > 0) nci = clamp(int(floor(r.X0 + ey * r.dX)), x0, x1 - 1);
        }
        if (L < top && mm_parent(nci, ncj, L) != mm_parent(ci, cj, L)) L += 1;
        ci = nci;
        cj = ncj;
    }
    if (!done) t_out = tau_cur;
    pxh_write_hit(r.zt - t_out * r.vz);
    return mm_at(r, t_out);
}

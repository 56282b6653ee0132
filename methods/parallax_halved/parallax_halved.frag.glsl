// Pixel-offset paper sec. 3.2: P + 0.5 z(P) V.xy / V.z.
vec2 pxh_method(vec2 P) { return P + pxh_V.xy * (0.5 * pxh_z(P) / pxh_V.z); }

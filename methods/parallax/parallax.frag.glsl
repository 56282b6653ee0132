// Kaneko et al. 2001; Welsh 2004 sec. 4.1: P + z(P) V.xy / V.z.
vec2 pxh_method(vec2 P) { return P + pxh_V.xy * (pxh_z(P) / pxh_V.z); }

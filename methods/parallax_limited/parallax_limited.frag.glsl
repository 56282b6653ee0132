// Welsh 2004 sec. 4.3 (offset limiting): P + z(P) V.xy.
vec2 pxh_method(vec2 P) { return P + pxh_V.xy * pxh_z(P); }

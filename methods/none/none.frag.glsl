// Plain texture mapping (baseline).
vec2 pxh_method(vec2 P) { return P; }

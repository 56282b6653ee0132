#!/usr/bin/env python3
# Writes results/experiments/engines.toml: scripts/make_engines_toml.py $(build/pxh list methods | grep -E "^[a-z_0-9]+  --" | cut -d" " -f1) > results/experiments/engines.toml
# (the presets named on the command line are the ones that exist; the groups below give each engine's default s and b).
# engines.toml: every engine preset at its engine's defaults (scale, bias) on a procedural and a
# measured field; theta 0..85; both backends.
groups = [  # (s, b, presets, how s follows from the engine's default)
 (0.005, 1.0, ["threejs_basic","threejs_steep","threejs_occlusion","threejs_relief"], "three.js example: parallaxScale 0.005 (as a depth map)"),
 (0.05, 0.0, ["babylon_parallax"], "Babylon.js parallaxScaleBias 0.05, parallax offset (b = 0)"),
 (0.05, 1.0, ["babylon_pom","godot_parallax","godot_deep","o3de_basic","o3de_steep","o3de_pom","o3de_relief","o3de_contact"], "Babylon.js POM 0.05; Godot heightmap_scale 5 x 0.01; O3DE factor 0.05"),
 (0.025, 0.5, ["playcanvas_basic_v2_21"], "PlayCanvas 2.21 heightMapFactor 1 x 0.025"),
 (0.1, 0.5, ["playcanvas_occlusion"], "PlayCanvas occlusion: heightMapFactor 1 x 0.1, heightMapBase 0.5"),
 (0.1, 1.0, ["bevy_occlusion","bevy_relief"], "Bevy parallax_depth_scale 0.1"),
 (0.02, 0.5, ["unity_parallax_offset"], "Unity Standard _Parallax 0.02"),
 (0.02, 1.0, ["hdrp_pom","dxsdk_pom"], "HDRP _HeightPoMAmplitude 2 cm; DirectX SDK g_fHeightMapScale 0.02"),
 (0.05, 0.6, ["jme_parallax"], "jMonkeyEngine ParallaxHeight 0.05 (classic, b = 0.6)"),
 (0.015, 1.0, ["jme_steep"], "jMonkeyEngine steep: 0.3 x ParallaxHeight 0.05"),
 (0.04, 1.0, ["ogre_parallax","ogre_pom"], "OGRE RTSS height_scale 0.04"),
]
# Presets whose entry sets a knob away from its default, with why (a comment above the entry).
EXTRA = {
 "dxsdk_pom": ("# As shipped the sample never sets g_vTextureDims, so its mip level is always 0 and its LOD\n"
               "# blend never runs: g_nLODThreshold 16 keeps the preset there (at jacksboro's level 2.65 under\n"
               "# this grid the default 3 would blend towards P; docs/guide/engines.md, \"Texture levels\").\n",
               "g_nLODThreshold = 16\n"),
}
import sys
have = set(sys.argv[1:])  # presets that exist
out = ['''# What engines ship: every engine preset at its engine's defaults (methods/march/presets/*.cpp;
# docs/findings/engines.md). Each preset runs on a procedural (bricks) and a
# measured (jacksboro) field at its engine's default height scale s and reference plane b
# ([[methods]] heightfields = [...] pairs them), theta 0-85, on the CPU reference and as GLSL.
name = "engines"
description = "engine parallax presets at engine defaults x bricks, jacksboro x theta 0-85"
samples = 128
backends = ["cpu", "glsl"]
precision = "float"
timing_repeats = 3

[views]
theta_deg = { from = 0, to = 85, step = 5 }
phi_deg = [30]
''']
methods = []
for s, b, presets, why in groups:
    presets = [p for p in presets if p in have]
    if not presets: continue
    names = []
    for field, spec in (("bricks", 'generator = "bricks"\nsize = 256'), ("jacksboro", 'scan = "jacksboro"')):
        name = f"{field}-s{s:g}-b{b:g}"
        names.append(name)
        out.append(f'# {why}\n[[heightfields]]\nname = "{name}"\n{spec}\nscale = {s:g}\nbias = {b:.1f}\n')
    for p in presets:
        why_extra, extra = EXTRA.get(p, ("", ""))
        methods.append(f'{why_extra}[[methods]]\nname = "{p}"\nheightfields = [{", ".join(chr(34)+n+chr(34) for n in names)}]\n{extra}')
print("\n".join(out + methods), end="")

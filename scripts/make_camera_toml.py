#!/usr/bin/env python3
# Writes results/experiments/camera.toml:
#   scripts/make_camera_toml.py $(build/pxh list methods | grep -E "^[a-z_0-9]+  --" | cut -d" " -f1) > results/experiments/camera.toml
# The seed methods and every engine preset (at its engine's default s and b, the groups of
# scripts/make_engines_toml.py, read from that file) on the measured field jacksboro, seen
# through the perspective camera from 1 to 32 tiles away at theta 45/70/80, in every level mode.
import ast
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
src = open(os.path.join(here, "make_engines_toml.py"), encoding="utf-8").read()
groups = next(ast.literal_eval(n.value) for n in ast.parse(src).body
              if isinstance(n, ast.Assign) and getattr(n.targets[0], "id", "") == "groups")
SEEDS = ["parallax", "parallax_limited", "steep", "pom", "relief"]  # at s = 0.05, b = 1
have = set(sys.argv[1:])  # methods that exist
out = ['''# Seen through a camera (docs/findings/camera.md): the
# seed methods and every engine preset at its engine's defaults on the measured field jacksboro,
# a perspective camera from 1 to 32 tiles away, theta 45/70/80, each setting with its height read
# at level 0 (base), at the pixel's level (level) and, on GLSL, through textureGrad (grad) and
# texture()'s own derivatives (implicit). Written by scripts/make_camera_toml.py.
name = "camera"
description = "seed methods and engine presets x perspective distance 1-32 x theta 45/70/80 x lod"
samples = 128
backends = ["cpu", "glsl"]
precision = "float"
timing_repeats = 1

[views]
theta_deg = [45, 70, 80]
phi_deg = [30]
camera = "perspective"
distance = [1, 2, 4, 8, 16, 32]
fov_deg = 45
''']
methods = []
LOD = 'lod = ["base", "level", "grad", "implicit"]'
seeded = False
for s, b, presets, why in groups:
    presets = [p for p in presets if p in have]
    seeds = [m for m in SEEDS if m in have] if (s, b) == (0.05, 1.0) and not seeded else []
    if not presets and not seeds:
        continue
    seeded = seeded or bool(seeds)
    name = f"jacksboro-s{s:g}-b{b:g}"
    out.append(f'# {why}\n[[heightfields]]\nname = "{name}"\nscan = "jacksboro"\nscale = {s:g}\n'
               f'bias = {b:.1f}\n')
    for m in seeds + presets:
        params = 'layers = 32\n' if m in ("steep", "pom", "relief") else ""
        methods.append(f'[[methods]]\nname = "{m}"\n{params}{LOD}\nheightfields = ["{name}"]\n')
print("\n".join(out + methods), end="")

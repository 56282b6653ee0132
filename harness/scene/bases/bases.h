// What a base's file includes (one file per base in this folder; registry.cpp lists them, each
// with its factory's declaration beside its line).
#pragma once
#include "harness/scene/base_surface.h"

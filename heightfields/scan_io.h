// Readers for the scanned sources: NumPy .npz/.npy arrays, PLY point clouds, OFF meshes.
#pragma once
#include <array>
#include <string>
#include <vector>

namespace pxh {

struct NpyArray {
    std::vector<size_t> shape;  // row-major (C order)
    std::vector<double> values;
};

// One array from an .npz archive (stored or deflated members); throws InputError.
NpyArray read_npz_array(const std::string& path, const std::string& member);

// Vertex positions of a PLY file (ascii or binary_little_endian; x, y, z as float or double).
std::vector<std::array<double, 3>> read_ply_points(const std::string& path);

struct Mesh {
    std::vector<std::array<double, 3>> vertices;
    std::vector<std::array<unsigned, 3>> triangles;  // polygons fanned into triangles
};
// An ASCII OFF mesh.
Mesh read_off(const std::string& path);

}  // namespace pxh

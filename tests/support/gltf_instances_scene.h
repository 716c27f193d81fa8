#pragma once
// A small glTF scene whose nodes share a mesh, for the loader's instancing tests (unit and CLI):
// mesh 0 (a tetrahedron, material "red", and a square, "green") is placed by three nodes, two
// of them under a parent with a rotation and an anisotropic scale, the third through a 4x4 matrix
// that mirrors and shears; mesh 1 (a square, "blue") is placed once, as a ground.
#include <cstdint>
#include <string>
#include <vector>

namespace thicket::testing {

/// The binary buffer the JSON of gltf_instances_json() refers to (132 bytes).
inline std::string gltf_instances_buffer() {
    std::string b;
    auto f = [&](std::initializer_list<float> values) {
        for (float v : values) b.append(reinterpret_cast<const char*>(&v), 4);
    };
    auto u16 = [&](std::initializer_list<uint16_t> values) {
        for (uint16_t v : values) b.append(reinterpret_cast<const char*>(&v), 2);
    };
    f({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1});            // 0: tetrahedron corners
    u16({0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3});           // 48: its four faces
    f({0, 0, -0.5f, 1, 0, -0.5f, 1, 1, -0.5f, 0, 1, -0.5f});  // 72: square corners
    u16({0, 1, 2, 0, 2, 3});                             // 120: its two triangles
    return b;
}

/// The glTF JSON; `extra_nodes` (node objects) are appended to the nodes and to the scene's
/// roots after the five above, numbered from 5, for variants of the scene.
inline std::string gltf_instances_json(const std::string& buffer_uri, const std::vector<std::string>& extra_nodes = {}) {
    std::string roots = "0, 3, 4", nodes;
    for (size_t i = 0; i < extra_nodes.size(); ++i) {
        roots += ", " + std::to_string(5 + i);
        nodes += ",\n            " + extra_nodes[i];
    }
    return R"({"asset": {"version": "2.0"}, "scene": 0,
  "scenes": [{"nodes": [)" + roots + R"(]}],
  "nodes": [{"translation": [3, 0, 0], "rotation": [0, 0, 0.38268343, 0.92387953], "scale": [1, 2, 1], "children": [1, 2]},
            {"mesh": 0, "translation": [0, 1, 0]},
            {"mesh": 0, "rotation": [0.5, 0.5, 0.5, 0.5], "scale": [0.5, 0.5, 0.5], "translation": [1, 0, 2]},
            {"mesh": 0, "matrix": [-1, 0, 0, 0, 0, 1, 0, 0, 0, 0.3, 1, 0, -3, 0, 0, 1]},
            {"mesh": 1, "translation": [0, -1, 0], "rotation": [-0.70710678, 0, 0, 0.70710678], "scale": [10, 10, 1]})" +
           nodes + R"(],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0},
                             {"attributes": {"POSITION": 2}, "indices": 3, "material": 1}]},
             {"primitives": [{"attributes": {"POSITION": 2}, "indices": 3, "material": 2}]}],
  "materials": [{"name": "red", "pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1]}},
                {"name": "green", "pbrMetallicRoughness": {"baseColorFactor": [0, 1, 0, 1]}},
                {"name": "blue", "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 1, 1]}}],
  "buffers": [{"uri": ")" + buffer_uri + R"(", "byteLength": 132}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                  {"buffer": 0, "byteOffset": 48, "byteLength": 24},
                  {"buffer": 0, "byteOffset": 72, "byteLength": 48},
                  {"buffer": 0, "byteOffset": 120, "byteLength": 12}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3"},
                {"bufferView": 1, "componentType": 5123, "count": 12, "type": "SCALAR"},
                {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC3"},
                {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}]})";
}

}  // namespace thicket::testing

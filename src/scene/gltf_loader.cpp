// glTF 2.0 (.gltf and .glb) through tinygltf. tinygltf parses the JSON and loads the buffers;
// every index, offset, stride and count it hands back is checked here before memory is touched,
// because it does not bound accessors by their buffers itself.
//
// Debian's libtinygltf.so already contains the implementation (and stb_image), so this file
// must not define TINYGLTF_IMPLEMENTATION.
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <tiny_gltf.h>

#include "gltf_materials.h"
#include "thicket/core/error.h"
#include "thicket/scene/loaders.h"
#include "thicket/util/input_file.h"

namespace thicket {
namespace {

using Mat4 = std::array<double, 16>;  ///< column-major, as glTF stores it

constexpr Mat4 identity() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; }

Mat4 multiply(const Mat4& a, const Mat4& b) {
    Mat4 r{};
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row) {
            double s = 0;
            for (int k = 0; k < 4; ++k) s += a[k * 4 + row] * b[c * 4 + k];
            r[c * 4 + row] = s;
        }
    return r;
}

Vec3 transform_point(const Mat4& m, const float p[3]) {
    const double x = p[0], y = p[1], z = p[2];
    return {float(m[0] * x + m[4] * y + m[8] * z + m[12]), float(m[1] * x + m[5] * y + m[9] * z + m[13]),
            float(m[2] * x + m[6] * y + m[10] * z + m[14])};
}

/// Images are not needed for geometry; skipping their decoding keeps loads fast and lets a
/// file with unreadable textures still load.
bool ignore_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*,
                  int, void*) {
    return true;
}

std::string one_line(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' ')) s.pop_back();
    for (char& c : s)
        if (c == '\n') c = ';';
    return s;
}

size_t component_size(int type) {
    switch (type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
        case TINYGLTF_COMPONENT_TYPE_INT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
        default: return 0;
    }
}

/// A bounds-checked strided view of an accessor's elements.
struct View {
    const unsigned char* base = nullptr;
    size_t stride = 0;
    size_t count = 0;
    const unsigned char* at(size_t i) const { return base + i * stride; }
};

class GltfReader {
public:
    GltfReader(const std::string& path, const tinygltf::Model& model) : path_(path), model_(model) {}

    /// The geometry as one triangle soup: every node's meshes with its world transform applied,
    /// in traversal order, with `materials` (gltf::read_materials of the same file) as its materials.
    TriangleMesh read_flat(std::vector<Material> materials) {
        set_materials(std::move(materials));
        TriangleMesh mesh;
        for (const Placement& p : placements()) add_mesh_triangles(p.mesh, &p.world, mesh);
        mesh.materials = materials_;
        return mesh;
    }

    /// The geometry as a scene: flattened as read_flat() when `flatten` or when no mesh is placed
    /// twice; otherwise instanced (docs/shapes.md, "glTF scenes"): geometry 0 holds the meshes placed
    /// once, flattened, under an identity instance (instance 0); each mesh placed by several nodes
    /// is one more geometry in its own space, with one instance per node in traversal order.
    /// A node whose transform instancing refuses (near-singular, checked_inverse) is flattened.
    Scene read_scene(std::vector<Material> materials, bool flatten) {
        Scene scene;
        scene.name = path_;
        set_materials(std::move(materials));
        const std::vector<Placement> places = placements();
        std::vector<uint32_t> uses(model_.meshes.size(), 0);
        for (const Placement& p : places) ++uses[size_t(p.mesh)];

        // A mesh placed twice or more, read once in its own space; empty ones (points, lines)
        // draw nothing and are never instanced.
        std::vector<TriangleMesh> local(model_.meshes.size());
        std::vector<char> shared(model_.meshes.size(), 0);
        if (!flatten)
            for (size_t m = 0; m < uses.size(); ++m)
                if (uses[m] >= 2) {
                    add_mesh_triangles(int(m), nullptr, local[m]);
                    shared[m] = local[m].triangle_count() > 0;
                }
        std::vector<char> instanced(places.size(), 0);
        std::vector<Affine> transforms(places.size());
        bool any = false;
        for (size_t i = 0; i < places.size(); ++i) {
            if (!shared[size_t(places[i].mesh)]) continue;
            transforms[i] = affine_of(places[i].world);
            // NaN (a non-finite entry) fails the comparison too.
            instanced[i] = transform_condition(transforms[i]) <= kMaxTransformCondition;
            any = any || instanced[i];
        }
        TriangleMesh rest;
        for (size_t i = 0; i < places.size(); ++i)
            if (!instanced[i]) add_mesh_triangles(places[i].mesh, &places[i].world, rest);
        if (!any) {
            rest.materials = materials_;
            scene.mesh = std::move(rest);
            return scene;
        }

        // Materials are set once at the end: add_mesh would copy the whole table per geometry.
        std::vector<uint32_t> material_ids;
        auto add = [&](TriangleMesh& m) {
            material_ids.insert(material_ids.end(), m.material_ids.begin(), m.material_ids.end());
            m.material_ids.clear();
            return scene.add_mesh(m);
        };
        if (rest.triangle_count() > 0) scene.add_instance(add(rest), Affine{});
        std::vector<uint32_t> geometry_of_mesh(model_.meshes.size(), kNoPrim);
        for (size_t i = 0; i < places.size(); ++i) {
            if (!instanced[i]) continue;
            uint32_t& g = geometry_of_mesh[size_t(places[i].mesh)];
            if (g == kNoPrim) g = add(local[size_t(places[i].mesh)]);
            scene.add_instance(g, transforms[i]);
        }
        if (!materials_.empty()) {
            scene.mesh.materials = materials_;
            scene.mesh.material_ids = std::move(material_ids);
        }
        return scene;
    }

private:
    [[noreturn]] void fail(const std::string& what) const { throw Error(path_ + ": " + what); }

    /// One node that draws a mesh, with its world transform.
    struct Placement {
        int mesh = -1;
        Mat4 world{};
    };

    void set_materials(std::vector<Material> materials) {
        if (materials.size() != model_.materials.size())
            fail("the JSON has " + std::to_string(materials.size()) + " materials but tinygltf read " +
                 std::to_string(model_.materials.size()));
        materials_ = std::move(materials);
    }

    /// Every node of the scene that has a mesh, depth first from the roots, children in order.
    std::vector<Placement> placements() {
        visited_.assign(model_.nodes.size(), 0);
        std::vector<Placement> out;
        for (int root : roots()) walk(root, out);
        return out;
    }

    /// The 3x4 top of a column-major affine glTF matrix (its last row is 0 0 0 1 for every
    /// transform glTF allows).
    static Affine affine_of(const Mat4& m) {
        Affine a;
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) a.m[r][c] = float(m[size_t(c * 4 + r)]);
        return a;
    }

    /// The default scene, else scene 0, else every node that is nobody's child.
    std::vector<int> roots() const {
        if (!model_.scenes.empty()) {
            const int s = model_.defaultScene >= 0 ? model_.defaultScene : 0;
            if (size_t(s) >= model_.scenes.size())
                fail("default scene " + std::to_string(s) + " does not exist");
            return model_.scenes[size_t(s)].nodes;
        }
        std::vector<char> is_child(model_.nodes.size(), 0);
        for (const tinygltf::Node& n : model_.nodes)
            for (int c : n.children)
                if (c >= 0 && size_t(c) < is_child.size()) is_child[size_t(c)] = 1;
        std::vector<int> out;
        for (size_t i = 0; i < is_child.size(); ++i)
            if (!is_child[i]) out.push_back(int(i));
        return out;
    }

    Mat4 local_transform(const tinygltf::Node& n, int index) const {
        const std::string where = "node " + std::to_string(index);
        if (!n.matrix.empty()) {
            if (n.matrix.size() != 16) fail(where + ": matrix must have 16 numbers");
            Mat4 m;
            std::copy(n.matrix.begin(), n.matrix.end(), m.begin());
            return m;
        }
        if (!n.translation.empty() && n.translation.size() != 3)
            fail(where + ": translation must have 3 numbers");
        if (!n.rotation.empty() && n.rotation.size() != 4) fail(where + ": rotation must have 4 numbers");
        if (!n.scale.empty() && n.scale.size() != 3) fail(where + ": scale must have 3 numbers");
        double t[3] = {0, 0, 0}, q[4] = {0, 0, 0, 1}, s[3] = {1, 1, 1};
        std::copy(n.translation.begin(), n.translation.end(), t);
        std::copy(n.rotation.begin(), n.rotation.end(), q);
        std::copy(n.scale.begin(), n.scale.end(), s);
        // Exporters write slightly denormalized quaternions; normalizing keeps R a rotation.
        const double len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        if (len > 0)
            for (double& c : q) c /= len;
        const double x = q[0], y = q[1], z = q[2], w = q[3];
        const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                                {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                                {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
        Mat4 m = identity();  // T * R * S
        for (int c = 0; c < 3; ++c)
            for (int row = 0; row < 3; ++row) m[c * 4 + row] = r[row][c] * s[c];
        for (int row = 0; row < 3; ++row) m[12 + row] = t[row];
        return m;
    }

    /// Depth-first, children in order, with an explicit stack: a deep (corrupt) hierarchy cannot
    /// overflow the call stack, and each node may be entered once, which also rejects cycles.
    void walk(int root, std::vector<Placement>& out) {
        std::vector<std::pair<int, Mat4>> stack{{root, identity()}};
        while (!stack.empty()) {
            auto [index, parent] = stack.back();
            stack.pop_back();
            if (index < 0 || size_t(index) >= model_.nodes.size())
                fail("node " + std::to_string(index) + " does not exist");
            if (visited_[size_t(index)])
                fail("node " + std::to_string(index) + " is reached twice (nodes must form a tree)");
            visited_[size_t(index)] = 1;
            const tinygltf::Node& node = model_.nodes[size_t(index)];
            const Mat4 world = multiply(parent, local_transform(node, index));
            if (node.mesh >= 0) {
                if (size_t(node.mesh) >= model_.meshes.size())
                    fail("node " + std::to_string(index) + ": mesh " + std::to_string(node.mesh) +
                         " does not exist");
                out.push_back({node.mesh, world});
            }
            for (auto it = node.children.rbegin(); it != node.children.rend(); ++it)
                stack.push_back({*it, world});
        }
    }

    /// Appends every primitive of mesh `index` to `out`, its vertices carried by `world` (kept as
    /// they are in the file when null).
    void add_mesh_triangles(int index, const Mat4* world, TriangleMesh& out) {
        const tinygltf::Mesh& mesh = model_.meshes[size_t(index)];
        for (size_t p = 0; p < mesh.primitives.size(); ++p)
            add_primitive(mesh.primitives[p], world, "mesh " + std::to_string(index) + " primitive " + std::to_string(p),
                          out);
    }

    /// Resolves an accessor to a strided view after checking it lies inside its buffer.
    View view(int accessor, int want_type, const std::string& where) const {
        if (accessor < 0 || size_t(accessor) >= model_.accessors.size())
            fail(where + ": accessor " + std::to_string(accessor) + " does not exist");
        const tinygltf::Accessor& a = model_.accessors[size_t(accessor)];
        const std::string what = where + ", accessor " + std::to_string(accessor);
        if (a.sparse.isSparse) fail(what + ": sparse accessors are not supported");
        if (a.type != want_type) fail(what + ": unexpected element type " + std::to_string(a.type));
        const size_t elem = component_size(a.componentType) * size_t(want_type == TINYGLTF_TYPE_VEC3 ? 3 : 1);
        if (elem == 0) fail(what + ": unsupported component type " + std::to_string(a.componentType));
        View v;
        v.count = a.count;
        if (a.count == 0) return v;
        if (a.bufferView < 0 || size_t(a.bufferView) >= model_.bufferViews.size())
            fail(what + ": buffer view " + std::to_string(a.bufferView) + " does not exist");
        const tinygltf::BufferView& bv = model_.bufferViews[size_t(a.bufferView)];
        if (bv.buffer < 0 || size_t(bv.buffer) >= model_.buffers.size())
            fail(what + ": buffer " + std::to_string(bv.buffer) + " does not exist");
        const std::vector<unsigned char>& data = model_.buffers[size_t(bv.buffer)].data;
        if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
            fail(what + ": buffer view " + std::to_string(a.bufferView) + " lies outside its buffer");
        v.stride = bv.byteStride != 0 ? bv.byteStride : elem;
        if (v.stride < elem)
            fail(what + ": byteStride " + std::to_string(v.stride) + " is smaller than an element");
        const size_t room = bv.byteLength;
        if (a.byteOffset > room || elem > room - a.byteOffset ||
            (a.count - 1) > (room - a.byteOffset - elem) / v.stride)
            fail(what + ": " + std::to_string(a.count) + " elements do not fit in buffer view " +
                 std::to_string(a.bufferView));
        v.base = data.data() + bv.byteOffset + a.byteOffset;
        return v;
    }

    uint32_t material_for(int gltf_material, const std::string& where) {
        if (gltf_material >= 0) {
            if (size_t(gltf_material) >= model_.materials.size())
                fail(where + ": material " + std::to_string(gltf_material) + " does not exist");
            return uint32_t(gltf_material);
        }
        if (model_.materials.empty()) return no_material;
        if (default_material_ == no_material) {
            default_material_ = uint32_t(materials_.size());
            Material fallback;
            fallback.name = "default";
            materials_.push_back(fallback);
        }
        return default_material_;
    }

    void add_primitive(const tinygltf::Primitive& prim, const Mat4* world, const std::string& where,
                       TriangleMesh& out) {
        if (prim.mode < TINYGLTF_MODE_TRIANGLES) return;  // points and lines carry no surface
        if (prim.mode > TINYGLTF_MODE_TRIANGLE_FAN)
            fail(where + ": unknown mode " + std::to_string(prim.mode));
        const auto pos_it = prim.attributes.find("POSITION");
        if (pos_it == prim.attributes.end()) fail(where + ": no POSITION attribute");
        const View pos = view(pos_it->second, TINYGLTF_TYPE_VEC3, where + " POSITION");
        const int pos_type =
            model_.accessors[size_t(pos_it->second)].componentType;  // index checked by view()
        if (pos_type != TINYGLTF_COMPONENT_TYPE_FLOAT)
            fail(where + ": POSITION must be float (component type " + std::to_string(pos_type) + ")");

        const size_t base = out.positions.size();
        if (pos.count > std::numeric_limits<uint32_t>::max() - base) fail(where + ": too many vertices");
        // No exact reserve(base + count) here: with N nodes sharing a mesh it reallocated the whole
        // array for every node, O(N^2); push_back's geometric growth keeps loading linear.
        for (size_t i = 0; i < pos.count; ++i) {
            float p[3];
            std::memcpy(p, pos.at(i), sizeof p);
            out.positions.push_back(world ? transform_point(*world, p) : Vec3{p[0], p[1], p[2]});
        }

        std::vector<uint32_t> idx;
        if (prim.indices >= 0) {
            const View iv = view(prim.indices, TINYGLTF_TYPE_SCALAR, where + " indices");
            const int ct = model_.accessors[size_t(prim.indices)].componentType;
            if (ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
                fail(where + ": index component type " + std::to_string(ct) +
                     " is not ubyte, ushort or uint");
            idx.resize(iv.count);
            for (size_t i = 0; i < iv.count; ++i) {
                uint32_t value = 0;
                if (ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
                    value = *iv.at(i);
                } else if (ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
                    uint16_t s;
                    std::memcpy(&s, iv.at(i), 2);
                    value = s;
                } else {
                    std::memcpy(&value, iv.at(i), 4);
                }
                if (value >= pos.count)
                    fail(where + ": index " + std::to_string(value) + " is out of range (" +
                         std::to_string(pos.count) + " vertices)");
                idx[i] = value;
            }
        } else {
            idx.resize(pos.count);
            for (size_t i = 0; i < pos.count; ++i) idx[i] = uint32_t(i);
        }

        const uint32_t material = material_for(prim.material, where);
        auto emit = [&](uint32_t a, uint32_t b, uint32_t c) {
            out.indices.push_back(uint32_t(base) + a);
            out.indices.push_back(uint32_t(base) + b);
            out.indices.push_back(uint32_t(base) + c);
        };
        const size_t n = idx.size();
        if (prim.mode == TINYGLTF_MODE_TRIANGLES) {
            for (size_t i = 0; i + 2 < n; i += 3) emit(idx[i], idx[i + 1], idx[i + 2]);
        } else if (prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
            // Every other triangle swaps its last two corners to keep the strip's winding.
            for (size_t i = 0; i + 2 < n; ++i) {
                if (i % 2 == 0)
                    emit(idx[i], idx[i + 1], idx[i + 2]);
                else
                    emit(idx[i], idx[i + 2], idx[i + 1]);
            }
        } else {
            for (size_t i = 1; i + 1 < n; ++i) emit(idx[0], idx[i], idx[i + 1]);
        }
        if (material != no_material) out.material_ids.resize(out.triangle_count(), material);
    }

    static constexpr uint32_t no_material = uint32_t(-1);

    const std::string& path_;
    const tinygltf::Model& model_;
    std::vector<Material> materials_;  ///< the file's, then the default one if a primitive needs it
    std::vector<char> visited_;
    uint32_t default_material_ = no_material;
};

// The files a glTF names (buffers, images) are read like every input: regular files only, their
// size checked against memory (a `uri: "."` made tinygltf ask for the size of a directory, which
// ended in std::bad_alloc). Paths are used as written: no ~ or $VAR expansion.
bool read_referenced_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
    try {
        const std::string bytes = read_input_file(path, "glTF buffer");
        out->assign(bytes.begin(), bytes.end());
        return true;
    } catch (const Error& e) {
        if (err) *err += e.what();
        return false;
    }
}

bool referenced_file_exists(const std::string& path, void*) {
    std::error_code ec;
    return std::filesystem::exists(path, ec);
}

std::string path_as_written(const std::string& path, void*) { return path; }

bool has_extension(const std::string& path, const char* ext) {
    std::string e = std::filesystem::path(path).extension().string();
    for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
    return e == ext;
}

/// A parsed glTF file: tinygltf's model and the materials read from its JSON.
struct Parsed {
    tinygltf::Model model;
    std::vector<Material> materials;
};

/// Parses the .gltf or .glb file `path` (buffers loaded, images skipped). Throws thicket::Error.
Parsed parse_gltf(const std::string& path) {
    const std::string bytes = read_input_file(path, "glTF file");
    if (bytes.size() > std::numeric_limits<unsigned>::max()) throw Error(path + ": larger than 4 GiB (glTF's limit)");
    const std::string dir = std::filesystem::path(path).parent_path().string();

    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&ignore_image, nullptr);
    loader.SetFsCallbacks({&referenced_file_exists, &path_as_written, &read_referenced_file, nullptr, nullptr});
    Parsed parsed;
    std::string err, warn;
    bool ok = false;
    try {
        ok = has_extension(path, ".glb")
                 ? loader.LoadBinaryFromMemory(&parsed.model, &err, &warn, reinterpret_cast<const unsigned char*>(bytes.data()),
                                               unsigned(bytes.size()), dir)
                 : loader.LoadASCIIFromString(&parsed.model, &err, &warn, bytes.data(), unsigned(bytes.size()), dir);
    } catch (const std::exception& e) {
        throw Error(path + ": glTF parse error: " + e.what());
    }
    // Materials come from the JSON itself (gltf_materials.h), checked against the material table.
    // tinygltf refuses some malformed factors itself (an emissiveFactor of 2 numbers) without the
    // JSON path: when it fails, a material error, if there is one, is the more useful message.
    const bool glb = has_extension(path, ".glb");
    if (!ok) {
        if (const std::string material = gltf::material_error(bytes, glb, path); !material.empty()) throw Error(material);
        throw Error(path + ": " + (err.empty() ? std::string("cannot parse glTF file") : one_line(err)));
    }
    if (!warn.empty()) std::cerr << path << ": warning: " << one_line(warn) << '\n';
    parsed.materials = gltf::read_materials(gltf::json_text(bytes, glb, path), path);
    return parsed;
}

}  // namespace

/// Reads a .gltf or .glb file: the default scene's meshes with node transforms applied, one
/// triangle per TRIANGLES/STRIP/FAN triangle in traversal order. Throws thicket::Error.
TriangleMesh load_gltf(const std::string& path) {
    Parsed parsed = parse_gltf(path);
    return GltfReader(path, parsed.model).read_flat(std::move(parsed.materials));
}

Scene load_gltf_scene(const std::string& path, const LoadOptions& options) {
    Parsed parsed = parse_gltf(path);
    return GltfReader(path, parsed.model).read_scene(std::move(parsed.materials), options.flatten);
}

}  // namespace thicket

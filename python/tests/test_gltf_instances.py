"""thicket.load_scene on a glTF whose nodes share a mesh: instances by default, one triangle soup
with flatten=True, and the same closest hits either way."""

import json
import struct

import numpy as np
import pytest

import thicket
from conftest import random_rays


def write_gltf(tmp_path):
    """A tetrahedron placed by three nodes (two under a rotated, scaled parent) and a triangle once."""
    buffer = struct.pack("<12f", 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1) + struct.pack("<12H", 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3)
    (tmp_path / "t.bin").write_bytes(buffer)
    gltf = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 3, 4]}],
        "nodes": [{"translation": [3, 0, 0], "rotation": [0, 0, 0.38268343, 0.92387953], "scale": [1, 2, 1],
                   "children": [1, 2]},
                  {"mesh": 0, "translation": [0, 1, 0]},
                  {"mesh": 0, "scale": [0.5, 0.5, 0.5], "translation": [1, 0, 2]},
                  {"mesh": 0, "matrix": [-1, 0, 0, 0, 0, 1, 0, 0, 0, 0.3, 1, 0, -3, 0, 0, 1]},
                  {"mesh": 1, "translation": [0, -1, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]},
                   {"primitives": [{"attributes": {"POSITION": 0}, "indices": 2}]}],
        "buffers": [{"uri": "t.bin", "byteLength": len(buffer)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 48, "byteLength": 24}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3"},
                      {"bufferView": 1, "componentType": 5123, "count": 12, "type": "SCALAR"},
                      {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}],
    }
    path = tmp_path / "t.gltf"
    path.write_text(json.dumps(gltf))
    return path


def test_shared_mesh_is_instanced_and_flatten_copies_it(tmp_path):
    path = write_gltf(tmp_path)
    instanced, flat = thicket.load_scene(path), thicket.load_scene(path, flatten=True)
    assert instanced.instance_count == 4  # the triangle placed once (flattened), then three nodes
    assert instanced.triangle_count == 1 + 4
    assert flat.instance_count == 0 and flat.triangle_count == 1 + 3 * 4
    # Half the rays aim at points inside the flattened triangles (they must hit), half anywhere.
    rays = random_rays(flat, 300, seed=27)
    rng = np.random.default_rng(27)
    corners = flat.vertices[flat.triangles[rng.integers(0, flat.triangle_count, 150)]]
    weights = rng.dirichlet([4, 4, 4], 150)[:, :, None]
    rays[:150, 3:6] = (corners * weights).sum(axis=1) - rays[:150, 0:3]
    a = thicket.build(instanced, "brute").cast_rays(rays)["t_hit"]
    b = thicket.build(flat, "brute").cast_rays(rays)["t_hit"]
    assert np.isfinite(b[:150]).all()
    assert np.array_equal(np.isfinite(a), np.isfinite(b))
    np.testing.assert_allclose(a[np.isfinite(a)], b[np.isfinite(b)], rtol=1e-4, atol=1e-5)


def test_flatten_is_keyword_only(tmp_path):
    with pytest.raises(TypeError):
        thicket.load_scene(write_gltf(tmp_path), True)

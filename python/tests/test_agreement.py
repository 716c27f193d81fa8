"""The module answers what `thicket trace` answers, ray for ray and bit for bit, and what brute
force answers for every registered variant."""

import os
import subprocess

import numpy as np
import pytest

import thicket
from conftest import SHARED_SCENES, random_rays

CLI = os.environ.get("THICKET_CLI", "")


def scenes_for_cli():
    yield "cornell"
    yield "teapot-patches"  # shapes: ids and uvs of Bezier patches
    if (SHARED_SCENES / "sponza-dabrovic.ply").exists():
        yield str(SHARED_SCENES / "sponza-dabrovic.ply")


@pytest.mark.skipif(not CLI, reason="THICKET_CLI is not set (ctest sets it)")
@pytest.mark.parametrize("scene_name", list(scenes_for_cli()))
def test_agrees_with_thicket_trace(tmp_path, scene_name):
    scene = thicket.load_scene(scene_name)
    rays = random_rays(scene, 20_000, seed=7)
    rays[::97, 6] = 0.5   # some narrowed intervals and invalid rows, as the CLI reads them too
    rays[::89, 7] = 1.0
    rays[::101, 3:6] = 0
    np.save(tmp_path / "rays.npy", rays)
    for spec in ("bvh8", "kdtree"):
        subprocess.run([CLI, "trace", scene_name, "--rays", str(tmp_path / "rays.npy"), "-o", str(tmp_path / "hits.npy"),
                        "--accel", spec, "--force"], check=True, capture_output=True)
        subprocess.run([CLI, "trace", scene_name, "--rays", str(tmp_path / "rays.npy"), "-o", str(tmp_path / "occ.npy"),
                        "--accel", spec, "--any-hit", "--force"], check=True, capture_output=True)
        cli = np.load(tmp_path / "hits.npy")
        ours = thicket.build(scene, spec).cast_rays(rays)
        assert 0.2 < np.isfinite(cli["t"]).mean() < 1.0
        assert np.array_equal(cli["t"], ours["t_hit"])
        assert np.array_equal(cli["prim"], ours["primitive_ids"])
        assert np.array_equal(cli["u"], ours["primitive_uvs"][:, 0])
        assert np.array_equal(cli["v"], ours["primitive_uvs"][:, 1])
        occ = np.load(tmp_path / "occ.npy")
        assert np.array_equal(occ.astype(bool), thicket.build(scene, spec).test_occlusions(rays))


def named_primitive_is_hit(scene, isect, ray, got, i):
    """The conformance suite's rule for a hit that names another primitive than brute force: that
    primitive alone, traced by brute force with the same triangle test, gives exactly the t and uv
    reported. Triangles are probed in a scene of that one triangle; shapes (which the module cannot
    take apart) through brute force's list of every crossing of the ray."""
    prim = int(got["primitive_ids"][i])
    if prim < scene.triangle_count:
        tri = scene.vertices[scene.triangles[prim]].astype(np.float32)
        alone = thicket.build(thicket.Scene(tri, np.array([[0, 1, 2]], np.int32)), f"brute:isect={isect}")
        probe = alone.cast_rays(ray[None, :])
        return probe["t_hit"][0] == got["t_hit"][i] and np.array_equal(probe["primitive_uvs"][0], got["primitive_uvs"][i])
    crossings = thicket.build(scene, f"brute:isect={isect}").list_intersections(ray[None, :])
    mine = crossings["primitive_ids"] == prim
    return bool(np.any(crossings["t_hit"][mine] == got["t_hit"][i]))


def variants():
    return [v for a in thicket.accels() for v in a["variants"]]


@pytest.mark.parametrize("scene_name", ["cornell", "teapot-patches"])
def test_every_variant_agrees_with_brute_force(scene_name):
    scene = thicket.load_scene(scene_name)
    rays = random_rays(scene, 3000, seed=3)
    refs = {}  # brute force with the variant's triangle test (uvs differ between the two tests)
    for isect in ("moller", "watertight"):
        brute = thicket.build(scene, f"brute:isect={isect}")
        refs[isect] = brute.cast_rays(rays), brute.test_occlusions(rays)
    for spec in variants():
        ref, ref_occ = refs["watertight" if "isect=watertight" in spec else "moller"]
        hit = np.isfinite(ref["t_hit"])
        assert 0.2 < hit.mean() < 1.0
        got = thicket.build(scene, spec).cast_rays(rays)
        assert np.array_equal(np.isfinite(got["t_hit"]), hit), spec
        # Another primitive may answer at the same t (a shared edge): t must agree to the suite's
        # 1e-5 relative, and the primitive named must really be hit there (the conformance suite's
        # rule, named_primitive_is_hit); where the id agrees, t and uv agree bit for bit.
        assert np.allclose(got["t_hit"][hit], ref["t_hit"][hit], rtol=1e-5, atol=0), spec
        same = hit & (got["primitive_ids"] == ref["primitive_ids"])
        isect = "watertight" if "isect=watertight" in spec else "moller"
        for i in np.flatnonzero(hit & ~same):
            assert named_primitive_is_hit(scene, isect, rays[i], got, i), f"{spec}: ray {i}"
        assert np.array_equal(got["t_hit"][same], ref["t_hit"][same]), spec
        assert np.array_equal(got["primitive_uvs"][same], ref["primitive_uvs"][same]), spec
        assert np.array_equal(thicket.build(scene, spec).test_occlusions(rays), ref_occ), spec

@pytest.mark.skipif(not CLI, reason="THICKET_CLI is not set (ctest sets it)")
def test_cli_count_all_and_closest_match_the_module(tmp_path):
    scene = thicket.load_scene("cornell")
    rays = random_rays(scene, 5000, seed=8)
    rays[::53, 3:6] = np.nan  # invalid rows: 0 crossings, no records
    np.save(tmp_path / "rays.npy", rays)
    run = lambda *a: subprocess.run([CLI, *a], check=True, capture_output=True, text=True)
    run("trace", "cornell", "--rays", str(tmp_path / "rays.npy"), "-o", str(tmp_path / "count.npy"), "--count")
    run("trace", "cornell", "--rays", str(tmp_path / "rays.npy"), "-o", str(tmp_path / "all.npy"), "--all")
    accel = thicket.build(scene, "bvh8")
    counts = np.load(tmp_path / "count.npy")
    assert counts.dtype == np.uint32 and np.array_equal(counts, accel.count_intersections(rays))
    records = np.load(tmp_path / "all.npy")
    assert records.dtype.names == ("ray", "t", "prim", "u", "v")
    lists = accel.list_intersections(rays)
    assert np.array_equal(records["ray"], lists["ray_ids"]) and np.array_equal(records["t"], lists["t_hit"])
    assert np.array_equal(records["prim"], lists["primitive_ids"])
    assert np.array_equal(records["u"], lists["primitive_uvs"][:, 0])

    pts = np.random.default_rng(3).random((2000, 3)).astype(np.float32) * 6 - 3
    np.save(tmp_path / "points.npy", pts)
    run("closest", "cornell", "--points", str(tmp_path / "points.npy"), "-o", str(tmp_path / "closest.npy"))
    closest = np.load(tmp_path / "closest.npy")
    want = thicket.build(scene, "bvh8").compute_closest_points(pts)  # the CLI's default structure
    assert np.array_equal(np.stack([closest["x"], closest["y"], closest["z"]], axis=1), want["points"])
    assert np.array_equal(closest["prim"], want["primitive_ids"])
    assert np.array_equal(closest["distance"], thicket.build(scene, "bvh8").compute_distance(pts))
    # Usage errors name the problem: two modes at once, shapes without closest points.
    bad = subprocess.run([CLI, "trace", "cornell", "--rays", str(tmp_path / "rays.npy"), "-o", str(tmp_path / "x.npy"),
                          "--count", "--all"], capture_output=True, text=True)
    assert bad.returncode == 1 and "choose one of --any-hit, --count and --all" in bad.stderr
    bad = subprocess.run([CLI, "closest", "teapot-patches", "--points", str(tmp_path / "points.npy"), "-o",
                          str(tmp_path / "x.npy")], capture_output=True, text=True)
    assert bad.returncode == 1 and "closest-point" in bad.stderr

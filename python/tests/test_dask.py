"""thicket.dask on a LocalCluster of 2 worker processes: the same answers as the single-process
queries ray for ray, and each worker loads the saved structure once, not once per chunk."""

import dask.array as da
import numpy as np
import pytest
from dask.distributed import Client, LocalCluster

import thicket
import thicket.dask
from conftest import random_rays


@pytest.fixture(scope="module")
def client():
    with LocalCluster(n_workers=2, threads_per_worker=2, processes=True, dashboard_address=":0") as cluster, \
            Client(cluster) as c:
        yield c


def test_cast_on_two_workers_matches_one_process(client, tmp_path):
    scene = thicket.load_scene("cornell")
    accel = thicket.build(scene, "bvh8")  # the default structure, saved and loaded by every worker
    accel.save(tmp_path / "cornell.bvh")
    rays = random_rays(scene, 40_000, seed=4).reshape(200, 200, 8)
    want = accel.cast_rays(rays)
    # 16 chunks over 2 workers: each worker gets several and must still load only once.
    lazy = da.from_array(rays, chunks=(50, 50, 8))
    hits = thicket.dask.cast_rays(lazy, "cornell", saved=tmp_path / "cornell.bvh")
    got = dict(zip(hits, da.compute(*hits.values())))
    for key in want:
        assert got[key].dtype == want[key].dtype and np.array_equal(got[key], want[key]), key
    assert np.array_equal(thicket.dask.test_occlusions(lazy, "cornell", saved=tmp_path / "cornell.bvh").compute(),
                          accel.test_occlusions(rays))
    assert np.array_equal(thicket.dask.count_intersections(lazy, "cornell", spec="kdtree").compute(),
                          accel.count_intersections(rays))
    loads = client.run(thicket.dask.load_count)
    assert len(loads) == 2
    # Per worker: at most the saved structure and the kdtree (built from the spec), once each.
    assert all(n <= 2 for n in loads.values()), loads
    assert sum(loads.values()) >= 2  # both structures were really loaded on the workers


def test_errors_before_any_work():
    with pytest.raises(ValueError, match=r"got shape \(10, 7\)"):
        thicket.dask.cast_rays(da.zeros((10, 7), np.float32), "cornell")
    with pytest.raises(ValueError, match="float64"):
        thicket.dask.count_intersections(da.zeros((10, 6)), "cornell")

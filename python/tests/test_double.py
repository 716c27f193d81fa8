"""precision=double: float64 vertices kept in double by thicket.Scene, float64 rays traced in double
by brute and bvh built with precision=double, and refused by float structures with a message that
names the option. A centimetre triangle 1e7 from the origin shows what float loses."""

import numpy as np
import pytest

import thicket

OFFSET = 1e7


def far_triangle():
    vertices = np.array([[0, 0, 0], [0.01, 0, 0], [0, 0.01, 0]], dtype=np.float64) + OFFSET
    return thicket.Scene(vertices, np.array([[0, 1, 2]], dtype=np.int32))


def ray_through_it(dtype):
    return np.array([[OFFSET + 0.002, OFFSET + 0.003, OFFSET - 5.0, 0, 0, 1]], dtype=dtype)


@pytest.mark.parametrize("spec", ["brute:precision=double", "bvh:precision=double"])
def test_double_structures_hit_what_float_loses(spec):
    scene = far_triangle()
    accel = thicket.build(scene, spec)
    assert accel.double_precision
    hit = accel.cast_rays(ray_through_it(np.float64))
    assert hit["primitive_ids"][0] == 0
    assert hit["t_hit"].dtype == np.float64
    assert hit["t_hit"][0] == pytest.approx(5.0, abs=1e-6)
    assert hit["primitive_uvs"][0] == pytest.approx([0.2, 0.3], abs=1e-6)
    assert accel.test_occlusions(ray_through_it(np.float64))[0]
    assert not accel.test_occlusions(ray_through_it(np.float64), tfar=4.0)[0]
    # The float structure over the same scene sees the triangle rounded to a point.
    flat = thicket.build(scene, "bvh")
    assert not flat.double_precision
    assert flat.cast_rays(ray_through_it(np.float32))["primitive_ids"][0] == thicket.INVALID_ID


def test_float_structures_refuse_float64_rays_naming_the_option():
    accel = thicket.build(far_triangle(), "bvh")
    for query in (accel.cast_rays, accel.test_occlusions):
        with pytest.raises(ValueError, match="precision=double"):
            query(ray_through_it(np.float64))
    with pytest.raises(ValueError, match="precision=double"):
        accel.count_intersections(ray_through_it(np.float64))


def test_float32_rays_on_a_double_structure_are_widened():
    scene = thicket.Scene(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32), np.array([[0, 1, 2]]))
    accel = thicket.build(scene, "bvh:precision=double")
    rays = np.array([[0.25, 0.25, -1, 0, 0, 1]], np.float32)
    assert accel.cast_rays(rays)["t_hit"][0] == pytest.approx(1.0)
    # An invalid float64 row (zero direction) is a miss, not an error.
    bad = np.array([[0.25, 0.25, -1, 0, 0, 0]], np.float64)
    assert accel.cast_rays(bad)["primitive_ids"][0] == thicket.INVALID_ID

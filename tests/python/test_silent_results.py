"""No silent zeros or silent defaults from Python: plan values that are not values and spacings wider than the
cloth raise, naming the keyword; meshes beyond pleat's double range raise naming the array; vertices no
triangle uses give NaN; an animated occluder pairs frame by frame and must hold each of the cloth's frames."""
import numpy as np
import pytest

import pleat
from test_bad_input import sheet


@pytest.mark.parametrize("options,message", [
    (dict(planes=0), "planes: must be >= 1, got 0"),
    (dict(spacing=0.0), "spacing: must be a finite number > 0, got 0"),
    (dict(spacing=float("nan")), "spacing: must be a finite number > 0, got nan"),
    (dict(spacing_edges=0.0), "spacing_edges: must be a finite number > 0, got 0"),
])
def test_values_that_are_not_values_are_refused_not_defaulted(options, message):
    faces, positions = sheet()
    with pytest.raises(ValueError) as error:
        pleat.Engine(faces, positions, **options)
    assert str(error.value) == message  # the command line's message, its option named as a keyword


def test_a_spacing_wider_than_the_cloth_is_refused():
    faces, positions = sheet()
    with pytest.raises(ValueError, match=r"^spacing=1e\+09 is wider than the cloth positions"):
        pleat.Engine(faces, positions, spacing=1e9)
    with pytest.raises(ValueError, match=r"^spacing_edges=1e\+06 \(a spacing of"):
        pleat.Engine(faces, positions, spacing_edges=1e6)
    assert pleat.Engine(faces, positions, spacing=0.9).num_planes > 0  # up to the cloth's extent


@pytest.mark.parametrize("scale,message", [
    (1e-300, r"^positions: the mesh spans only 1e-300"),
    (1e-40, r"^positions: the mesh spans only 1e-40"),
    (1e100, r"^positions:frame 0, vertex 1: coordinate 3\.3+e\+99 beyond \+-2\^53"),
    (1e200, r"^positions:frame 0, vertex 1: coordinate"),
])
def test_meshes_beyond_double_range_are_refused_naming_the_input(scale, message):
    faces, positions = sheet()
    with pytest.raises(ValueError, match=message):
        pleat.sky_visibility(faces, positions * scale)


def test_within_the_range_the_unit_does_not_matter():
    faces, positions = sheet()
    positions[:, 5, 1] += 0.4  # a bump, so that A is not 1 everywhere
    reference = pleat.sky_visibility(faces, positions)
    assert reference.min() < 0.99
    for scale in (2.0**-83, 2.0**40):  # about 1e-25, 1e12, exactly (a power of two): the same bits
        assert np.array_equal(pleat.sky_visibility(faces, positions * scale), reference)
    engine = pleat.Engine(faces, positions)
    with pytest.raises(ValueError, match=r"positions:vertex 1: a coordinate beyond \+-2\^53"):
        engine.compute(positions[0] * 1e100)


def test_vertices_no_triangle_uses_are_nan():
    faces, positions = sheet()
    lone = np.concatenate([positions, np.full((2, 1, 3), 7.0)], axis=1)  # vertex 16: no face
    sky = pleat.sky_visibility(faces, lone)
    assert np.isnan(sky[:, 16]).all()
    assert np.allclose(sky[:, :16], 1.0)
    result = pleat.Engine(faces, lone).compute(lone[1], frame_index=1)
    assert np.isnan(result.sky_visibility[16]).all()
    assert np.isnan(result.solid_angles[16]).all()
    assert np.isnan(result.bent_normals[16]).all()
    assert not np.isnan(result.sky_visibility[:16]).any()


def test_an_animated_occluder_must_hold_each_of_the_cloths_frames():
    faces, positions = sheet(frames=3)
    floor = positions[:2] - [0.0, 0.5, 0.0]  # two frames for the cloth's three
    with pytest.raises(ValueError, match=r"occluders\[0\]: the animated occluder has no source frame 2 "
                                         r"\(it holds frames 0 to 1 in 2 frames, the cloth frames 0 to 2 in 3\)"):
        pleat.Engine(faces, positions, occluders=[(faces, floor)])
    longer = np.concatenate([positions, positions]) - [0.0, 0.5, 0.0]  # six frames: frames 0-2 are the cloth's
    paired = pleat.sky_visibility(faces, positions, occluders=[(faces, longer)])
    exact = pleat.sky_visibility(faces, positions, occluders=[(faces, longer[:3])])
    assert np.array_equal(paired, exact)

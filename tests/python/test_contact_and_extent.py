"""The Python module in contact and out of the first frame's box: contact_tolerance, sunk vertices reported,
and an Engine made on one frame computing another far from it as the whole sequence would."""
import warnings

import numpy as np
import pytest

import pleat
from conftest import SOURCE


def sheet(lift=0.0, n=11, spacing=0.1):
    """A flat n x n sheet in the plane z = lift (front +z), faces and positions."""
    x, y = np.meshgrid(np.arange(n) * spacing, np.arange(n) * spacing, indexing="ij")
    positions = np.stack([x.ravel(), y.ravel(), np.full(n * n, lift)], axis=1)
    faces = []
    for i in range(n - 1):
        for j in range(n - 1):
            a, b, c, d = i * n + j, (i + 1) * n + j, (i + 1) * n + j + 1, i * n + j + 1
            faces += [[a, b, c], [a, c, d]]
    return np.array(faces), positions


def test_a_sheet_just_under_the_ground_is_not_inverted():
    faces, positions = sheet(lift=-0.001)
    a = pleat.sky_visibility(faces, positions, ground="z=0")
    assert np.all(a[:, 0] > 0.98) and np.all(a[:, 1] < 0.02)


def test_sunk_vertices_are_reported_and_the_tolerance_is_a_keyword():
    faces, positions = sheet(lift=-0.3)
    with pytest.warns(UserWarning, match="deeper than the contact tolerance"):
        a = pleat.sky_visibility(faces, positions, ground="z=0")
    assert np.all(a[:, 0] > 0.98)
    engine = pleat.Engine(faces, positions, ground="z=0")
    assert engine.compute(positions).penetrating_vertices == 121
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        pleat.sky_visibility(faces, positions, ground="z=0", contact_tolerance=0.5)
    with pytest.raises(ValueError, match="contact_tolerance"):
        pleat.Engine(faces, positions, ground="z=0", contact_tolerance=-1.0)


def test_an_engine_computes_frames_far_from_its_first():
    # Made on frame 0 of the pile, asked for frame 59 and for frame 59 moved 100 units away: the values of
    # the whole sequence's frame 59, and of the same cloth there (a lattice plan follows each frame).
    cloth = pleat.load(SOURCE / "data" / "pile" / "pile.obj", cache=SOURCE / "data" / "pile" / "pile.pc2")
    whole = pleat.Engine(cloth.faces, cloth.positions[[0, 59]], engine="static")
    expected = whole.compute(cloth.positions[59], frame_index=1, keep_cones=False).sky_visibility
    first = pleat.Engine(cloth.faces, cloth.positions[0], engine="static")
    got = first.compute(cloth.positions[59], keep_cones=False).sky_visibility
    np.testing.assert_array_equal(got, expected)
    moved = first.compute(cloth.positions[59] + 100.0, keep_cones=False).sky_visibility
    assert np.abs(moved - expected).mean() < 0.01  # the lattice cuts it elsewhere, not nowhere

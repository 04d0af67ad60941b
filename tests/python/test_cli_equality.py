"""pleat.sky_visibility and pleat.Engine equal `pleat visibility` bit for bit on the bundled cloth."""
import numpy as np
import pytest

import pleat
from conftest import SOURCE, run_cli, truncate_pc2

FRAMES = 3  # the first frames of the drape, as a sequence of their own (the plan is the sequence's)


@pytest.fixture(scope="module")
def drape(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("drape")
    source = SOURCE / "data" / "drape"
    truncate_pc2(source / "drape.pc2", tmp / "drape.pc2", FRAMES)
    truncate_pc2(source / "drape_colliders.pc2", tmp / "table.pc2", FRAMES)
    return {"obj": source / "drape.obj", "pc2": tmp / "drape.pc2",
            "table": source / "drape_colliders.obj", "table_pc2": tmp / "table.pc2", "tmp": tmp}


def test_load_reads_the_cache(drape):
    cloth = pleat.load(drape["obj"], cache=drape["pc2"])
    assert cloth.faces.dtype == np.int64 and cloth.faces.shape == (6000, 3)
    assert cloth.positions.dtype == np.float64 and cloth.positions.shape == (FRAMES, 3111, 3)
    assert cloth.fps == pytest.approx(24.0)
    assert list(cloth.source_frames) == [21, 22, 23]  # the drape's cache starts at scene frame 21
    assert cloth.positions.flags.c_contiguous and cloth.positions.flags.owndata


def test_sequence_equals_cli(drape):
    cloth = pleat.load(drape["obj"], cache=drape["pc2"])
    ours = pleat.sky_visibility(cloth.faces, cloth.positions)
    assert ours.shape == (FRAMES, 3111, 2) and ours.dtype == np.float64
    assert np.array_equal(ours, run_cli(drape["obj"], "--cache", drape["pc2"]))


def test_occluders_ground_and_plan_options_equal_cli(drape):
    cloth = pleat.load(drape["obj"], cache=drape["pc2"])
    table = pleat.load(drape["table"], cache=drape["table_pc2"])  # animated: it turns
    options = dict(engine="static", orientations=12, spacing_edges=0.75, ground="y=0", threads=2)
    ours = pleat.sky_visibility(cloth.faces, cloth.positions, occluders=[table], **options)
    theirs = run_cli(drape["obj"], "--cache", drape["pc2"], "--engine", "static", "--orientations", 12,
                     "--spacing-edges", 0.75, "--ground", "y=0",
                     "--occluder", f"{drape['table']},cache={drape['table_pc2']}")
    assert np.array_equal(ours, theirs)
    # The occluders block sky: without them the cloth sees more of it.
    alone = pleat.sky_visibility(cloth.faces, cloth.positions, orientations=12, spacing_edges=0.75)
    assert (alone.sum() - ours.sum()) > 100.0
    # (faces, positions) pairs work as well as load results, a static occluder as (V, 3).
    pair = pleat.sky_visibility(cloth.faces, cloth.positions, occluders=[(table.faces, table.positions)],
                                **options)
    assert np.array_equal(pair, ours)


def test_part_of_the_shot_with_a_ground_equals_cli_frames(drape):
    # The ground is an exact plane, not a square sized by the frames given: the first two frames alone (the same
    # first frame, hence the same plan) give the values `--frames 0:2` gives from the whole file.
    cloth = pleat.load(drape["obj"], cache=drape["pc2"])
    part = pleat.sky_visibility(cloth.faces, cloth.positions[:2], engine="static", ground="y=0")
    theirs = run_cli(drape["obj"], "--cache", drape["pc2"], "--engine", "static", "--ground", "y=0",
                     "--frames", "0:2")
    assert np.array_equal(part, theirs)


def test_saved_plan_equals_cli(drape):
    plan = drape["tmp"] / "plan.json"
    theirs = run_cli(drape["obj"], "--cache", drape["pc2"], "--paper", "--save-plan", plan)
    cloth = pleat.load(drape["obj"], cache=drape["pc2"])
    assert np.array_equal(pleat.sky_visibility(cloth.faces, cloth.positions, paper=True), theirs)
    assert np.array_equal(pleat.sky_visibility(cloth.faces, cloth.positions, plan=plan), theirs)


def test_one_frame_in_the_callers_vertex_order(drape, tmp_path):
    """A single (V, 3) frame gives (V, 2); vertices split at a seam (welded, as the command line does)
    and given in another order keep the caller's order."""
    rest = pleat.load(drape["obj"])
    faces, positions = rest.faces, rest.positions[0]
    rng = np.random.default_rng(7)
    order = rng.permutation(len(positions))  # new vertex i is old vertex order[i]
    new_of_old = np.argsort(order)
    seam = rng.choice(len(faces), 500, replace=False)  # these faces get copies of their first corner
    copies = faces[seam, 0]
    positions2 = np.concatenate([positions[order], positions[copies]])
    faces2 = new_of_old[faces]
    faces2[seam, 0] = len(positions) + np.arange(len(seam))
    path = tmp_path / "seamed.obj"
    with open(path, "w") as f:
        f.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in positions2)
        f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces2)
    ours = pleat.sky_visibility(faces2, positions2)
    assert ours.shape == (len(positions2), 2)
    assert np.array_equal(ours, run_cli(path)[0])
    # The copies carry their originals' values; the permutation undone gives the unseamed result.
    assert np.array_equal(ours[len(positions):], ours[new_of_old[copies]])
    np.testing.assert_allclose(ours[new_of_old], pleat.sky_visibility(faces, positions), rtol=0, atol=1e-9)


def test_engine_compute_kinetic_equals_static_and_cli(drape):
    cloth = pleat.load(drape["obj"], cache=drape["pc2"])
    table = pleat.load(drape["table"], cache=drape["table_pc2"])
    options = dict(occluders=[table], ground="y=0", orientations=12)
    kinetic = pleat.Engine(cloth.faces, cloth.positions, engine="kinetic", **options)
    static = pleat.Engine(cloth.faces, cloth.positions, engine="static", threads=1, **options)
    assert (kinetic.engine, static.engine) == ("kinetic", "static")
    expected = pleat.sky_visibility(cloth.faces, cloth.positions, **options)
    for t in range(FRAMES):
        k = kinetic.compute(cloth.positions[t], frame_index=t)
        s = static.compute(cloth.positions[t], frame_index=t)
        assert np.array_equal(k.sky_visibility, expected[t])
        for name in ("sky_visibility", "bent_normals", "solid_angles"):
            assert np.array_equal(getattr(k, name), getattr(s, name)), name
        assert k.bent_normals.shape == (3111, 2, 3) and k.solid_angles.shape == (3111, 2)
        assert np.allclose(np.linalg.norm(k.bent_normals, axis=2), 1.0)
        for v in (0, 1555, 3110):
            for side in (0, "back"):
                pieces = k.cone(v, side)
                assert all(np.array_equal(a, b) for a, b in zip(pieces, s.cone(v, side)))
                for piece in pieces:
                    assert piece.shape[1] == 3 and np.allclose(np.linalg.norm(piece, axis=1), 1.0)
    with pytest.raises(ValueError, match="side"):
        k.cone(0, "up")
    with pytest.raises(IndexError):
        k.cone(3111, 0)

"""Bad arrays raise ValueError with the library's message, bad files an InputError naming the file; nothing
crashes."""
import numpy as np
import pytest

import pleat


def sheet(n=4, frames=2):
    """An n x n grid sheet, slightly different in each frame: faces (F, 3) int64, positions (T, V, 3)."""
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    base = np.stack([i.ravel() / (n - 1), np.zeros(n * n), j.ravel() / (n - 1)], axis=1)
    positions = np.stack([base + [0.0, 0.01 * t, 0.0] for t in range(frames)])
    a = (i[:-1, :-1] * n + j[:-1, :-1]).ravel()
    faces = np.concatenate([np.stack([a, a + 1, a + n + 1], 1), np.stack([a, a + n + 1, a + n], 1)])
    return faces.astype(np.int64), positions


def test_the_sheet_is_fine():
    faces, positions = sheet()
    result = pleat.sky_visibility(faces, positions)
    assert result.shape == (2, 16, 2)
    assert np.allclose(result, 1.0)  # a flat sheet alone sees the whole sky on both sides
    assert np.array_equal(pleat.sky_visibility(faces.astype(np.int32), positions.astype(np.float32)),
                          pleat.sky_visibility(faces, positions.astype(np.float32).astype(np.float64)))


def with_nan(p):
    p = p.copy()
    p[1, 5, 2] = np.nan
    return p


def with_inf(p):
    p = p.copy()
    p[0, 3, 0] = np.inf
    return p


BAD_POSITIONS = [
    (lambda p: p[..., :2], r"^positions: shape \(2, 16, 2\); expected"),
    (lambda p: p[0, 0], r"shape \(3,\)"),
    (lambda p: p.astype(np.int64), r"dtype int64; expected float64 or float32"),
    (lambda p: p.astype(np.complex128), r"dtype complex128"),
    (lambda p: p[:0], r"no frames"),
    (lambda p: p[:, :0], r"no vertices"),
    (with_nan, r"positions:frame 1, vertex 5: non-finite coordinate"),
    (with_inf, r"positions:frame 0, vertex 3: non-finite coordinate"),
    (lambda p: p[:, :10], r"vertex index 1[0-5] out of range \(10 vertices\)"),
    (lambda p: None, r"None is not an array"),
    (lambda p: "text", r"dtype <U4"),
]


@pytest.mark.parametrize("bad,message", BAD_POSITIONS)
def test_bad_positions(bad, message):
    faces, positions = sheet()
    with pytest.raises(ValueError, match=message):
        pleat.sky_visibility(faces, bad(positions))


BAD_FACES = [
    (lambda f: f.astype(np.float64), r"^faces: dtype float64; expected integers"),
    (lambda f: f[:, :2], r"faces: shape \(18, 2\); expected \(F, 3\)"),
    (lambda f: f.ravel(), r"faces: shape \(54,\)"),
    (lambda f: f[:0], r"faces: no faces"),
    (lambda f: np.where(f == 7, -1, f), r"face 2: vertex index -1 out of range \(16 vertices\)"),
    (lambda f: np.where(f == 7, 16, f), r"vertex index 16 out of range"),
    (lambda f: np.where(f == 7, 2**40, f), r"vertex index 1099511627776 out of range"),
    (lambda f: np.zeros((1, 3), np.int64), r"every face collapses after welding"),
]


@pytest.mark.parametrize("bad,message", BAD_FACES)
def test_bad_faces(bad, message):
    faces, positions = sheet()
    with pytest.raises(ValueError, match=message):
        pleat.sky_visibility(bad(faces), positions)


def test_bad_compute_and_options():
    faces, positions = sheet()
    engine = pleat.Engine(faces, positions)
    with pytest.raises(ValueError, match=r"positions: 15 vertices; the engine's cloth has 16"):
        engine.compute(positions[0, :15])
    with pytest.raises(ValueError, match=r"expected \(V, 3\)"):
        engine.compute(positions)
    bad = positions[1].copy()
    bad[4, 1] = np.nan
    with pytest.raises(ValueError, match=r"positions:vertex 4: non-finite coordinate"):
        engine.compute(bad)
    with pytest.raises(IndexError, match="frame_index 2 out of range"):
        engine.compute(positions[1], frame_index=2)
    assert np.allclose(engine.compute(positions[1], frame_index=1).sky_visibility, 1.0)  # still usable
    # Vertices welded because they coincide in every frame given must coincide in computed ones.
    doubled = np.concatenate([positions, positions[:, :1]], axis=1)
    seamed = faces.copy()
    seamed[0, 0] = 16
    welded = pleat.Engine(seamed, doubled)
    moved = doubled[0].copy()
    moved[16] += 0.1
    with pytest.raises(ValueError, match="vertex 16: coincides with vertex 0"):
        welded.compute(moved)
    for options, message in [
        (dict(engine="fast"), "engine 'fast' is not kinetic or static"),
        (dict(orientations=0), "orientations: 0 is not in 1..1000"),
        (dict(spacing=-1.0), "spacing: must be"),
        (dict(spacing=0.1, spacing_edges=0.5), "exclude each other"),
        (dict(spacing_edges=0.0), "spacing_edges: must be a finite number > 0, got 0"),
        (dict(max_missing=2.0), "max_missing"),
        (dict(cone_storage="nearest"), "cone_storage: 'nearest'"),
        (dict(plan="p.json", orientations=6), "a plan file fixes the planes"),
        (dict(ground="up=0"), "--ground: 'up=0' is not AXIS=VALUE"),
        (dict(threads=-1), "threads: must be >= 0"),
        (dict(occluders=[(faces,)]), r"occluders\[0\]: expected a \(faces, positions\) pair"),
        (dict(occluders=[(faces, positions[:, :, :2])]), r"occluders\[0\] positions: shape"),
    ]:
        with pytest.raises(ValueError, match=message):
            pleat.Engine(faces, positions, **options)
    with pytest.raises(TypeError):
        pleat.Engine(faces, positions, orientation=6)  # a misspelt option is not ignored
    for options, message in [(dict(orientations="6"), "orientations: expected an int, got str"),
                             (dict(ground=0), "ground: expected a str like 'y=0', got int"),
                             (dict(threads=1.5), "threads: expected an int, got float")]:
        with pytest.raises(TypeError, match=message):
            pleat.Engine(faces, positions, **options)


def test_bad_files(tmp_path):
    with pytest.raises(pleat.InputError, match="missing.obj"):
        pleat.load(tmp_path / "missing.obj")
    broken = tmp_path / "broken.obj"
    broken.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    with pytest.raises(pleat.InputError, match=r"broken.obj:line 4"):
        pleat.load(broken)
    good = tmp_path / "good.obj"
    good.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    (tmp_path / "short.pc2").write_bytes(b"POINTCACHE2\0" + bytes(8))
    with pytest.raises(pleat.InputError, match=r"short.pc2"):
        pleat.load(good, cache=tmp_path / "short.pc2")
    with pytest.raises(pleat.InputError, match=r"unknown input format"):
        pleat.load(tmp_path / "cloth.xyz")
    faces, positions = pleat.load(good).faces, pleat.load(good).positions
    with pytest.raises(pleat.InputError, match=r"p.json"):
        pleat.Engine(faces, positions, plan=tmp_path / "p.json")
    assert issubclass(pleat.InputError, ValueError)

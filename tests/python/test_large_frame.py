"""A 300k-vertex frame: inputs read in place (float64 or float32, C-contiguous), results allocated once and
owned by their arrays. numpy reports its allocations to tracemalloc, so a copy of the input made on the way
in would show in the traced peak."""
import tracemalloc

import numpy as np
import pytest

import pleat

N = 548  # 548 x 548 = 300,304 vertices


@pytest.fixture(scope="module")
def wave():
    i, j = np.meshgrid(np.linspace(0.0, 1.0, N), np.linspace(0.0, 1.0, N), indexing="ij")
    positions = np.stack([i, 0.05 * np.sin(6.0 * i) * np.cos(5.0 * j), j], axis=-1).reshape(-1, 3)
    a = (np.arange(N - 1)[:, None] * N + np.arange(N - 1)[None, :]).ravel()
    faces = np.concatenate([np.stack([a, a + 1, a + N + 1], 1), np.stack([a, a + N + 1, a + N], 1)])
    return faces, np.ascontiguousarray(positions)


OPTIONS = dict(orientations=1, planes=1, engine="static")  # one plane: the test is of the arrays


def traced_peak(call):
    tracemalloc.start()
    try:
        result = call()
        return result, tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_300k_vertices_without_copies(wave):
    faces, positions = wave
    vertices = len(positions)
    assert vertices == 300_304
    result, peak = traced_peak(lambda: pleat.sky_visibility(faces, positions, **OPTIONS))
    assert result.shape == (vertices, 2) and result.flags.owndata and result.base is None
    out_bytes = result.nbytes
    assert peak < out_bytes + positions.nbytes // 4, (peak, out_bytes)  # no copy of the positions
    assert np.all((result >= 0.0) & (result <= 1.0))
    # float32 is read in place too, and gives the results of its values as float64.
    single = positions.astype(np.float32)
    result32, peak32 = traced_peak(lambda: pleat.sky_visibility(faces, single, **OPTIONS))
    assert peak32 < out_bytes + single.nbytes // 4, (peak32, out_bytes)
    # The measure can fail: a Fortran-ordered input is copied once, and the peak shows it.
    fortran = np.asfortranarray(positions)
    _, peak_fortran = traced_peak(lambda: pleat.sky_visibility(faces, fortran, **OPTIONS))
    assert peak_fortran >= out_bytes + positions.nbytes


def test_engine_results_own_their_memory(wave):
    faces, positions = wave
    engine = pleat.Engine(faces, positions, **OPTIONS)
    frame, peak = traced_peak(lambda: engine.compute(positions, keep_cones=False))
    arrays = (frame.sky_visibility, frame.bent_normals, frame.solid_angles)
    for array in arrays:
        assert array.flags.owndata and array.base is None and array.flags.c_contiguous
    assert peak < sum(a.nbytes for a in arrays) + positions.nbytes // 4
    with pytest.raises(ValueError, match="keep_cones=False"):
        frame.cone(0, 0)


def test_gil_released_while_computing(wave):
    """Another Python thread keeps running while the engine is made and a frame computed: no long pause."""
    import threading
    import time

    faces, positions = wave
    done = threading.Event()
    worker = threading.Thread(target=lambda: (pleat.sky_visibility(faces, positions, **OPTIONS), done.set()))
    start = last = time.perf_counter()
    longest_pause = 0.0
    worker.start()
    while not done.is_set() and worker.is_alive():
        now = time.perf_counter()
        longest_pause, last = max(longest_pause, now - last), now
    worker.join()
    total = last - start
    assert done.is_set() and total > 0.5
    assert longest_pause < total / 3, (longest_pause, total)

"""The module as Python users expect it: Ctrl+C (a real SIGINT) stops a computation between frames and inside
a long frame with KeyboardInterrupt, keeping the finished frames; progress reaches a tqdm bar or a callable;
a misspelt keyword names the option meant; frames= computes a part of a shot as `pleat visibility
--frames` does; dir(pleat) is the API; big-endian arrays are read."""
import io
import os
import signal
import subprocess
import threading

import numpy as np
import pytest

import pleat
from conftest import EXECUTABLE, run_cli


def generated(tmp_path, resolution, frames):
    """A `pleat generate curtain` cloth (OBJ + PC2) loaded."""
    obj = tmp_path / f"curtain_{resolution}.obj"
    subprocess.run([EXECUTABLE, "-q", "generate", "curtain", "-o", str(obj), "--resolution", str(resolution),
                    "--frames", str(frames)], check=True)
    return pleat.load(obj, cache=obj.with_suffix(".pc2"))


@pytest.fixture
def ctrl_c():
    """Python's own SIGINT handler (KeyboardInterrupt), also where the test runner was started with SIGINT
    ignored (a background job of a non-interactive shell, where Python leaves it ignored)."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def interrupter(delay):
    """A thread that, started, sends this process SIGINT after `delay` seconds (Ctrl+C in a terminal)."""
    return threading.Timer(delay, os.kill, (os.getpid(), signal.SIGINT))


def test_interrupt_between_frames_keeps_the_finished_ones(tmp_path, ctrl_c):
    cloth = generated(tmp_path, 40, 40)
    out = np.full((40, cloth.positions.shape[1], 2), np.nan)
    timer = interrupter(0.05)

    def progress(done, total):
        if done == 1:  # once the first frame is done, Ctrl+C arrives while the next ones compute
            timer.start()

    with pytest.raises(KeyboardInterrupt) as raised:
        pleat.sky_visibility(cloth.faces, cloth.positions, progress=progress, out=out, threads=1)
    timer.join()
    notes = getattr(raised.value, "__notes__", [])
    assert len(notes) == 1 and notes[0].startswith("pleat: stopped after "), notes
    finished = int(notes[0].split()[3])
    assert 1 <= finished < 40, notes
    assert np.isnan(out[finished:]).all()
    # The finished frames are the shot's frames, as computed without the interrupt.
    assert np.array_equal(out[:finished], pleat.sky_visibility(cloth.faces, cloth.positions,
                                                                frames=slice(0, finished)))


def test_interrupt_inside_a_long_frame(tmp_path, ctrl_c):
    cloth = generated(tmp_path, 160, 2)  # 25,600 vertices: a frame takes seconds on one thread
    engine = pleat.Engine(cloth.faces, cloth.positions, threads=1)
    timer = interrupter(0.3)
    timer.start()
    with pytest.raises(KeyboardInterrupt) as raised:
        engine.compute(cloth.positions[1], frame_index=1, keep_cones=False)
    timer.join()
    # Raised by pleat inside the frame (Python itself would raise it only after the frame, without the note).
    assert getattr(raised.value, "__notes__", []) == [
        "pleat: interrupted during the frame (the Engine stays usable)"]
    # The engine (kinetic: abandoned between two frames) gives the same values as a fresh one.
    again = engine.compute(cloth.positions[1], frame_index=1, keep_cones=False).sky_visibility
    fresh = pleat.Engine(cloth.faces, cloth.positions, threads=1)
    assert np.array_equal(again, fresh.compute(cloth.positions[1], frame_index=1,
                                               keep_cones=False).sky_visibility)


def test_progress_callable_and_tqdm(tmp_path):
    cloth = generated(tmp_path, 12, 5)
    calls = []
    pleat.sky_visibility(cloth.faces, cloth.positions, progress=lambda done, total: calls.append((done, total)))
    assert calls == [(1, 5), (2, 5), (3, 5), (4, 5), (5, 5)]
    tqdm = pytest.importorskip("tqdm")
    with tqdm.tqdm(total=3, file=io.StringIO()) as bar:
        pleat.sky_visibility(cloth.faces, cloth.positions, frames="2:", progress=bar)
        assert bar.n == 3
    # An exception in the callback stops the computation and comes out as it is.
    with pytest.raises(ZeroDivisionError):
        pleat.sky_visibility(cloth.faces, cloth.positions, progress=lambda done, total: 1 / 0)


def test_misspelt_keywords_name_the_option_meant():
    faces = np.array([[0, 1, 2]])
    positions = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float64)
    with pytest.raises(TypeError, match=r"^unknown option 'spcing'; did you mean 'spacing'\?$"):
        pleat.Engine(faces, positions, spcing=0.1)
    with pytest.raises(TypeError, match=r"^unknown option 'spcing'; did you mean 'spacing'\?$"):
        pleat.sky_visibility(faces, positions, spcing=0.1)
    with pytest.raises(TypeError, match=r"^unknown option 'frmaes'; did you mean 'frames'\?$"):
        pleat.sky_visibility(faces, positions, frmaes="0:1")
    with pytest.raises(TypeError, match=r"^unknown option 'colour' \(options: frames progress out engine "):
        pleat.sky_visibility(faces, positions, colour=1)


def test_frames_reproduce_the_cli_on_a_part_of_the_shot(tmp_path, data):
    pc2 = tmp_path / "drape.pc2"
    from conftest import truncate_pc2

    truncate_pc2(data / "drape" / "drape.pc2", pc2, 12)
    cloth = pleat.load(data / "drape" / "drape.obj", cache=pc2)
    part = pleat.sky_visibility(cloth.faces, cloth.positions, frames="8:11", ground="y=0")
    assert np.array_equal(part, run_cli(data / "drape" / "drape.obj", "--cache", pc2, "--frames", "8:11",
                                        "--ground", "y=0"))
    # The trap frames= removes: the same frames passed alone are another shot (their first frame sets the plan).
    alone = pleat.sky_visibility(cloth.faces, cloth.positions[8:11], ground="y=0")
    assert not np.array_equal(part, alone)
    assert np.array_equal(pleat.sky_visibility(cloth.faces, cloth.positions, frames=[-1], ground="y=0"),
                          pleat.sky_visibility(cloth.faces, cloth.positions, frames=slice(11, 12), ground="y=0"))
    with pytest.raises(ValueError, match="frames: selects no frame"):
        pleat.sky_visibility(cloth.faces, cloth.positions, frames="5:5")
    with pytest.raises(IndexError):
        pleat.sky_visibility(cloth.faces, cloth.positions, frames=12)


def test_dir_is_the_api_and_big_endian_arrays_are_read():
    assert dir(pleat) == sorted(pleat.__all__)
    assert "os" not in dir(pleat)
    faces = np.array([[0, 1, 2], [0, 2, 3], [1, 4, 2]])
    positions = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0.3], [0, 1, 0], [2, 0, 1]], dtype=np.float64)
    native = pleat.sky_visibility(faces, positions)
    assert np.array_equal(pleat.sky_visibility(faces.astype(">i4"), positions.astype(">f8")), native)
    assert np.array_equal(pleat.sky_visibility(faces.astype(">u2"), positions.astype(">f4")),
                          pleat.sky_visibility(faces, positions.astype("<f4")))


def test_read_cone_cache_equals_the_csv(tmp_path, data):
    pc2 = tmp_path / "drape.pc2"
    from conftest import truncate_pc2

    truncate_pc2(data / "drape" / "drape.pc2", pc2, 4)
    cones = tmp_path / "drape.cones"
    csv_values = run_cli(data / "drape" / "drape.obj", "--cache", pc2, "--frames", "1:4", "--cones", cones)
    cache = pleat.read_cone_cache(cones)
    assert np.array_equal(cache.sky_visibility, csv_values)
    assert cache.frames.tolist() == [1, 2, 3]
    assert np.allclose(np.diff(cache.times), 1 / 24)
    with pytest.raises(pleat.InputError, match="drape.obj"):
        pleat.read_cone_cache(data / "drape" / "drape.obj")

"""Fixtures of the Python module's tests: the pleat executable and the bundled data (ctest sets
PLEAT_EXECUTABLE and PLEAT_SOURCE_DIR, and PYTHONPATH to the build tree's python/)."""
import csv
import os
import pathlib
import struct
import subprocess

import numpy as np
import pytest

SOURCE = pathlib.Path(os.environ.get("PLEAT_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
EXECUTABLE = os.environ.get("PLEAT_EXECUTABLE", str(SOURCE / "build" / "cli" / "pleat"))


@pytest.fixture
def data():
    return SOURCE / "data"


def truncate_pc2(source, target, frames):
    """The first `frames` samples of the PC2 cache `source`, byte for byte, as `target`."""
    data = pathlib.Path(source).read_bytes()
    points = struct.unpack_from("<i", data, 16)[0]
    header = bytearray(data[:32])
    struct.pack_into("<i", header, 28, frames)
    pathlib.Path(target).write_bytes(bytes(header) + data[32:32 + frames * points * 12])


def run_cli(*args):
    """`pleat visibility ARGS -o -`: the (T, V, 2) front,back columns of its CSV, parsed exactly."""
    out = subprocess.run([EXECUTABLE, "-q", "visibility", *map(str, args), "-o", "-"], check=True,
                         capture_output=True, text=True).stdout
    rows = list(csv.reader(out.splitlines()))
    assert rows[0] == ["frame", "vertex", "front", "back", "source_frame"]
    frame = np.array([int(r[0]) for r in rows[1:]])
    values = np.array([[float(r[2]), float(r[3])] for r in rows[1:]])  # shortest repr: exact doubles
    frames = len(np.unique(frame))
    return values.reshape(frames, -1, 2)

"""pleat: per-vertex visibility cones and sky visibility of animated cloth (A. J. Stewart, "Computing
visibility from folded surfaces", 1999), with numpy arrays in and out.

    import pleat
    cloth = pleat.load("data/drape/drape.obj", cache="data/drape/drape.pc2")
    sky = pleat.sky_visibility(cloth.faces, cloth.positions, ground="y=0")  # (T, V, 2): front, back

The options are those of `pleat visibility` (underscores for dashes): engine ("kinetic" or "static"; the
same results), orientations, spacing, spacing_edges, planes, adaptive, max_missing, cone_storage,
cone_reconstruction, paper, plan (a file written by --save-plan), occluders, ground ("y=0"), threads (like
--threads; None: all cores), max_edit_fraction; a misspelt one raises TypeError with the nearest name. Results are in the caller's vertex
order and equal, bit for bit, the command line's on the same input and options. The frames you pass are the
shot: as the whole file does for `pleat visibility`, their first frame sets the plan's orientations and
spacing (its planes are a lattice anchored in world space, over the box of every frame). To compute a part of
a shot as `pleat visibility --frames 85:90` does, pass the whole shot and frames="85:90" (or slice(85, 90)).

Ctrl+C stops a computation promptly (between frames and inside a long one) with KeyboardInterrupt; the
frames finished before it are in `out` when one was given (a note on the exception says how many).
progress= takes a tqdm bar (tqdm(total=...)) or any callable (done, total).

A vertex no triangle uses has no surface, so its values are NaN (empty in the CSV). Float arrays of any byte
order are read (float64 and float32 in place, others converted). Bad arrays raise ValueError (InputError, a
ValueError, for what the library rejects: non-finite coordinates, coordinates beyond 2^53, a mesh less than 1e-30
across, ...); bad files raise InputError naming the file and the place.
"""
from ._pleat import Engine, FrameResult, InputError, __version__, _load, _read_cone_cache, _sky_visibility

__all__ = ["ConeCache", "Engine", "FrameResult", "InputError", "LoadedMesh", "load", "read_cone_cache",
           "sky_visibility", "__version__"]


class LoadedMesh:
    """A cloth as pleat reads it from a file, in the file's vertex order (before welding).

    faces: (F, 3) int64, triangles (polygons are triangulated as the command line does)
    positions: (T, V, 3) float64, every frame
    fps: frames per second (0.0 for a single frame)
    source_frames: (T,) int64, the frames' numbers in the source (PC2 start frame + i x sample rate, the
        numbers in OBJ-sequence file names, MDD/glTF time x 24: the CSV's source_frame column)
    """

    __slots__ = ("faces", "positions", "fps", "source_frames", "path")

    def __init__(self, faces, positions, fps, source_frames, path):
        self.faces, self.positions, self.fps, self.source_frames, self.path = (
            faces, positions, fps, source_frames, path)

    def __repr__(self):
        t, v, _ = self.positions.shape
        return f"<pleat.LoadedMesh {self.path!r}: {t} frames x {v} vertices, {len(self.faces)} faces>"


def load(path, cache=None):
    """Reads any input `pleat visibility` reads: .obj (with a .pc2/.mdd `cache`), a numbered OBJ sequence
    (printf pattern or directory), .gltf/.glb. Raises InputError naming the file and the place."""
    import os

    path = os.fspath(path)
    faces, positions, fps, source_frames = _load(path, None if cache is None else os.fspath(cache))
    return LoadedMesh(faces, positions, fps, source_frames, path)


class ConeCache:
    """The values of a cone cache (`pleat visibility --cones`), per input vertex.

    sky_visibility: (T, V, 2) float64, A of the front and back
    frames: (T,) int64, each frame's index in the input (what --frames counts; the cache does not hold the
        source's frame numbers: LoadedMesh.source_frames[frames] gives them)
    times: (T,) float64, seconds
    """

    __slots__ = ("sky_visibility", "frames", "times", "path")

    def __init__(self, sky_visibility, frames, times, path):
        self.sky_visibility, self.frames, self.times, self.path = sky_visibility, frames, times, path

    def __repr__(self):
        t, v, _ = self.sky_visibility.shape
        return f"<pleat.ConeCache {self.path!r}: {t} frames x {v} vertices>"


def read_cone_cache(path):
    """Reads the values of a cone cache. Raises InputError naming the file and the byte where it is
    malformed."""
    import os

    path = os.fspath(path)
    return ConeCache(*_read_cone_cache(path), path)


def sky_visibility(faces, positions, *, frames=None, progress=None, out=None, **options):
    """Sky visibility A (front, back) of the shot's frames: (T, V, 2) float64 for (T, V, 3) positions, (V, 2)
    for (V, 3). Equal to the front,back columns of `pleat visibility` on the same frames and options.

    frames: which frames to compute, as `pleat visibility --frames` does (the plan still made from the whole
        shot): "85:90", "-10:", an int, a slice or a sequence of ints; the result has one row per frame.
    progress: called after each frame: a tqdm bar (its update(1)) or a callable progress(done, total).
    out: a C-contiguous float64 array of the result's shape to write into (the frames finished before an
        interrupt stay there).
    options: those of Engine (help(pleat.Engine))."""
    return _sky_visibility(faces, positions, frames=frames, progress=progress, out=out, **options)


def __dir__():
    return sorted(__all__)

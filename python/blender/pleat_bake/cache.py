# The baked results of one object: a NumPy .npz beside the .blend, <blend name>_pleat/<object name>.npz,
# holding `frames` (T,) int64 scene frame numbers (increasing), `front` and `back` (T, V) float32 sky
# visibility A per vertex in the mesh's vertex order. Written atomically (a temporary name, then a rename).

import os
import tempfile

import bpy
import numpy as np


def cache_path(obj):
    """Where obj's cache goes: (path as stored on the object, absolute path, beside the .blend?)."""
    name = bpy.path.clean_name(obj.name) + ".npz"
    if bpy.data.filepath:
        folder = bpy.path.clean_name(bpy.path.display_name_from_filepath(bpy.data.filepath)) + "_pleat"
        stored = "//" + folder + "/" + name
        return stored, bpy.path.abspath(stored), True
    absolute = os.path.join(tempfile.gettempdir(), "pleat_unsaved", name)
    return absolute, absolute, False


def write(path, frames, front, back):
    frames = np.asarray(frames, dtype=np.int64)
    front = np.asarray(front, dtype=np.float32)
    back = np.asarray(back, dtype=np.float32)
    if front.shape != back.shape or front.ndim != 2 or front.shape[0] != frames.shape[0]:
        raise ValueError("pleat cache: front and back must be (frames, vertices)")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    fd, temporary = tempfile.mkstemp(suffix=".npz", dir=os.path.dirname(path))
    try:
        with os.fdopen(fd, "wb") as out:
            np.savez(out, frames=frames, front=front, back=back)
        os.replace(temporary, path)
    except BaseException:
        os.unlink(temporary)
        raise


def read(path):
    """(frames, front, back) from a cache file; ValueError naming the file when it is not one."""
    with np.load(path) as data:
        try:
            frames, front, back = data["frames"], data["front"], data["back"]
        except KeyError as e:
            raise ValueError(f"{path}: not a pleat cache (no {e})") from None
    if (frames.ndim != 1 or front.ndim != 2 or front.shape != back.shape or front.shape[0] != frames.shape[0]
            or frames.shape[0] == 0 or np.any(np.diff(frames) <= 0)):
        raise ValueError(f"{path}: not a pleat cache (inconsistent shapes or frame numbers)")
    return frames, front, back

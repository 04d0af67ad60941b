# Results computed elsewhere onto the artist's object: "Load sky visibility" reads a `pleat visibility` CSV,
# a cone cache (`pleat visibility --cones`) or an add-on cache (.npz) and plays it back on the active mesh as
# a bake does (playback.py): the file must have the mesh's vertex count (the values go on its vertices in
# order, as the input of `pleat visibility` had them), and its frames are keyed by their source frame
# numbers (the CSV's source_frame column: PC2 start frame + index x sample rate, OBJ-sequence file numbers),
# which for a cache exported from this scene are the scene's frames. A cone cache holds input frame indices
# only: its frame i goes to the operator's First frame + i. The values are copied into the object's own cache
# beside the .blend (cache.py).

import os

import bpy
import numpy as np

from . import cache, playback

CSV_HEADER = "frame,vertex,front,back,source_frame"


def read_csv(path):
    """(source frames (T,), front (T, V), back (T, V)) of a `pleat visibility` CSV; ValueError naming the file
    and the line otherwise."""
    with open(path, encoding="utf-8") as f:
        header = f.readline().strip()
    if header != CSV_HEADER:
        raise ValueError(f"{path}: line 1: expected the header '{CSV_HEADER}' of `pleat visibility -o`")
    try:
        rows = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    except ValueError as e:
        raise ValueError(f"{path}: {e}") from None
    if rows.shape[0] == 0 or rows.shape[1] != 5:
        raise ValueError(f"{path}: no rows of 5 columns after the header")
    vertex, source = rows[:, 1].astype(np.int64), rows[:, 4].astype(np.int64)
    frames = np.unique(source)
    vertices = int(vertex.max()) + 1
    if rows.shape[0] != len(frames) * vertices:
        raise ValueError(f"{path}: {rows.shape[0]} rows for {len(frames)} frames of {vertices} vertices (a frame "
                         "or a vertex is missing)")
    front = np.full((len(frames), vertices), np.nan, dtype=np.float32)
    back = np.full_like(front, np.nan)
    at = np.searchsorted(frames, source)
    front[at, vertex], back[at, vertex] = rows[:, 2], rows[:, 3]
    if np.isnan(front).any():
        raise ValueError(f"{path}: a (source frame, vertex) pair repeats while another is missing")
    return frames, front, back


def read_cones(path, first_frame):
    """(scene frames, front, back) of a cone cache, read by the pleat module (one reader of the format); its
    input frame i is scene frame first_frame + i."""
    import pleat

    cones = pleat.read_cone_cache(path)
    frames = first_frame + cones.frames.astype(np.int64)
    return frames, cones.sky_visibility[:, :, 0], cones.sky_visibility[:, :, 1]


def load_onto(obj, path, first_frame):
    """Reads `path` (by its extension) and makes it obj's playback cache; returns (frames, where stored)."""
    kind = os.path.splitext(path)[1].lower()
    if kind == ".csv":
        frames, front, back = read_csv(path)
    elif kind == ".cones":
        frames, front, back = read_cones(path, first_frame)
    elif kind == ".npz":
        frames, front, back = cache.read(path)
    else:
        raise ValueError(f"{path}: not a .csv, .cones or .npz file")
    vertices = len(obj.data.vertices)
    if front.shape[1] != vertices:
        raise ValueError(f"{path} has {front.shape[1]} vertices, {obj.name}'s mesh {vertices}: load it onto "
                         "the mesh it was computed for (same vertices, same order)")
    stored, target, _ = cache.cache_path(obj)
    cache.write(target, frames, front, back)
    obj[playback.CACHE_PROPERTY] = stored
    playback.ensure_attributes(obj.data)
    return frames, target


class PLEAT_OT_load(bpy.types.Operator):
    """Play back sky visibility computed elsewhere (a pleat CSV, cone cache or add-on cache) on the active
    mesh, frame by frame by source frame number"""
    bl_idname = "pleat.load_sky_visibility"
    bl_label = "Load sky visibility"
    bl_options = {"REGISTER", "UNDO"}

    filepath: bpy.props.StringProperty(subtype="FILE_PATH")
    filter_glob: bpy.props.StringProperty(default="*.csv;*.cones;*.npz", options={"HIDDEN"})
    first_frame: bpy.props.IntProperty(
        name="First frame", default=1,
        description="A cone cache's frames are the input's frame indices: the scene frame of the input's "
                    "first frame (a CSV names its source frames itself)")

    @classmethod
    def poll(cls, context):
        return context.active_object is not None and context.active_object.type == "MESH"

    def invoke(self, context, event):
        self.first_frame = context.scene.frame_start
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context):
        obj = context.active_object
        try:
            frames, target = load_onto(obj, bpy.path.abspath(self.filepath), self.first_frame)
        except ImportError as e:
            self.report({"ERROR"}, f"a cone cache is read by the pleat module, not importable here ({e})")
            return {"CANCELLED"}
        except (ValueError, OSError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        playback.apply_all(context.scene)
        self.report({"INFO"}, f"pleat: frames {frames[0]}-{frames[-1]} of {self.filepath} on {obj.name} "
                              f"({target})")
        return {"FINISHED"}

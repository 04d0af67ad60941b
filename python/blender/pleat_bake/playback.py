# Playing a bake back: at every frame change the baked object's own mesh gets that frame's values as
# attributes (pleat_front, pleat_back: float, point domain; pleat_sky_color and pleat_sky_color_back: each
# side's A as a grey float colour). The shader node group "pleat sky visibility" (shading.py) reads them.
#
# The values are written in frame_change_pre, before the depsgraph evaluates the new frame, and the mesh is
# tagged so that its evaluated copy (after modifiers) takes them. That tag re-evaluates the mesh, which
# clears an unbaked physics cache; the bake operator therefore asks for baked caches (bake.py).

import os

import bpy
import numpy as np
from bpy.app.handlers import persistent

from . import cache

CACHE_PROPERTY = "pleat_cache"
FRONT, BACK = "pleat_front", "pleat_back"
COLOR, COLOR_BACK = "pleat_sky_color", "pleat_sky_color_back"

suspended = False  # True while a bake steps through frames: it reads meshes and must not change them
_loaded = {}  # absolute path -> (mtime, (frames, front, back))
_warned = set()


def _cache_of(path):
    mtime = os.path.getmtime(path)
    hit = _loaded.get(path)
    if hit is None or hit[0] != mtime:
        hit = (mtime, cache.read(path))
        _loaded[path] = hit
    return hit[1]


def ensure_attributes(mesh):
    """Creates the attributes the playback writes (changes the mesh's layers: only when baking)."""
    for name in (FRONT, BACK):
        if name not in mesh.attributes:
            mesh.attributes.new(name, "FLOAT", "POINT")
    for name in (COLOR, COLOR_BACK):
        if name not in mesh.attributes:
            mesh.color_attributes.new(name, "FLOAT_COLOR", "POINT")


def apply(obj, frame):
    """Writes the values of the baked frame at or before `frame` (the first one before the range) on obj's
    mesh. Raises ValueError when the cache is missing or does not fit the mesh."""
    path = bpy.path.abspath(obj[CACHE_PROPERTY])
    if not os.path.isfile(path):
        raise ValueError(f"{obj.name}: the pleat cache {path} is missing")
    frames, front, back = _cache_of(path)
    mesh = obj.data
    n = len(mesh.vertices)
    if front.shape[1] != n:
        raise ValueError(f"{obj.name}: the pleat cache {path} has {front.shape[1]} vertices, the mesh {n}")
    if any(name not in mesh.attributes for name in (FRONT, BACK)):
        raise ValueError(f"{obj.name}: the mesh lost the pleat attributes; bake again")
    k = int(np.clip(np.searchsorted(frames, frame, side="right") - 1, 0, len(frames) - 1))
    mesh.attributes[FRONT].data.foreach_set("value", front[k])
    mesh.attributes[BACK].data.foreach_set("value", back[k])
    rgba = np.ones((n, 4), dtype=np.float32)
    for name, values in ((COLOR, front[k]), (COLOR_BACK, back[k])):
        if name not in mesh.attributes:  # baked by an older add-on: bake again for both colours
            continue
        rgba[:, :3] = values[:, None]
        mesh.attributes[name].data.foreach_set("color", rgba.ravel())
    mesh.update_tag()


def apply_all(scene):
    if suspended:
        return
    for obj in scene.objects:
        if obj.type != "MESH" or CACHE_PROPERTY not in obj:
            continue
        try:
            apply(obj, scene.frame_current)
        except (ValueError, OSError) as e:
            if str(e) not in _warned:  # once per problem, not at every frame
                _warned.add(str(e))
                print("pleat:", e)


@persistent
def _on_frame_change(scene, *args):
    apply_all(scene)


@persistent
def _on_load(*args):
    _loaded.clear()
    _warned.clear()
    if bpy.context.scene is not None:
        apply_all(bpy.context.scene)


def register():
    bpy.app.handlers.frame_change_pre.append(_on_frame_change)
    bpy.app.handlers.load_post.append(_on_load)


def unregister():
    bpy.app.handlers.frame_change_pre.remove(_on_frame_change)
    bpy.app.handlers.load_post.remove(_on_load)

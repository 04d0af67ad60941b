# Playing a bake back: at every frame change the baked object's own mesh gets that frame's values as
# attributes (pleat_front, pleat_back: float, point domain; pleat_sky_color: front A as a grey float colour),
# and a material template shows them (an Attribute node per side, mixed by Geometry ▸ Backfacing).
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
FRONT, BACK, COLOR = "pleat_front", "pleat_back", "pleat_sky_color"
MATERIAL = "pleat sky visibility"

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
    if COLOR not in mesh.attributes:
        mesh.color_attributes.new(COLOR, "FLOAT_COLOR", "POINT")


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
    if any(name not in mesh.attributes for name in (FRONT, BACK, COLOR)):
        raise ValueError(f"{obj.name}: the mesh lost the pleat attributes; bake again")
    k = int(np.clip(np.searchsorted(frames, frame, side="right") - 1, 0, len(frames) - 1))
    mesh.attributes[FRONT].data.foreach_set("value", front[k])
    mesh.attributes[BACK].data.foreach_set("value", back[k])
    rgba = np.ones((n, 4), dtype=np.float32)
    rgba[:, :3] = front[k][:, None]
    mesh.attributes[COLOR].data.foreach_set("color", rgba.ravel())
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


def material_template():
    """The material "pleat sky visibility" (made once): A of the side the camera sees, as emission."""
    material = bpy.data.materials.get(MATERIAL)
    if material is not None:
        return material
    material = bpy.data.materials.new(MATERIAL)
    material.use_nodes = True
    nodes, links = material.node_tree.nodes, material.node_tree.links
    nodes.clear()
    front = nodes.new("ShaderNodeAttribute")
    front.attribute_name, front.location = FRONT, (-600, 150)
    back = nodes.new("ShaderNodeAttribute")
    back.attribute_name, back.location = BACK, (-600, -50)
    geometry = nodes.new("ShaderNodeNewGeometry")
    geometry.location = (-600, 350)
    mix = nodes.new("ShaderNodeMix")
    mix.data_type, mix.location = "FLOAT", (-350, 150)
    factor = next(s for s in mix.inputs if s.name == "Factor" and s.type == "VALUE")
    a = next(s for s in mix.inputs if s.name == "A" and s.type == "VALUE")
    b = next(s for s in mix.inputs if s.name == "B" and s.type == "VALUE")
    links.new(geometry.outputs["Backfacing"], factor)
    links.new(front.outputs["Fac"], a)
    links.new(back.outputs["Fac"], b)
    emission = nodes.new("ShaderNodeEmission")
    emission.location = (-150, 150)
    links.new(next(s for s in mix.outputs if s.name == "Result" and s.type == "VALUE"),
              emission.inputs["Color"])
    output = nodes.new("ShaderNodeOutputMaterial")
    output.location = (50, 150)
    links.new(emission.outputs["Emission"], output.inputs["Surface"])
    return material


class PLEAT_OT_material(bpy.types.Operator):
    """Add the material template that shows the baked sky visibility (front or back by the side seen)"""
    bl_idname = "pleat.add_material"
    bl_label = "Add sky visibility material"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return context.active_object is not None and context.active_object.type == "MESH"

    def execute(self, context):
        obj = context.active_object
        material = material_template()
        if material.name not in obj.data.materials:
            obj.data.materials.append(material)
        return {"FINISHED"}


def register():
    bpy.app.handlers.frame_change_pre.append(_on_frame_change)
    bpy.app.handlers.load_post.append(_on_load)


def unregister():
    bpy.app.handlers.frame_change_pre.remove(_on_frame_change)
    bpy.app.handlers.load_post.remove(_on_load)

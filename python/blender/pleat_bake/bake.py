# The "Bake sky visibility" operator: steps through the scene's frame range reading the evaluated meshes,
# runs pleat's engine over the frames (through the `pleat` Python module), and stores the result for
# playback (cache.py, playback.py). Interactively it is modal: one step per timer tick, progress in the
# window manager's progress bar and the status bar, Esc cancels (nothing is written). From a script
# (`bpy.ops.pleat.bake_sky_visibility()`, or `blender -b`) it runs to the end in one call.

import bpy
import numpy as np

from . import cache, playback, shading


class BakeError(Exception):
    """A reason the bake cannot go on, for the user (reported, not raised out of the operator)."""


class MeshReading:
    """What the bake reads of an evaluated mesh at one frame: its polygons (connectivity) and its vertices'
    world positions."""

    __slots__ = ("corners", "loop_starts", "positions", "tessellation")

    def __init__(self, corners, loop_starts, positions, tessellation):
        self.corners = corners          # (L,) int32: each loop's vertex
        self.loop_starts = loop_starts  # (P,) int32: each polygon's first loop
        self.positions = positions      # (V, 3) float64, world space
        self.tessellation = tessellation  # (F, 3) int32 loop indices of Blender's loop triangles, or None

    def same_polygons(self, other):
        return (np.array_equal(self.corners, other.corners)
                and np.array_equal(self.loop_starts, other.loop_starts))

    def triangles(self, split):
        """(F, 3) int64 vertex triangles of `split` (loop triangles of a reading with these polygons)."""
        return self.corners[split].astype(np.int64)


def read_mesh(obj, depsgraph, tessellate):
    """obj's evaluated mesh at the current frame as a MeshReading; with `tessellate`, Blender's loop triangles
    of this frame's shape (convex or concave polygons split inside their outline)."""
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        positions = np.empty(3 * len(mesh.vertices), dtype=np.float64)
        mesh.vertices.foreach_get("co", positions)
        corners = np.empty(len(mesh.loops), dtype=np.int32)
        mesh.loops.foreach_get("vertex_index", corners)
        loop_starts = np.empty(len(mesh.polygons), dtype=np.int32)
        mesh.polygons.foreach_get("loop_start", loop_starts)
        tessellation = None
        if tessellate:
            mesh.calc_loop_triangles()
            tessellation = np.empty(3 * len(mesh.loop_triangles), dtype=np.int32)
            mesh.loop_triangles.foreach_get("loops", tessellation)
            tessellation = tessellation.reshape(-1, 3)
        matrix = np.array(evaluated.matrix_world, dtype=np.float64)
    finally:
        evaluated.to_mesh_clear()
    positions = positions.reshape(-1, 3) @ matrix[:3, :3].T + matrix[:3, 3]
    return MeshReading(corners, loop_starts, positions, tessellation)


class FixedSplit:
    """One object's frames over one triangulation: Blender splits a quad or n-gon along the diagonals that suit
    each frame's shape (a folding quad changes diagonal from frame to frame), but pleat needs the same
    triangles in every frame, so the split of the first frame read is kept for all. Later frames must have
    the same polygons (vertices in the same order)."""

    def __init__(self, name):
        self.name = name
        self.first = None  # MeshReading of the first frame
        self.faces = None  # (F, 3) int64
        self.frames = []   # (V, 3) world positions per frame

    def add(self, obj, depsgraph, frame):
        reading = read_mesh(obj, depsgraph, tessellate=self.first is None)
        if self.first is None:
            self.first = reading
            self.faces = reading.triangles(reading.tessellation)
        elif len(reading.positions) != len(self.first.positions) or not reading.same_polygons(self.first):
            raise BakeError(f"{self.name}: the evaluated mesh changes its vertices or polygons at frame {frame} "
                            "(pleat needs the same vertices and polygons over the frame range; a modifier "
                            "that remeshes, or a cloth whose faces tear, cannot be baked)")
        self.frames.append(reading.positions)

    def positions(self):
        return np.stack(self.frames)


def engine_options(settings):
    """The keyword options of pleat.Engine / pleat.sky_visibility the panel's settings give."""
    options = {"engine": settings.engine}
    if settings.plan:
        options["plan"] = bpy.path.abspath(settings.plan)
    else:
        if settings.orientations > 0:
            options["orientations"] = settings.orientations
        if settings.spacing > 0.0:
            options["spacing"] = settings.spacing
        if settings.paper:
            options["paper"] = True
    if settings.ground:
        options["ground"] = f"z={settings.ground_height!r}"
    if settings.contact_tolerance > 0.0:
        options["contact_tolerance"] = settings.contact_tolerance
    return options


def unbaked_caches(obj):
    """Names of obj's physics modifiers whose point cache is not baked."""
    return [m.name for m in obj.modifiers
            if m.type in {"CLOTH", "SOFT_BODY"} and not m.point_cache.is_baked]


def check(context):
    """The object to bake, or BakeError saying why not."""
    obj = context.active_object
    if obj is None or obj.type != "MESH":
        raise BakeError("select the cloth: the active object must be a mesh")
    unbaked = unbaked_caches(obj)
    if unbaked:
        raise BakeError(f"{obj.name}: bake the physics cache first ({', '.join(unbaked)}: Physics ▸ Cache "
                        "▸ Bake); playing the visibility back re-evaluates the mesh, which clears an unbaked "
                        "cache")
    scene = context.scene
    if scene.frame_end < scene.frame_start:
        raise BakeError("the scene's frame range is empty")
    return obj


def bake_steps(scene, obj):
    """Generator of (fraction done, status text): the whole bake of obj over scene's frame range, one frame
    per step. Leaves the scene at the frame it started from, also when closed early (cancelled) or failing.
    Reads bpy.context at each step (a modal operator's steps run in different callbacks)."""
    import pleat  # here, so that the add-on registers (and says what is missing) without the module

    settings = scene.pleat
    frames = list(range(scene.frame_start, scene.frame_end + 1))
    occluder_objects = [o for o in (settings.occluders.all_objects if settings.occluders else [])
                        if o.type == "MESH" and o != obj]
    start_frame, start_subframe = scene.frame_current, scene.frame_subframe
    total = 2 * len(frames)
    playback.suspended = True
    try:
        cloth = FixedSplit(obj.name)
        occluders = [FixedSplit(f"occluder {o.name}") for o in occluder_objects]
        for k, frame in enumerate(frames):
            scene.frame_set(frame)
            depsgraph = bpy.context.evaluated_depsgraph_get()
            cloth.add(obj, depsgraph, frame)
            if k == 0:
                if len(cloth.faces) == 0:
                    raise BakeError(f"{obj.name}: the evaluated mesh has no faces at frame {frame}")
                if len(cloth.first.positions) != len(obj.data.vertices):
                    raise BakeError(f"{obj.name}: its modifiers make {len(cloth.first.positions)} vertices of "
                                    f"the mesh's {len(obj.data.vertices)}; the results go on the mesh's own "
                                    "vertices, so the modifiers must keep them (disable subdivision and the "
                                    "like while baking)")
            for split, o in zip(occluders, occluder_objects):
                split.add(o, depsgraph, frame)
            yield (k + 1) / total, f"pleat: reading frame {frame}"

        faces, positions = cloth.faces, cloth.positions()
        # An occluder that does not move is passed once (V,3), one that does per frame (T,V,3).
        occluder_arrays = []
        for split in occluders:
            if len(split.faces) == 0:
                continue
            stacked = split.positions()
            occluder_arrays.append((split.faces, stacked[0] if np.all(stacked == stacked[0]) else stacked))
        try:
            engine = pleat.Engine(faces, positions, occluders=occluder_arrays, **engine_options(settings))
        except ValueError as e:
            raise BakeError(str(e)) from None
        front = np.empty((len(frames), positions.shape[1]), dtype=np.float32)
        back = np.empty_like(front)
        for k, frame in enumerate(frames):
            try:
                visibility = engine.compute(positions[k], frame_index=k, keep_cones=False).sky_visibility
            except ValueError as e:
                raise BakeError(f"frame {frame}: {e}") from None
            front[k], back[k] = visibility[:, 0], visibility[:, 1]
            yield (len(frames) + k + 1) / total, f"pleat: sky visibility of frame {frame}"

        stored, path, beside_blend = cache.cache_path(obj)
        cache.write(path, frames, front, back)
        obj[playback.CACHE_PROPERTY] = stored
        playback.ensure_attributes(obj.data)
        if not obj.data.materials:
            obj.data.materials.append(shading.material_template())
        else:
            shading.node_group()  # for the artist's own materials (Insert into materials)
        keep = "" if beside_blend else " (save the .blend to keep it beside it)"
        yield 1.0, f"pleat: wrote {path}{keep}"
    finally:
        playback.suspended = False
        scene.frame_set(start_frame, subframe=start_subframe)


class PLEAT_OT_bake(bpy.types.Operator):
    """Compute the sky visibility of the active object's both sides over the scene's frame range (pleat),
    occluded by the chosen collection, and play it back as mesh attributes"""
    bl_idname = "pleat.bake_sky_visibility"
    bl_label = "Bake sky visibility"
    bl_options = {"REGISTER"}

    @classmethod
    def poll(cls, context):
        return context.active_object is not None and context.active_object.type == "MESH"

    def _start(self, context):
        try:
            obj = check(context)
            self._steps = bake_steps(context.scene, obj)
            self._fraction, self._last = 0.0, ""
            return True
        except BakeError as e:
            self.report({"ERROR"}, str(e))
            return False

    def _step(self):
        """One step; False when the bake ended (finished or failed: reported)."""
        try:
            self._fraction, self._last = next(self._steps)
            return True
        except StopIteration:
            self.report({"INFO"}, self._last)
            return False
        except ImportError as e:
            self._failed = True
            self.report({"ERROR"}, f"the pleat Python module is not importable from Blender's Python ({e}); "
                                   "install it for Debian's python3 (README, Python)")
            return False
        except BakeError as e:
            self._failed = True
            self.report({"ERROR"}, str(e))
            return False
        except Exception as e:  # the module's or the file system's: reported, not a traceback
            self._failed = True
            self.report({"ERROR"}, f"pleat: {type(e).__name__}: {e}")
            return False

    def execute(self, context):
        self._failed = False
        if not self._start(context):
            return {"CANCELLED"}
        while self._step():
            pass
        return {"CANCELLED"} if self._failed else {"FINISHED"}

    def invoke(self, context, event):
        if context.window is None:  # no window to run modally in (blender -b): all at once
            return self.execute(context)
        self._failed = False
        if not self._start(context):
            return {"CANCELLED"}
        wm = context.window_manager
        wm.progress_begin(0.0, 1.0)
        self._timer = wm.event_timer_add(0.01, window=context.window)
        wm.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def _end(self, context):
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        context.workspace.status_text_set(None)

    def modal(self, context, event):
        if event.type == "ESC" and event.value == "PRESS":
            self._steps.close()  # restores the frame; nothing was written
            self._end(context)
            self.report({"WARNING"}, "pleat: bake cancelled, nothing written")
            return {"CANCELLED"}
        if event.type != "TIMER":
            return {"RUNNING_MODAL"}  # the scene must not change under the bake
        if self._step():
            context.window_manager.progress_update(self._fraction)
            context.workspace.status_text_set(self._last + " (Esc cancels)")
            return {"RUNNING_MODAL"}
        self._end(context)
        return {"CANCELLED"} if self._failed else {"FINISHED"}

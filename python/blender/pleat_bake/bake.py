# The "Bake sky visibility" operator: steps through the scene's frame range reading the evaluated meshes,
# runs pleat's engine over the frames (through the `pleat` Python module), and stores the result for
# playback (cache.py, playback.py). Interactively it is modal: one step per timer tick, progress in the
# window manager's progress bar and the status bar, Esc cancels (nothing is written). From a script
# (`bpy.ops.pleat.bake_sky_visibility()`, or `blender -b`) it runs to the end in one call.

import bpy
import numpy as np

from . import cache, playback


class BakeError(Exception):
    """A reason the bake cannot go on, for the user (reported, not raised out of the operator)."""


def world_mesh(obj, depsgraph):
    """(triangles (F,3) int64, world positions (V,3) float64) of obj's evaluated mesh."""
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        positions = np.empty(3 * len(mesh.vertices), dtype=np.float64)
        mesh.vertices.foreach_get("co", positions)
        mesh.calc_loop_triangles()
        triangles = np.empty(3 * len(mesh.loop_triangles), dtype=np.int32)
        mesh.loop_triangles.foreach_get("vertices", triangles)
        matrix = np.array(evaluated.matrix_world, dtype=np.float64)
    finally:
        evaluated.to_mesh_clear()
    positions = positions.reshape(-1, 3) @ matrix[:3, :3].T + matrix[:3, 3]
    return triangles.reshape(-1, 3).astype(np.int64), positions


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
        faces, positions = None, []
        occluders = [(None, []) for _ in occluder_objects]
        for k, frame in enumerate(frames):
            scene.frame_set(frame)
            depsgraph = bpy.context.evaluated_depsgraph_get()
            triangles, p = world_mesh(obj, depsgraph)
            if faces is None:
                faces = triangles
                if len(faces) == 0:
                    raise BakeError(f"{obj.name}: the evaluated mesh has no faces at frame {frame}")
                if len(p) != len(obj.data.vertices):
                    raise BakeError(f"{obj.name}: its modifiers make {len(p)} vertices of the mesh's "
                                    f"{len(obj.data.vertices)}; the results go on the mesh's own vertices, "
                                    "so the modifiers must keep them (disable subdivision and the like "
                                    "while baking)")
            elif len(p) != len(positions[0]) or not np.array_equal(triangles, faces):
                raise BakeError(f"{obj.name}: the evaluated mesh changes its vertices or faces at frame "
                                f"{frame} (pleat needs the same connectivity over the frame range)")
            positions.append(p)
            for i, o in enumerate(occluder_objects):
                o_triangles, o_positions = world_mesh(o, depsgraph)
                o_faces, o_frames = occluders[i]
                if o_faces is None:
                    occluders[i] = (o_triangles, o_frames)
                elif len(o_positions) != len(o_frames[0]) or not np.array_equal(o_triangles, o_faces):
                    raise BakeError(f"occluder {o.name}: the evaluated mesh changes its vertices or faces "
                                    f"at frame {frame}")
                o_frames.append(o_positions)
            yield (k + 1) / total, f"pleat: reading frame {frame}"

        positions = np.stack(positions)
        # An occluder that does not move is passed once (V,3), one that does per frame (T,V,3).
        occluder_arrays = []
        for o_faces, o_frames in occluders:
            if len(o_faces) == 0:
                continue
            stacked = np.stack(o_frames)
            occluder_arrays.append((o_faces, stacked[0] if np.all(stacked == stacked[0]) else stacked))
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
            obj.data.materials.append(playback.material_template())
        else:
            playback.material_template()
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

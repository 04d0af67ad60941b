# The Blender add-on (python/blender/pleat_bake) against the command line, run by ctest in Blender headless:
#   blender -b --factory-startup --python-exit-code 1 --python tests/blender/bake_test.py -- \
#       --pleat PLEAT_EXECUTABLE --module-dir DIR_WITH_THE_PLEAT_MODULE --work SCRATCH_DIR
# A cloth grid falls on a sphere (cloth modifier, collision) for a few frames and its cache is baked; the
# operator bakes the sky visibility with the sphere's collection as occluders and a ground; the attributes
# the playback writes at each frame must equal the front/back columns of `pleat visibility` run on the same
# frames exported as a numbered OBJ sequence (numbered by scene frame, so the CSV's source_frame column
# names them) with the sphere as --occluder. Also: the physics cache survives playback, a cancelled bake
# writes nothing and leaves the frame as it was, and an unbaked cloth or a modifier that changes the vertices
# is refused with a message.

import argparse
import csv
import os
import shutil
import subprocess
import sys

import bpy
import numpy as np

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
parser = argparse.ArgumentParser()
parser.add_argument("--pleat", required=True)
parser.add_argument("--module-dir", required=True)
parser.add_argument("--work", required=True)
args = parser.parse_args(argv)

sys.path.insert(0, args.module_dir)
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python", "blender"))
import pleat_bake  # noqa: E402
from pleat_bake import bake, playback  # noqa: E402

FIRST, LAST = 3, 8  # scene frames: not starting at 0 or 1, so that frame numbers are checked
GROUND = -0.75
failures = []


def expect(condition, message):
    if not condition:
        failures.append(message)
        print("FAILED:", message)


shutil.rmtree(args.work, ignore_errors=True)
os.makedirs(args.work)
bpy.ops.wm.read_factory_settings(use_empty=True)
pleat_bake.register()
scene = bpy.context.scene
scene.frame_start, scene.frame_end = FIRST, LAST

occluders = bpy.data.collections.new("Colliders")
scene.collection.children.link(occluders)
bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, segments=16, ring_count=8, location=(0.1, 0.0, 0.0))
sphere = bpy.context.active_object
sphere.modifiers.new("Collision", "COLLISION")
for c in list(sphere.users_collection):
    c.objects.unlink(sphere)
occluders.objects.link(sphere)

bpy.ops.mesh.primitive_grid_add(x_subdivisions=10, y_subdivisions=10, size=1.6, location=(0.0, 0.0, 0.62))
cloth = bpy.context.active_object
cloth.modifiers.new("Cloth", "CLOTH")
cloth.modifiers["Cloth"].settings.quality = 4
cache = cloth.modifiers["Cloth"].point_cache
cache.frame_start, cache.frame_end = 1, LAST  # simulated from frame 1: the baked range starts mid-fall
bpy.ops.wm.save_as_mainfile(filepath=os.path.join(args.work, "scene.blend"))

# An unbaked cloth is refused (playing back would clear its cache).
bpy.context.view_layer.objects.active = cloth
try:
    bpy.ops.pleat.bake_sky_visibility()
    expect(False, "baking over an unbaked cloth cache was accepted")
except RuntimeError as e:
    expect("bake the physics cache first" in str(e), f"unbaked cache: unexpected message {e}")

with bpy.context.temp_override(scene=scene, point_cache=cache):
    bpy.ops.ptcache.bake(bake=True)
expect(cache.is_baked, "the cloth cache did not bake")


def evaluated(obj):
    """(triangles, world positions in float64) of obj's evaluated mesh, written here rather than taken from
    the add-on; checked against Blender's own (float32) transform of the mesh."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated_obj = obj.evaluated_get(depsgraph)
    mesh = evaluated_obj.to_mesh()
    local = np.array([v.co[:] for v in mesh.vertices], dtype=np.float64)
    mesh.calc_loop_triangles()
    triangles = np.array([t.vertices[:] for t in mesh.loop_triangles], dtype=np.int64)
    matrix = np.array(evaluated_obj.matrix_world, dtype=np.float64)
    mesh.transform(evaluated_obj.matrix_world)
    by_blender = np.array([v.co[:] for v in mesh.vertices], dtype=np.float64)
    evaluated_obj.to_mesh_clear()
    world = local @ matrix[:3, :3].T + matrix[:3, 3]
    expect(np.allclose(world, by_blender, atol=1e-6), f"{obj.name}: world positions differ from Blender's")
    return triangles, world


simulated = {}
for frame in range(FIRST, LAST + 1):
    scene.frame_set(frame)
    simulated[frame] = evaluated(cloth)[1]
expect(np.ptp(simulated[LAST][:, 2]) > 0.05, "the cloth did not drape over the sphere")

settings = scene.pleat
settings.occluders = occluders
settings.engine = "kinetic"
settings.ground, settings.ground_height = True, GROUND

# A cancelled bake (the generator closed early, as Esc does) writes nothing and restores the frame.
scene.frame_set(5)
steps = bake.bake_steps(scene, cloth)
next(steps)
next(steps)
steps.close()
expect(scene.frame_current == 5, "a cancelled bake did not restore the frame")
expect(playback.CACHE_PROPERTY not in cloth, "a cancelled bake named a cache")
expect(not os.path.exists(os.path.join(args.work, "scene_pleat")), "a cancelled bake wrote a cache")

# A modifier that changes the vertices (the results go on the mesh's own) is refused.
subdivision = cloth.modifiers.new("Subdivision", "SUBSURF")
try:
    bpy.ops.pleat.bake_sky_visibility()
    expect(False, "a bake through a subdivision modifier was accepted")
except RuntimeError as e:
    expect("modifiers make" in str(e), f"subdivided: unexpected message {e}")
cloth.modifiers.remove(subdivision)
expect(scene.frame_current == 5, "a refused bake did not restore the frame")

result = bpy.ops.pleat.bake_sky_visibility("INVOKE_DEFAULT")  # as the panel's button; no window: at once
expect(result == {"FINISHED"}, f"the bake returned {result}")
expect(scene.frame_current == 5, "the bake did not restore the frame")
cache_file = os.path.join(args.work, "scene_pleat", "Grid.npz")
expect(cloth.get(playback.CACHE_PROPERTY) == "//scene_pleat/Grid.npz", "the object does not name its cache")
expect(os.path.isfile(cache_file), f"no cache at {cache_file}")
expect(playback.MATERIAL in cloth.data.materials, "the material template was not assigned")


def attribute(mesh, name):
    values = np.empty(len(mesh.vertices), dtype=np.float32)
    mesh.attributes[name].data.foreach_get("value", values)
    return values


# Play back, out of order: each frame's attributes, on the mesh and after the modifiers.
baked = {}
for frame in [7, FIRST, 6, LAST, 4, 5]:
    scene.frame_set(frame)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    shown = cloth.evaluated_get(depsgraph).data
    front, back = attribute(cloth.data, playback.FRONT), attribute(cloth.data, playback.BACK)
    expect(np.array_equal(attribute(shown, playback.FRONT), front), f"frame {frame}: evaluated front differs")
    expect(np.array_equal(attribute(shown, playback.BACK), back), f"frame {frame}: evaluated back differs")
    color = np.empty(4 * len(front), dtype=np.float32)
    cloth.data.attributes[playback.COLOR].data.foreach_get("color", color)
    expect(np.array_equal(color.reshape(-1, 4)[:, 0], front), f"frame {frame}: colour is not front A")
    expect(np.array_equal(evaluated(cloth)[1], simulated[frame]), f"frame {frame}: playback moved the cloth")
    baked[frame] = (front, back)
scene.frame_set(FIRST - 2)  # before the range: the first baked frame holds
expect(np.array_equal(attribute(cloth.data, playback.FRONT), baked[FIRST][0]), "before the range")

# The same frames through the command line.
frames_dir = os.path.join(args.work, "frames")
os.makedirs(frames_dir)
for frame in range(FIRST, LAST + 1):
    scene.frame_set(frame)
    triangles, positions = evaluated(cloth)
    with open(os.path.join(frames_dir, f"cloth_{frame:04d}.obj"), "w") as out:
        out.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in positions)
        out.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in triangles)
triangles, positions = evaluated(sphere)
with open(os.path.join(args.work, "sphere.obj"), "w") as out:
    out.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in positions)
    out.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in triangles)
csv_path = os.path.join(args.work, "visibility.csv")
run = subprocess.run([args.pleat, "visibility", os.path.join(frames_dir, "cloth_%04d.obj"), "--occluder",
                      os.path.join(args.work, "sphere.obj"), "--ground", f"z={GROUND!r}",
                      "--engine", "kinetic",
                      "-o", csv_path, "-q"], capture_output=True, text=True)
if run.returncode != 0:
    print("FAILED: pleat visibility:", run.stdout, run.stderr)
    sys.exit(1)
cli = {}
with open(csv_path) as f:
    for row in csv.DictReader(f):
        front, back = cli.setdefault(int(row["source_frame"]), ([], []))
        front.append(float(row["front"]))
        back.append(float(row["back"]))
expect(sorted(cli) == list(range(FIRST, LAST + 1)), f"the CSV's source frames are {sorted(cli)}")
worst = 0.0
for frame, (front, back) in baked.items():
    if frame not in cli:
        continue
    for side, (mine, theirs) in enumerate(zip((front, back), cli[frame])):
        theirs = np.asarray(theirs, dtype=np.float32)  # the attributes are float32
        expect(len(theirs) == len(mine), f"frame {frame}: vertex counts differ")
        if len(theirs) == len(mine):
            worst = max(worst, float(np.max(np.abs(mine - theirs))))
            expect(np.array_equal(mine, theirs),
                   f"frame {frame}, side {side}: the add-on differs from the CLI")
occluded = min(float(np.min(back)) for front, back in baked.values())
expect(occluded < 0.9, f"nothing occludes the underside of the cloth (min back A {occluded})")
print(f"blender bake: {len(baked)} frames x {len(cloth.data.vertices)} vertices; largest difference from the "
      f"CLI {worst}; failures: {len(failures)}")
pleat_bake.unregister()
expect(playback._on_frame_change not in bpy.app.handlers.frame_change_pre, "unregister left the handler")
if failures:
    sys.exit(1)

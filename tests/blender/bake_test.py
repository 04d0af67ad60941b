# The Blender add-on (python/blender/pleat_bake) against the command line, run by ctest in Blender headless
# after the add-on was installed the README's way (python/blender/install.py into BLENDER_USER_SCRIPTS, its
# preferences saved in BLENDER_USER_CONFIG; both set by ctest, see tests/CMakeLists.txt):
#   blender -b --python-exit-code 1 --python tests/blender/bake_test.py -- --pleat PLEAT --work SCRATCH_DIR
# A cloth made as a Blender user makes one: a plane subdivided into a 41 x 41 grid of quads, one corner's
# three quads dissolved into a concave n-gon, with cloth physics, dropped on a cube (collision, in the
# occluders' collection) over a ground plane (collision; given to pleat as its exact ground) and its cache
# baked. Blender re-splits folded quads between frames (checked: the case this test is for); the add-on keeps
# the first frame's split. The attributes the playback writes at each frame must equal the front/back
# columns of `pleat visibility` run on the same frames exported as a numbered OBJ sequence with that split
# (numbered by scene frame, so the CSV's source_frame column names them) with the cube as --occluder. Also:
# the physics cache survives playback, a cancelled bake writes nothing and leaves the frame as it was, and
# an unbaked cloth or a modifier that changes the vertices is refused with a message.

import argparse
import csv
import os
import shutil
import subprocess
import sys

import bmesh
import bpy
import mathutils
import numpy as np

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
parser = argparse.ArgumentParser()
parser.add_argument("--pleat", required=True)
parser.add_argument("--work", required=True)
args = parser.parse_args(argv)

FIRST, LAST = 3, 20  # scene frames: not starting at 0 or 1, so that frame numbers are checked
GROUND = 0.0
failures = []


def expect(condition, message):
    if not condition:
        failures.append(message)
        print("FAILED:", message)


# Installed the README's way: enabled in the saved preferences, the module importable with no path set here.
if "pleat_bake" not in bpy.context.preferences.addons:
    print("FAILED: the add-on pleat_bake is not enabled in the preferences (python/blender/install.py)")
    sys.exit(1)
import pleat  # noqa: E402
import pleat_bake  # noqa: E402
from pleat_bake import bake, playback, shading  # noqa: E402

modules = bpy.utils.user_resource("SCRIPTS", path="modules")
expect(os.path.realpath(pleat.__file__).startswith(os.path.realpath(modules)),
       f"pleat imported from {pleat.__file__}, not from Blender's user modules {modules}")

shutil.rmtree(args.work, ignore_errors=True)
os.makedirs(args.work)
bpy.ops.wm.read_homefile(use_empty=True)
expect("pleat_bake" in bpy.context.preferences.addons, "opening a new file disabled the add-on")
scene = bpy.context.scene
scene.frame_start, scene.frame_end = FIRST, LAST

occluders = bpy.data.collections.new("Colliders")
scene.collection.children.link(occluders)
bpy.ops.mesh.primitive_cube_add(size=0.8, location=(0.0, 0.0, 0.4))
cube = bpy.context.active_object
cube.modifiers.new("Collision", "COLLISION")
for c in list(cube.users_collection):
    c.objects.unlink(cube)
occluders.objects.link(cube)
bpy.ops.mesh.primitive_plane_add(size=8.0, location=(0.0, 0.0, GROUND))
bpy.context.active_object.modifiers.new("Collision", "COLLISION")

bpy.ops.mesh.primitive_plane_add(size=2.4, location=(0.0, 0.0, 1.2))
cloth = bpy.context.active_object
cloth.name = "Cloth"
bpy.ops.object.mode_set(mode="EDIT")
bpy.ops.mesh.subdivide(number_cuts=39)
bpy.ops.object.mode_set(mode="OBJECT")
# The three quads of an L at one corner, dissolved into one concave polygon (8 corners, one reflex).
bm = bmesh.new()
bm.from_mesh(cloth.data)
cell = 2.4 / 40
corner = [f for f in bm.faces
          if any(np.allclose(f.calc_center_median()[:2], (-1.2 + (i + 0.5) * cell, -1.2 + (j + 0.5) * cell))
                 for i, j in ((0, 0), (1, 0), (0, 1)))]
expect(len(corner) == 3, f"found {len(corner)} corner quads")
bmesh.ops.dissolve_faces(bm, faces=corner, use_verts=False)
bm.to_mesh(cloth.data)
bm.free()
sizes = sorted(len(p.vertices) for p in cloth.data.polygons)
expect(len(cloth.data.vertices) == 41 * 41 and sizes[-1] == 8 and sizes[-2] == 4,
       f"the cloth has {len(cloth.data.vertices)} vertices and polygons of {sorted(set(sizes))} corners")
NGON = next(p.index for p in cloth.data.polygons if len(p.vertices) == 8)

cloth.modifiers.new("Cloth", "CLOTH")
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
    """(loop triangles as vertex indices, world positions in float64) of obj's evaluated mesh at the current
    frame, written here rather than taken from the add-on; checked against Blender's own (float32) transform
    of the mesh."""
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


def polygon_area(points):
    """Area of a planar-ish polygon (Newell's normal's length / 2)."""
    return 0.5 * np.linalg.norm(np.sum(np.cross(points, np.roll(points, -1, axis=0)), axis=0))


simulated, resplit = {}, []
for frame in range(FIRST, LAST + 1):
    scene.frame_set(frame)
    triangles, simulated[frame] = evaluated(cloth)
    if frame == FIRST:
        split = triangles  # the first frame's split, which the add-on must keep
    elif not np.array_equal(np.sort(triangles, axis=1), np.sort(split, axis=1)):
        resplit.append(frame)
expect(np.ptp(simulated[LAST][:, 2]) > 0.3, "the cloth did not drape over the cube")
expect(simulated[LAST][:, 2].min() < GROUND + 0.05, "the cloth did not reach the ground")
expect(len(resplit) > 0, "Blender's tessellation never changed over the range: nothing tests the fixed split")
print(f"blender re-splits the cloth's quads at frames {resplit}")
# The n-gon's triangles of the kept split tile it: their areas sum to its area on the flat rest mesh.
ngon = list(cloth.data.polygons[NGON].vertices)
inside = [t for t in split if set(t) <= set(ngon)]
expect(len(inside) == len(ngon) - 2, f"the n-gon has {len(inside)} triangles")
first = np.array([v.co[:] for v in cloth.data.vertices], dtype=np.float64)
tiled = sum(polygon_area(first[t]) for t in inside)
expect(abs(tiled - polygon_area(first[ngon])) < 1e-6 * polygon_area(first[ngon]),
       f"the n-gon's triangles cover {tiled}, the n-gon {polygon_area(first[ngon])}")

settings = scene.pleat
settings.occluders = occluders
settings.engine = "kinetic"
settings.ground, settings.ground_height = True, GROUND
settings.contact_tolerance = 0.01
expect(abs(bake.engine_options(settings).get("contact_tolerance", 0.0) - 0.01) < 1e-8,  # a float32 property
       "the contact tolerance is not passed on")

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
cache_file = os.path.join(args.work, "scene_pleat", "Cloth.npz")
expect(cloth.get(playback.CACHE_PROPERTY) == "//scene_pleat/Cloth.npz", "the object does not name its cache")
expect(os.path.isfile(cache_file), f"no cache at {cache_file}")
expect(shading.MATERIAL in cloth.data.materials, "the material template was not assigned")


def attribute(mesh, name):
    values = np.empty(len(mesh.vertices), dtype=np.float32)
    mesh.attributes[name].data.foreach_get("value", values)
    return values


# Play back, out of order: each frame's attributes, on the mesh and after the modifiers.
baked = {}
order = [7, FIRST, LAST, 16, 4]
for frame in order + [f for f in range(FIRST, LAST + 1) if f not in order]:
    scene.frame_set(frame)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    shown = cloth.evaluated_get(depsgraph).data
    front, back = attribute(cloth.data, playback.FRONT), attribute(cloth.data, playback.BACK)
    expect(np.array_equal(attribute(shown, playback.FRONT), front), f"frame {frame}: evaluated front differs")
    expect(np.array_equal(attribute(shown, playback.BACK), back), f"frame {frame}: evaluated back differs")
    color = np.empty(4 * len(front), dtype=np.float32)
    cloth.data.attributes[playback.COLOR].data.foreach_get("color", color)
    expect(np.array_equal(color.reshape(-1, 4)[:, 0], front), f"frame {frame}: colour is not front A")
    cloth.data.attributes[playback.COLOR_BACK].data.foreach_get("color", color)
    expect(np.array_equal(color.reshape(-1, 4)[:, 0], back), f"frame {frame}: back colour is not back A")
    expect(np.array_equal(evaluated(cloth)[1], simulated[frame]), f"frame {frame}: playback moved the cloth")
    baked[frame] = (front, back)
scene.frame_set(FIRST - 2)  # before the range: the first baked frame holds
expect(np.array_equal(attribute(cloth.data, playback.FRONT), baked[FIRST][0]), "before the range")

# The same frames through the command line, over the first frame's split.
frames_dir = os.path.join(args.work, "frames")
os.makedirs(frames_dir)
for frame in range(FIRST, LAST + 1):
    with open(os.path.join(frames_dir, f"cloth_{frame:04d}.obj"), "w") as out:
        out.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in simulated[frame])
        out.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in split)
triangles, positions = evaluated(cube)
with open(os.path.join(args.work, "cube.obj"), "w") as out:
    out.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in positions)
    out.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in triangles)
csv_path = os.path.join(args.work, "visibility.csv")
run = subprocess.run([args.pleat, "visibility", os.path.join(frames_dir, "cloth_%04d.obj"), "--occluder",
                      os.path.join(args.work, "cube.obj"), "--ground", f"z={GROUND!r}", "--contact-tolerance", "0.01",
                      "--engine", "kinetic", "--cones", os.path.join(args.work, "visibility.cones"),
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


def played(obj, frame):
    """(front, back) attributes of obj's mesh at `frame`."""
    scene.frame_set(frame)
    return attribute(obj.data, playback.FRONT), attribute(obj.data, playback.BACK)


# Results computed elsewhere, loaded onto a copy of the cloth's mesh (the same vertices): the CLI's CSV and
# cone cache and the add-on's own cache play back at the scene frames their source frames name.
copy = cloth.copy()
copy.data = cloth.data.copy()
copy.modifiers.clear()
del copy[playback.CACHE_PROPERTY]
scene.collection.objects.link(copy)
bpy.context.view_layer.objects.active = copy
for source in (csv_path, os.path.join(args.work, "visibility.cones"), cache_file):
    result = bpy.ops.pleat.load_sky_visibility(filepath=source, first_frame=FIRST)
    expect(result == {"FINISHED"}, f"loading {source} returned {result}")
    for frame in (FIRST, 16, LAST):
        got = played(copy, frame)
        expect(all(np.array_equal(g, w) for g, w in zip(got, baked[frame])),
               f"{os.path.basename(source)} loaded: frame {frame} differs from the bake")
bpy.ops.mesh.primitive_ico_sphere_add()  # another vertex count: refused, naming both
try:
    bpy.ops.pleat.load_sky_visibility(filepath=csv_path)
    expect(False, "a CSV of another mesh was loaded")
except RuntimeError as e:
    expect("1681 vertices" in str(e) and "Icosphere" in str(e), f"another mesh: unexpected message {e}")
bpy.data.objects.remove(bpy.context.active_object)
bpy.data.objects.remove(copy)

# The node group in the artist's own material: multiplied into Base Color, nothing replaced, once only.
artist = bpy.data.materials.new("Artist cotton")
artist.use_nodes = True
principled = next(n for n in artist.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
principled.inputs["Base Color"].default_value = (0.8, 0.35, 0.2, 1.0)
cloth.data.materials.clear()
cloth.data.materials.append(artist)
bpy.context.view_layer.objects.active = cloth
nodes_before = len(artist.node_tree.nodes)
for attempt in range(2):
    expect(bpy.ops.pleat.insert_node_group() == {"FINISHED"}, "insert into materials failed")
expect(len(artist.node_tree.nodes) == nodes_before + 2, "inserting twice added the nodes twice")
expect(list(cloth.data.materials) == [artist], "inserting replaced the material")
base = principled.inputs["Base Color"]
multiply = base.links[0].from_node if base.is_linked else None
expect(multiply is not None and multiply.blend_type == "MULTIPLY", "Base Color is not multiplied")
if multiply is not None:
    colour = next(s for s in multiply.inputs if s.name == "A" and s.type == "RGBA")
    expect(np.allclose(colour.default_value, (0.8, 0.35, 0.2, 1.0)), "the material's own colour was lost")


def render(path):
    """A small Cycles image of the scene (view transform Standard); its mean over the pixels."""
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(path)
    pixels = np.array(image.pixels[:], dtype=np.float32).reshape(-1, 4)
    bpy.data.images.remove(image)
    return float(pixels[:, :3].mean())


scene.frame_set(LAST)
scene.render.engine = "CYCLES"
scene.cycles.samples, scene.cycles.device, scene.cycles.use_denoising = 16, "CPU", False
scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 320, 240, 100
scene.view_settings.view_transform = "Standard"
scene.world = bpy.data.worlds.new("sky")
scene.world.color = (0.8, 0.85, 0.9)
bpy.ops.object.camera_add(location=(2.6, -2.6, 2.2))
camera = bpy.context.active_object
camera.rotation_euler = mathutils.Vector((-2.6, 2.6, -1.8)).to_track_quat("-Z", "Y").to_euler()
scene.camera = camera
with_occlusion = render(os.path.join(args.work, "cloth_occlusion.png"))
strength = next(n for n in artist.node_tree.nodes if n.type == "GROUP").inputs["Strength"]
strength.default_value = 0.0
without = render(os.path.join(args.work, "cloth_plain.png"))
expect(with_occlusion < without, f"the occlusion did not darken the render ({with_occlusion} vs {without})")
print(f"cycles: mean {with_occlusion:.4f} with the occlusion, {without:.4f} without")

occluded = min(float(np.min(back)) for front, back in baked.values())
expect(occluded < 0.9, f"nothing occludes the underside of the cloth (min back A {occluded})")
print(f"blender bake: {len(baked)} frames x {len(cloth.data.vertices)} vertices; largest difference from the "
      f"CLI {worst}; failures: {len(failures)}")
bpy.ops.preferences.addon_disable(module="pleat_bake")
expect(playback._on_frame_change not in bpy.app.handlers.frame_change_pre, "unregister left the handler")
if failures:
    sys.exit(1)

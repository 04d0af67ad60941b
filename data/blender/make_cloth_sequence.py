"""Build and simulate the bundled cloth sequences `data/drape/`, `data/pile/`, `data/rucked/`
and `data/layered/` with Blender's cloth solver.

Run headless from the repository root (Blender 3.4):

    blender -b --factory-startup --python-exit-code 1 \
        --python data/blender/make_cloth_sequence.py -- [--scene drape|pile|rucked|layered] \
        [--out data/<scene>] [--preview] [--no-check] [--colliders-only]

Scenes (every parameter is in the scene's dict below; cloth-object collision and cloth
self-collision are on in all of them; a simulation run writes the cloth, --colliders-only the
obstacles):

  drape   (default) a 2.0 m x 2.4 m cloth (50 x 60 quads, 3111 vertices, 6000 triangles) is
          dropped from 1.1 m onto a round table (closed cylinder, radius 0.5 m, height 0.75 m)
          standing on a ground plane. It drapes into deep hanging folds, its corners pile up on
          the ground, and from frame 30 the table turns 75 degrees about its axis (a lazy
          susan, eased) so that the folds keep moving and twisting until frame 120.
  pile    a 1.5 m x 1.5 m sheet (60 x 60 quads, 3721 vertices, 7200 triangles) hangs from its
          top edge, which is pinned and lowered to the ground while it swings back and forth
          and turns (a hook on an animated empty), so the sheet is laid down on a ground plane
          in layers that buckle into a pile of folds.
  rucked  an open tube (a cylinder without caps, 48 around x 60 along, 2928 vertices, 5760
          triangles) around a horizontal arm (a collision cylinder): one end ring is pinned,
          the other (the cuff) is pinned to an animated empty that pushes it toward the first
          and twists it, so the tube is compressed along its axis into folds, like a
          pushed-up sleeve.
  layered three square sheets (36 x 36 quads each, 1.6 m, 1.54 m and 1.48 m wide; 4107
          vertices, 7776 triangles, three components) stacked 3 cm apart, each turned 12 degrees
          more than the one below, are dropped together onto a round table (radius 0.45 m) that
          turns 60 degrees from frame 30 to 110: plies that fold over each other, lying a few
          millimetres apart, like a folded-over hem or a collar.

Output (axis convention: Y-up, right-handed; Blender (x, y, z) -> file (x, z, -y), the
same rotation Blender's own OBJ/glTF exporters apply by default; metres):
  <name>.obj  rest (pre-simulation) positions and triangles (1-based `f`), vertex order =
              the cache's vertex order. The triangles are Blender's own tessellation of the
              quads (mesh.loop_triangles), i.e. exactly the triangles the solver collided.
  <name>.pc2  PC2 point cache: evaluated (post-modifier), world-space positions, one sample
              per kept frame (startFrame = first kept Blender frame, sampleRate = 1.0).
  preview_*.png (with --preview) small Workbench renders of the stored positions of the
              --preview-frames (obstacles included).

With --colliders-only the cloth is neither built nor simulated: the scene's obstacles are built
exactly as for the simulation (make_obstacles: same meshes, placement, keys and modifiers) and
their evaluated world-space positions are written, in the same conventions, for the kept frames:
  <name>_colliders.obj  every obstacle but the ground in one mesh (Blender's own triangles),
              positions at the first simulated frame; if no obstacle moves, that is all.
  <name>_colliders.pc2  if any obstacle moves (a turning table): one sample per kept frame,
              the same startFrame and number of samples as <name>.pc2; static obstacles in the
              same mesh simply repeat their positions.
The ground plane (Blender z = 0, file y = 0) is not written: pleat's `--ground y=0` stands for it.
The obstacles' collision outer thickness (obstacle_thickness) is a solver margin, not geometry:
the cloth rests about that far (plus its own collision distance) above the written surfaces.

With the check on (default), every kept frame is tested for self-intersection using
mathutils.bvhtree: triangle pairs that overlap and share no vertex are counted; the
per-frame counts are printed and written to self_intersections.txt next to the outputs,
together with the smallest distance between two vertices more than two edges apart and the
scene's obstacle checks (deepest penetration of a cloth vertex into the table or the arm,
lowest point below the ground).
"""

import argparse
import math
import os
import struct
import sys
import time

import bpy
from mathutils import Euler, Matrix, Vector
from mathutils.bvhtree import BVHTree

# ---------------------------------------------------------------------------------------
# Parameters (all of each sequence is defined here)
# ---------------------------------------------------------------------------------------
# Keys of a scene dict:
#   mesh        ("grid", nx, ny, sx, sy): nx x ny quads in the xy plane, centred, row-major
#               (x fastest); ("tube", n_around, n_along, radius, length): rings about the
#               x axis, centred, ring-major (around fastest), no caps, normals outward;
#               ("layers", n_layers, n, size, gap, turn_deg, shrink): stacked square grids (see
#               layers_mesh).
#   z, offset, spin_deg, tilt_deg
#               placement baked into the vertices: translate (offset, z) @ rotate z @ rotate x.
#   pins        optional: vertices pinned in place ("fixed") or pinned to an animated empty
#               ("hooked", by a Hook modifier before the cloth), chosen by predicates of the
#               vertex's mesh indices (i, j); the empty's keys are (frame, location, rotation
#               in degrees), Bezier-interpolated; from frame "release" on (if given) no vertex
#               is pinned any more.
#   table       optional: closed cylinder standing on the ground, turning about z (keys).
#   arm         optional: closed cylinder along x (radius, length, centre).
#   ground      optional: size of the ground plane at z = 0.
#   fps, sim, keep  frame rate, simulated and kept Blender frames (inclusive).
#   cloth, collision  Blender cloth / cloth-collision settings, set in this order.
#   camera      preview camera location and target; preview_frames the default frames.
DRAPE = dict(
    mesh=("grid", 50, 60, 2.0, 2.4),   # quads along x and y -> (51 x 61) = 3111 vertices; metres
    z=1.10,                            # initial height of the flat cloth
    offset=(0.12, -0.08),              # cloth centre relative to the table axis (asymmetric folds)
    tilt_deg=4.0,                      # small tilt about x so the drop is not perfectly symmetric
    spin_deg=17.0,                     # rotation about z
    table=dict(r=0.5, h=0.75,          # round table: a closed cylinder standing on the ground
               spin=((30, 0.0), (120, 75.0))),   # (frame, degrees about z), Bezier ease: a lazy susan
    ground=8.0,
    fps=24,
    sim=(1, 120),                      # simulated Blender frames
    keep=(21, 120),                    # frames written to the cache (100 frames)
    cloth=dict(
        quality=12,                    # solver steps per frame
        mass=0.3,                      # kg per vertex (Blender "Vertex Mass")
        air_damping=1.0,
        tension_stiffness=15.0, compression_stiffness=15.0,
        shear_stiffness=5.0, bending_stiffness=2.0,
        tension_damping=5.0, compression_damping=5.0,
        shear_damping=5.0, bending_damping=0.5,
    ),
    collision=dict(
        collision_quality=6,
        use_collision=True,
        distance_min=0.008,            # cloth <-> objects
        use_self_collision=True,
        self_distance_min=0.006,       # cloth <-> cloth (grid spacing is 0.04 m)
        self_friction=5.0,
        self_impulse_clamp=0.0,
        impulse_clamp=0.0,
    ),
    obstacle_thickness=0.01,           # collision modifier outer thickness
    obstacle_friction=5.0,
    camera=((2.2, -2.4, 2.1), (0.05, 0.0, 0.35)),
    preview_frames="40,120",
)

PILE = dict(
    mesh=("grid", 60, 60, 1.5, 1.5),   # 61 x 61 = 3721 vertices, edge 0.025 m
    z=1.25,                            # flat sheet, held at its centre 1.25 m above the ground
    offset=(0.0, 0.0),
    tilt_deg=3.0,
    spin_deg=20.0,
    pins=dict(fixed=lambda i, j: False,
              hooked=lambda i, j: abs(i - 30) <= 1 and abs(j - 30) <= 1,   # 3 x 3 at the centre
              keys=((1, (0.0, 0.0, 1.25), (0.0, 0.0, 0.0)),      # hangs from its centre,
                    (12, (0.0, 0.0, 1.25), (0.0, 0.0, 0.0)),     # is lowered and twisted,
                    (65, (0.04, -0.03, 0.30), (0.0, 0.0, 150.0))),
              release=65),                                       # then let go
    ground=8.0,
    fps=24,
    sim=(1, 100),
    keep=(21, 100),                    # 80 frames
    cloth=dict(
        quality=10,
        mass=0.3,
        air_damping=1.0,
        tension_stiffness=15.0, compression_stiffness=15.0,
        shear_stiffness=15.0, bending_stiffness=4.0,
        tension_damping=5.0, compression_damping=5.0,
        shear_damping=5.0, bending_damping=0.5,
        vertex_group_mass="pin",
    ),
    collision=dict(
        collision_quality=5,
        use_collision=True,
        distance_min=0.006,
        use_self_collision=True,
        self_distance_min=0.005,       # grid spacing is 0.025 m
        self_friction=5.0,
        self_impulse_clamp=0.0,
        impulse_clamp=0.0,
    ),
    obstacle_thickness=0.01,
    obstacle_friction=5.0,
    camera=((1.25, -1.4, 1.15), (0.05, 0.0, 0.12)),
    preview_frames="40,100",
)

SLEEVE = dict(
    mesh=("tube", 48, 60, 0.11, 1.0),  # 48 x 61 = 2928 vertices; edges 0.0144 m around, 0.0167 m along
    z=0.90,                            # tube axis height (along x, from x = -0.5 to 0.5)
    offset=(0.0, 0.0),
    tilt_deg=0.0,
    spin_deg=0.0,
    pins=dict(fixed=lambda i, j: j == 0,   # shoulder ring fixed; cuff ring pushed toward it, twisted
              hooked=lambda i, j: j == 60,
              keys=((1, (0.5, 0.0, 0.90), (0.0, 0.0, 0.0)),
                    (10, (0.5, 0.0, 0.90), (0.0, 0.0, 0.0)),
                    (110, (-0.05, 0.0, 0.90), (40.0, 0.0, 0.0)))),   # past the end: still moving at 100
    arm=dict(r=0.06, length=1.5, centre=(0.0, 0.0, 0.90)),
    fps=24,
    sim=(1, 100),
    keep=(21, 100),                    # 80 frames
    cloth=dict(
        quality=12,
        mass=0.3,
        air_damping=1.0,
        tension_stiffness=15.0, compression_stiffness=15.0,
        shear_stiffness=5.0, bending_stiffness=5.0,
        tension_damping=5.0, compression_damping=5.0,
        shear_damping=5.0, bending_damping=0.5,
        vertex_group_mass="pin",
    ),
    collision=dict(
        collision_quality=8,
        use_collision=True,
        distance_min=0.006,
        use_self_collision=True,
        self_distance_min=0.006,       # edges are 0.014-0.017 m
        self_friction=5.0,
        self_impulse_clamp=0.0,
        impulse_clamp=0.0,
    ),
    obstacle_thickness=0.005,
    obstacle_friction=5.0,
    camera=((0.3, -1.15, 1.3), (-0.05, 0.0, 0.88)),
    preview_frames="40,100",
)

LAYERED = dict(
    # Three square sheets stacked 3 cm apart (edge 0.045 m), each turned a little more than the one
    # below and a little smaller, like a folded-over hem or a collar's plies: 3 x 37 x 37 = 4107
    # vertices, 7776 triangles, three components.
    mesh=("layers", 3, 36, 1.6, 0.03, 12.0, 0.06),
    z=1.05,                            # height of the lowest sheet
    offset=(0.10, -0.06),
    tilt_deg=3.0,
    spin_deg=10.0,
    table=dict(r=0.45, h=0.75,
               spin=((30, 0.0), (110, 60.0))),
    ground=8.0,
    fps=24,
    sim=(1, 110),
    keep=(31, 110),                    # 80 frames: from the plies lying on the table to the heap
    cloth=DRAPE["cloth"],              # the drape's fabric
    collision=dict(
        collision_quality=8,
        use_collision=True,
        distance_min=0.008,
        use_self_collision=True,       # the plies collide with each other through self-collision
        self_distance_min=0.008,       # (0.006 and quality 6 left one face pair crossing in 10 frames)
        self_friction=5.0,
        self_impulse_clamp=0.0,
        impulse_clamp=0.0,
    ),
    obstacle_thickness=0.01,
    obstacle_friction=5.0,
    camera=((2.0, -2.2, 1.9), (0.05, 0.0, 0.35)),
    preview_frames="50,110",
)

SCENES = dict(drape=DRAPE, pile=PILE, rucked=SLEEVE, layered=LAYERED)  # rucked: "sleeve" and "tube" name a generated kind


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser(prog="make_cloth_sequence.py")
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--scene", choices=sorted(SCENES), default="drape",
                    help="which sequence to build (default: drape)")
    ap.add_argument("--out", default=None,
                    help="output folder (default: data/<scene> next to this script's folder)")
    ap.add_argument("--name", default=None, help="base name of the .obj/.pc2 files (default: the scene)")
    ap.add_argument("--preview", action="store_true", help="render small PNG previews")
    ap.add_argument("--preview-frames", default=None,
                    help="comma-separated Blender frames to render (default: the scene's)")
    ap.add_argument("--no-check", action="store_true", help="skip the self-intersection check")
    ap.add_argument("--colliders-only", action="store_true",
                    help="do not simulate: write the obstacles (but the ground) as "
                         "<name>_colliders.obj (+ .pc2 if any moves) for the kept frames")
    args = ap.parse_args(argv)
    if args.out is None:
        args.out = os.path.join(os.path.dirname(here), args.scene)
    if args.name is None:
        args.name = args.scene
    if args.preview_frames is None:
        args.preview_frames = SCENES[args.scene]["preview_frames"]
    return args


# ---------------------------------------------------------------------------------------
# Scene
# ---------------------------------------------------------------------------------------
def reset_scene(P):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.fps = P["fps"]
    scene.render.fps_base = 1.0
    scene.frame_start = P["sim"][0]
    scene.frame_end = P["sim"][1]
    scene.gravity = (0.0, 0.0, -9.81)
    scene.use_gravity = True
    return scene


def grid_mesh(nx, ny, sx, sy):
    """nx x ny quads in the xy plane, centred; rows of nx + 1 vertices, x fastest.
    Returns vertices, quads and each vertex's (column i, row j)."""
    verts, faces = [], []
    for j in range(ny + 1):                             # row-major, x fastest
        for i in range(nx + 1):
            verts.append((sx * (i / nx - 0.5), sy * (j / ny - 0.5), 0.0))
    for j in range(ny):
        for i in range(nx):
            a = j * (nx + 1) + i
            faces.append((a, a + 1, a + nx + 2, a + nx + 1))   # CCW seen from +z
    ij = [(i, j) for j in range(ny + 1) for i in range(nx + 1)]
    return verts, faces, ij


def tube_mesh(n_around, n_along, radius, length):
    """Open tube about the x axis, centred: n_along + 1 rings of n_around vertices.
    Returns vertices, quads and each vertex's (index around i, ring j)."""
    verts, faces = [], []
    for j in range(n_along + 1):                        # ring-major, around fastest
        x = length * (j / n_along - 0.5)
        for i in range(n_around):
            t = 2.0 * math.pi * i / n_around
            verts.append((x, radius * math.cos(t), radius * math.sin(t)))
    for j in range(n_along):
        for i in range(n_around):
            a, b = j * n_around + i, j * n_around + (i + 1) % n_around
            faces.append((a, b, b + n_around, a + n_around))    # normals point outward
    ij = [(i, j) for j in range(n_along + 1) for i in range(n_around)]
    return verts, faces, ij


def layers_mesh(n_layers, n, size, gap, turn_deg, shrink):
    """n_layers square sheets of n x n quads, the lowest `size` wide, each next one `gap` higher,
    turned `turn_deg` more about z and `shrink` narrower; sheet-major, then row-major, x fastest.
    Returns vertices, quads and each vertex's (column i, row j) in its sheet."""
    verts, faces, ij = [], [], []
    for k in range(n_layers):
        g_verts, g_faces, g_ij = grid_mesh(n, n, size - k * shrink, size - k * shrink)
        turn = Matrix.Rotation(math.radians(k * turn_deg), 3, "Z")
        base = len(verts)
        verts += [tuple(turn @ Vector((x, y, k * gap))) for x, y, _ in g_verts]
        faces += [tuple(base + a for a in f) for f in g_faces]
        ij += g_ij
    return verts, faces, ij


def animated_empty(scene, name, keys):
    """An empty with Bezier location/rotation keys (frame, location, rotation in degrees);
    it is left at its first key's pose."""
    empty = bpy.data.objects.new(name, None)
    scene.collection.objects.link(empty)
    for fr, loc, rot in keys:
        empty.location = loc
        empty.rotation_euler = [math.radians(d) for d in rot]
        empty.keyframe_insert("location", frame=fr)
        empty.keyframe_insert("rotation_euler", frame=fr)
    fr, loc, rot = keys[0]
    empty.location = loc
    empty.rotation_euler = [math.radians(d) for d in rot]
    return empty


def add_pins(scene, obj, ij, pins):
    """Vertex group "pin" (the cloth's pin group) over the fixed and hooked vertices; the
    hooked ones follow an animated empty through a Hook modifier (added before the cloth)."""
    fixed = [v for v, (i, j) in enumerate(ij) if pins["fixed"](i, j)]
    hooked = [v for v, (i, j) in enumerate(ij) if pins["hooked"](i, j)]
    vg = obj.vertex_groups.new(name="pin")
    vg.add(fixed + hooked, 1.0, "REPLACE")
    if hooked:
        empty = animated_empty(scene, "hook", pins["keys"])
        _, loc, rot = pins["keys"][0]
        bind = Matrix.Translation(loc) @ Euler([math.radians(d) for d in rot]).to_matrix().to_4x4()
        hook = obj.modifiers.new("Hook", "HOOK")
        hook.object = empty
        hook.vertex_indices_set(hooked)
        hook.center = loc
        hook.matrix_inverse = bind.inverted()           # no displacement at the first key
    if pins.get("release"):
        # The cloth re-reads its pin group every step: from the release frame on, this sets
        # every pin weight to 0 (group B absent = weight 0, mixed in at full influence).
        mix = obj.modifiers.new("Release", "VERTEX_WEIGHT_MIX")
        mix.vertex_group_a = "pin"
        mix.default_weight_b = 0.0
        mix.mix_mode = "SET"
        mix.mix_set = "A"
        for fr, influence in ((pins["release"] - 1, 0.0), (pins["release"], 1.0)):
            mix.mask_constant = influence
            mix.keyframe_insert("mask_constant", frame=fr)
        for kp in obj.animation_data.action.fcurves[0].keyframe_points:
            kp.interpolation = "CONSTANT"


def make_cloth(scene, P):
    kind = P["mesh"][0]
    verts, faces, ij = {"grid": grid_mesh, "tube": tube_mesh, "layers": layers_mesh}[kind](*P["mesh"][1:])
    mesh = bpy.data.meshes.new("cloth")
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    # Bake the placement into the vertices so object transform is identity (world == local).
    m = (Matrix.Translation((P["offset"][0], P["offset"][1], P["z"]))
         @ Matrix.Rotation(math.radians(P["spin_deg"]), 4, "Z")
         @ Matrix.Rotation(math.radians(P["tilt_deg"]), 4, "X"))
    mesh.transform(m)
    obj = bpy.data.objects.new("cloth", mesh)
    scene.collection.objects.link(obj)
    if "pins" in P:
        add_pins(scene, obj, ij, P["pins"])

    mod = obj.modifiers.new("Cloth", "CLOTH")
    s = mod.settings
    for k, v in P["cloth"].items():
        setattr(s, k, v)
    c = mod.collision_settings
    for k, v in P["collision"].items():
        setattr(c, k, v)
    mod.point_cache.frame_start = P["sim"][0]
    mod.point_cache.frame_end = P["sim"][1]
    return obj, mod


def make_obstacles(scene, P):
    obstacles = []
    if "table" in P:
        T = P["table"]
        bpy.ops.mesh.primitive_cylinder_add(vertices=96, radius=T["r"], depth=T["h"],
                                            end_fill_type="NGON", location=(0.0, 0.0, T["h"] / 2))
        table = bpy.context.active_object
        table.name = "table"
        for fr, deg in T["spin"]:
            table.rotation_euler = (0.0, 0.0, math.radians(deg))
            table.keyframe_insert("rotation_euler", index=2, frame=fr)
        obstacles.append(table)
    if "arm" in P:
        A = P["arm"]
        bpy.ops.mesh.primitive_cylinder_add(vertices=96, radius=A["r"], depth=A["length"],
                                            end_fill_type="NGON", location=A["centre"],
                                            rotation=(0.0, math.pi / 2, 0.0))
        arm = bpy.context.active_object
        arm.name = "arm"
        obstacles.append(arm)
    if "ground" in P:
        bpy.ops.mesh.primitive_plane_add(size=P["ground"], location=(0.0, 0.0, 0.0))
        ground = bpy.context.active_object
        ground.name = "ground"
        obstacles.append(ground)
    for ob in obstacles:
        ob.modifiers.new("Collision", "COLLISION")
        ob.collision.thickness_outer = P["obstacle_thickness"]
        ob.collision.cloth_friction = P["obstacle_friction"]
        ob.collision.use_culling = False
    return obstacles


def obstacle_checks(P):
    """(column name, function of the world positions) for each obstacle of the scene: the
    deepest penetration of a cloth vertex into it (0 if none)."""
    checks = []
    if "table" in P:
        r, h = P["table"]["r"], P["table"]["h"]
        checks.append(("table_penetration",
                       lambda pos: max(0.0, max(min(r - p.xy.length, h - p.z) for p in pos))))
    if "arm" in P:
        r, half, c = P["arm"]["r"], P["arm"]["length"] / 2, Vector(P["arm"]["centre"])
        checks.append(("arm_penetration",
                       lambda pos: max(0.0, max(min(r - (p - c).yz.length, half - abs(p.x - c.x))
                                                for p in pos))))
    if "ground" in P:
        checks.append(("below_ground", lambda pos: max(0.0, -min(p.z for p in pos))))
    return checks


# ---------------------------------------------------------------------------------------
# Export helpers
# ---------------------------------------------------------------------------------------
def to_file_axes(co):
    """Blender Z-up (x, y, z) -> file Y-up (x, z, -y)."""
    return (co[0], co[2], -co[1])


def evaluated_positions(obj, depsgraph):
    ev = obj.evaluated_get(depsgraph)
    me = ev.to_mesh()
    mw = ev.matrix_world.copy()
    pos = [mw @ v.co for v in me.vertices]
    ev.to_mesh_clear()
    return pos


def write_obj(path, rest_positions, tris, nframes_note, object_name,
              what="cloth solver, self-collision on; rest (pre-simulation) positions"):
    tmp = path + ".tmp"
    with open(tmp, "w", newline="\n") as f:
        f.write("# pleat bundled cloth sequence, generated by data/blender/make_cloth_sequence.py\n")
        f.write("# Blender %s %s.\n" % (bpy.app.version_string, what))
        f.write("# Y-up, metres. Vertex order = %s. %d vertices, %d triangles.\n"
                % (nframes_note, len(rest_positions), len(tris)))
        f.write("o %s\n" % object_name)
        for p in rest_positions:
            x, y, z = to_file_axes(p)
            f.write("v %.6f %.6f %.6f\n" % (x, y, z))
        for t in tris:
            f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))
    os.replace(tmp, path)


def write_pc2(path, frames_positions, start_frame):
    n = len(frames_positions[0])
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(struct.pack("<12siiffi", b"POINTCACHE2\0", 1, n, float(start_frame), 1.0,
                            len(frames_positions)))
        for pos in frames_positions:
            assert len(pos) == n
            flat = []
            for p in pos:
                flat.extend(to_file_axes(p))
            f.write(struct.pack("<%df" % (3 * n), *flat))
    os.replace(tmp, path)


# ---------------------------------------------------------------------------------------
# Checks
# ---------------------------------------------------------------------------------------
def self_intersections(positions, tris, tri_sets):
    tree = BVHTree.FromPolygons(positions, tris, all_triangles=True)
    pairs = tree.overlap(tree)
    count = 0
    seen = set()
    for a, b in pairs:
        if a == b:
            continue
        key = (a, b) if a < b else (b, a)
        if key in seen:
            continue
        seen.add(key)
        if tri_sets[a] & tri_sets[b]:
            continue                                    # shares a vertex or an edge
        count += 1
    return count


def min_nonadjacent_vertex_distance(positions, ring2):
    """Smallest distance between two vertices that are not within 2 edges of each other."""
    from mathutils.kdtree import KDTree
    kd = KDTree(len(positions))
    for i, p in enumerate(positions):
        kd.insert(p, i)
    kd.balance()
    best = float("inf")
    for i, p in enumerate(positions):
        for (_, j, d) in kd.find_n(p, 12):
            if j != i and j not in ring2[i] and d < best:
                best = d
    return best


# ---------------------------------------------------------------------------------------
def render_previews(scene, cloth, quads, frames_pos, outdir, camera):
    """Render the stored positions (not a re-evaluated cache) as a plain mesh."""
    cloth.hide_render = True
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.display.shading.light = "STUDIO"
    scene.display.shading.color_type = "SINGLE"
    scene.display.shading.single_color = (0.8, 0.55, 0.35)
    scene.display.shading.show_cavity = True
    scene.display.shading.cavity_type = "BOTH"
    scene.display.shading.show_shadows = False
    scene.display.shading.show_backface_culling = False
    scene.world = bpy.data.worlds.new("w") if scene.world is None else scene.world
    scene.world.color = (0.2, 0.22, 0.25)
    scene.render.resolution_x = 560
    scene.render.resolution_y = 420
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.image_settings.compression = 100
    cam_data = bpy.data.cameras.new("cam")
    cam_data.lens = 40
    cam = bpy.data.objects.new("cam", cam_data)
    scene.collection.objects.link(cam)
    cam.location = camera[0]
    direction = Vector(camera[1]) - cam.location
    cam.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
    scene.camera = cam
    for fr, pos in sorted(frames_pos.items()):
        me = bpy.data.meshes.new("preview_%d" % fr)
        me.from_pydata([tuple(p) for p in pos], [], quads)
        me.update()
        for poly in me.polygons:
            poly.use_smooth = True
        ob = bpy.data.objects.new("preview_%d" % fr, me)
        scene.collection.objects.link(ob)
        scene.render.filepath = os.path.join(outdir, "preview_%03d.png" % fr)
        bpy.ops.render.render(write_still=True)
        bpy.data.objects.remove(ob)


def evaluated_mesh(obj, depsgraph):
    """World-space positions and Blender's own triangles (loop_triangles) of the evaluated mesh."""
    ev = obj.evaluated_get(depsgraph)
    me = ev.to_mesh()
    me.calc_loop_triangles()
    mw = ev.matrix_world.copy()
    pos = [mw @ v.co for v in me.vertices]
    tris = [tuple(t.vertices) for t in me.loop_triangles]
    ev.to_mesh_clear()
    return pos, tris


def write_colliders(args, P):
    """Build the obstacles as the simulation does, without the cloth, and write every one but
    the ground (pleat's --ground stands for it) as one mesh: <name>_colliders.obj, plus
    <name>_colliders.pc2 over the kept frames if any of them is animated."""
    sim_start = P["sim"][0]
    keep_start, keep_end = P["keep"]
    scene = reset_scene(P)
    obstacles = [ob for ob in make_obstacles(scene, P) if ob.name != "ground"]
    print("scene %s: obstacles %s; ground plane (z = 0) %s"
          % (args.scene, ", ".join(ob.name for ob in obstacles) or "none",
             "yes (not written: --ground y=0)" if "ground" in P else "none"))
    if not obstacles:
        print("nothing to write: the scene has no obstacle but the ground")
        return
    moving = [ob.name for ob in obstacles if ob.animation_data and ob.animation_data.action]

    def positions(fr):
        scene.frame_set(fr)
        dg = bpy.context.evaluated_depsgraph_get()
        pos, tris, ranges = [], [], []
        for ob in obstacles:
            p, t = evaluated_mesh(ob, dg)
            tris += [tuple(len(pos) + i for i in tri) for tri in t]
            ranges.append("%s %d-%d" % (ob.name, len(pos) + 1, len(pos) + len(p)))
            pos += p
        return pos, tris, ranges

    rest, tris, ranges = positions(sim_start)
    frames = []
    for fr in range(keep_start, keep_end + 1):
        pos, t, _ = positions(fr)
        if len(pos) != len(rest) or t != tris:
            raise RuntimeError("frame %d: the obstacles' topology changed" % fr)
        frames.append(pos)
    if not moving and any(p != q for pos in frames for p, q in zip(pos, rest)):
        raise RuntimeError("no obstacle is animated, yet their positions change")

    base = os.path.join(args.out, args.name + "_colliders")
    name = os.path.basename(base)
    if moving:
        write_obj(base + ".obj", rest, tris, "the vertex order of %s.pc2 (%s)" % (name, ", ".join(ranges)),
                  name, what="obstacles of the cloth simulation (ground plane not included); "
                             "positions at frame %d" % sim_start)
        write_pc2(base + ".pc2", frames, keep_start)
        print("wrote %s.obj and %s.pc2: %d vertices, %d triangles, %d frames (Blender frames %d-%d); "
              "moving: %s" % (base, base, len(rest), len(tris), len(frames), keep_start, keep_end,
                              ", ".join(moving)))
    else:
        write_obj(base + ".obj", rest, tris, ", ".join(ranges), name,
                  what="obstacles of the cloth simulation (ground plane not included); "
                       "static, the same in every frame")
        if os.path.exists(base + ".pc2"):
            os.remove(base + ".pc2")                    # stale: the obstacles no longer move
            print("removed stale %s.pc2" % base)
        print("wrote %s.obj: %d vertices, %d triangles, static" % (base, len(rest), len(tris)))


def main():
    args = parse_args()
    P = SCENES[args.scene]
    sim_start, sim_end = P["sim"]
    keep_start, keep_end = P["keep"]
    os.makedirs(args.out, exist_ok=True)
    if args.colliders_only:
        write_colliders(args, P)
        return
    scene = reset_scene(P)
    cloth, mod = make_cloth(scene, P)
    make_obstacles(scene, P)
    checks = obstacle_checks(P)

    me = cloth.data
    me.calc_loop_triangles()
    tris = [tuple(t.vertices) for t in me.loop_triangles]
    rest = [cloth.matrix_world @ v.co for v in me.vertices]
    nverts = len(rest)
    tri_sets = [frozenset(t) for t in tris]
    adj = [set() for _ in range(nverts)]
    for e in me.edges:
        a, b = e.vertices
        adj[a].add(b)
        adj[b].add(a)
    ring2 = []
    for i in range(nverts):
        r = set(adj[i])
        for j in adj[i]:
            r |= adj[j]
        ring2.append(r)
    print("scene %s: %d vertices, %d quads, %d triangles"
          % (args.scene, nverts, len(me.polygons), len(tris)))

    quads = [tuple(p.vertices) for p in me.polygons]
    preview_frames = [int(x) for x in args.preview_frames.split(",")] if args.preview else []
    preview_pos = {}
    frames = []
    report = []
    t0 = time.time()
    for fr in range(sim_start, sim_end + 1):        # step sequentially so the solver advances
        scene.frame_set(fr)
        dg = bpy.context.evaluated_depsgraph_get()
        pos = evaluated_positions(cloth, dg)
        if len(pos) != nverts:
            raise RuntimeError("frame %d: evaluated mesh has %d vertices, expected %d"
                               % (fr, len(pos), nverts))
        if fr in preview_frames:
            preview_pos[fr] = pos
        if fr < keep_start or fr > keep_end:
            print("frame %3d simulated (%.1fs)" % (fr, time.time() - t0), flush=True)
            continue
        frames.append(pos)
        line = "frame %3d" % fr
        if not args.no_check:
            nint = self_intersections(pos, tris, tri_sets)
            dmin = min_nonadjacent_vertex_distance(pos, ring2)
            obst = tuple(f(pos) for _, f in checks)
            line += ("  self-intersecting triangle pairs %d  min non-adjacent vertex dist %.4f m"
                     % (nint, dmin))
            line += "".join("  %s %.4f m" % (name.replace("_", " "), v)
                            for (name, _), v in zip(checks, obst))
            report.append((fr, nint, dmin) + obst)
        print(line + "  (%.1fs)" % (time.time() - t0), flush=True)

    base = os.path.join(args.out, args.name)
    write_obj(base + ".obj", rest, tris, "the vertex order of %s.pc2" % args.name, args.scene)
    write_pc2(base + ".pc2", frames, keep_start)
    print("wrote %s.obj and %s.pc2: %d vertices, %d triangles, %d frames (Blender frames %d-%d)"
          % (base, base, nverts, len(tris), len(frames), keep_start, keep_end))

    if report:
        bad = [r for r in report if r[1] > 0]
        with open(os.path.join(args.out, "self_intersections.txt"), "w") as f:
            f.write(" ".join(["frame intersecting_pairs min_nonadjacent_vertex_dist"]
                             + [name for name, _ in checks]) + "\n")
            for r in report:
                f.write(("%d %d %.5f" + " %.5f" * len(checks) + "\n") % r)
        print("self-intersection check: %d of %d frames have intersecting triangle pairs, "
              "total %d pairs, max %d; min non-adjacent vertex distance %.4f m"
              % (len(bad), len(report), sum(r[1] for r in report), max(r[1] for r in report),
                 min(r[2] for r in report)))

    if args.preview:
        render_previews(scene, cloth, quads, preview_pos, args.out, P["camera"])


if __name__ == "__main__":
    main()

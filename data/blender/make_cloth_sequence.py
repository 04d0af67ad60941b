"""Build and simulate the bundled cloth sequence `data/drape/` with Blender's cloth solver.

Run headless from the repository root (Blender 3.4):

    blender -b --factory-startup --python-exit-code 1 \
        --python data/blender/make_cloth_sequence.py -- [--out data/drape] [--preview] [--no-check]

Scene: a 2.0 m x 2.4 m cloth (50 x 60 quads, 3111 vertices, 6000 triangles) is dropped
from 1.1 m onto a round table (closed cylinder, radius 0.5 m, height 0.75 m) standing on a
ground plane. It drapes into deep hanging folds, its corners pile up on the ground, and from
frame 30 the table turns 75 degrees about its axis (a lazy susan, eased) so that the folds
keep moving and twisting until frame 120. Cloth-object collision and cloth self-collision
are both on. Only the cloth is written; the table and the ground are not.

Output (axis convention: Y-up, right-handed; Blender (x, y, z) -> file (x, z, -y), the
same rotation Blender's own OBJ/glTF exporters apply by default; metres):
  drape.obj  rest (pre-simulation) positions and triangles (1-based `f`), vertex order =
             the cache's vertex order. The triangles are Blender's own tessellation of the
             quads (mesh.loop_triangles), i.e. exactly the triangles the solver collided.
  drape.pc2  PC2 point cache: evaluated (post-modifier), world-space positions, one sample
             per kept frame (startFrame = first kept Blender frame, sampleRate = 1.0).
  preview_*.png (with --preview) small Workbench renders of the stored positions of the
             --preview-frames (table and ground included).

With the check on (default), every kept frame is tested for self-intersection using
mathutils.bvhtree: triangle pairs that overlap and share no vertex are counted; the
per-frame counts are printed and written to self_intersections.txt next to the outputs,
together with the smallest distance between two vertices more than two edges apart, the
deepest penetration of a cloth vertex into the table and the lowest point below the ground.
"""

import argparse
import math
import os
import struct
import sys
import time

import bpy
from mathutils import Matrix, Vector
from mathutils.bvhtree import BVHTree

# ---------------------------------------------------------------------------------------
# Parameters (all of the sequence is defined here)
# ---------------------------------------------------------------------------------------
CLOTH_NX, CLOTH_NY = 50, 60          # quads along x and y -> (51 x 61) = 3111 vertices
CLOTH_SX, CLOTH_SY = 2.0, 2.4        # metres
CLOTH_Z = 1.10                       # initial height of the flat cloth
CLOTH_OFFSET = (0.12, -0.08)         # cloth centre relative to the table axis (asymmetric folds)
CLOTH_TILT_DEG = 4.0                 # small tilt about x so the drop is not perfectly symmetric
CLOTH_SPIN_DEG = 17.0                # rotation about z
TABLE_R, TABLE_H = 0.5, 0.75        # round table: a closed cylinder standing on the ground
TABLE_SPIN = ((30, 0.0), (120, 75.0))  # (frame, degrees about z), Bezier ease: a lazy susan
FPS = 24
SIM_START, SIM_END = 1, 120          # simulated Blender frames
KEEP_START, KEEP_END = 21, 120       # frames written to the cache (100 frames)

CLOTH = dict(
    quality=12,                      # solver steps per frame
    mass=0.3,                        # kg per vertex (Blender "Vertex Mass")
    air_damping=1.0,
    tension_stiffness=15.0, compression_stiffness=15.0,
    shear_stiffness=5.0, bending_stiffness=2.0,
    tension_damping=5.0, compression_damping=5.0,
    shear_damping=5.0, bending_damping=0.5,
)
COLLISION = dict(
    collision_quality=6,
    use_collision=True,
    distance_min=0.008,              # cloth <-> objects
    use_self_collision=True,
    self_distance_min=0.006,         # cloth <-> cloth (grid spacing is 0.04 m)
    self_friction=5.0,
    self_impulse_clamp=0.0,
    impulse_clamp=0.0,
)
OBSTACLE_THICKNESS = 0.01            # collision modifier outer thickness
OBSTACLE_FRICTION = 5.0


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser(prog="make_cloth_sequence.py")
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--out", default=os.path.join(os.path.dirname(here), "drape"),
                    help="output folder (default: data/drape next to this script)")
    ap.add_argument("--name", default="drape", help="base name of the .obj/.pc2 files")
    ap.add_argument("--preview", action="store_true", help="render two small PNG previews")
    ap.add_argument("--preview-frames", default="40,120")
    ap.add_argument("--no-check", action="store_true", help="skip the self-intersection check")
    return ap.parse_args(argv)


# ---------------------------------------------------------------------------------------
# Scene
# ---------------------------------------------------------------------------------------
def reset_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.fps = FPS
    scene.render.fps_base = 1.0
    scene.frame_start = SIM_START
    scene.frame_end = SIM_END
    scene.gravity = (0.0, 0.0, -9.81)
    scene.use_gravity = True
    return scene


def make_cloth(scene):
    verts, faces = [], []
    for j in range(CLOTH_NY + 1):                       # row-major, x fastest
        for i in range(CLOTH_NX + 1):
            verts.append((CLOTH_SX * (i / CLOTH_NX - 0.5), CLOTH_SY * (j / CLOTH_NY - 0.5), 0.0))
    for j in range(CLOTH_NY):
        for i in range(CLOTH_NX):
            a = j * (CLOTH_NX + 1) + i
            faces.append((a, a + 1, a + CLOTH_NX + 2, a + CLOTH_NX + 1))   # CCW seen from +z
    mesh = bpy.data.meshes.new("cloth")
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    # Bake the placement into the vertices so object transform is identity (world == local).
    m = (Matrix.Translation((CLOTH_OFFSET[0], CLOTH_OFFSET[1], CLOTH_Z))
         @ Matrix.Rotation(math.radians(CLOTH_SPIN_DEG), 4, "Z")
         @ Matrix.Rotation(math.radians(CLOTH_TILT_DEG), 4, "X"))
    mesh.transform(m)
    obj = bpy.data.objects.new("cloth", mesh)
    scene.collection.objects.link(obj)

    mod = obj.modifiers.new("Cloth", "CLOTH")
    s = mod.settings
    for k, v in CLOTH.items():
        setattr(s, k, v)
    c = mod.collision_settings
    for k, v in COLLISION.items():
        setattr(c, k, v)
    mod.point_cache.frame_start = SIM_START
    mod.point_cache.frame_end = SIM_END
    return obj, mod


def make_obstacles(scene):
    bpy.ops.mesh.primitive_cylinder_add(vertices=96, radius=TABLE_R, depth=TABLE_H,
                                        end_fill_type="NGON", location=(0.0, 0.0, TABLE_H / 2))
    table = bpy.context.active_object
    table.name = "table"
    for fr, deg in TABLE_SPIN:
        table.rotation_euler = (0.0, 0.0, math.radians(deg))
        table.keyframe_insert("rotation_euler", index=2, frame=fr)
    bpy.ops.mesh.primitive_plane_add(size=8.0, location=(0.0, 0.0, 0.0))
    ground = bpy.context.active_object
    ground.name = "ground"
    for ob in (table, ground):
        ob.modifiers.new("Collision", "COLLISION")
        ob.collision.thickness_outer = OBSTACLE_THICKNESS
        ob.collision.cloth_friction = OBSTACLE_FRICTION
        ob.collision.use_culling = False
    return table, ground


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


def write_obj(path, rest_positions, tris, nframes_note):
    tmp = path + ".tmp"
    with open(tmp, "w", newline="\n") as f:
        f.write("# pleat bundled cloth sequence, generated by data/blender/make_cloth_sequence.py\n")
        f.write("# Blender %s cloth solver, self-collision on; rest (pre-simulation) positions.\n"
                % bpy.app.version_string)
        f.write("# Y-up, metres. Vertex order = %s. %d vertices, %d triangles.\n"
                % (nframes_note, len(rest_positions), len(tris)))
        f.write("o drape\n")
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
def render_previews(scene, cloth, quads, frames_pos, outdir):
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
    cam.location = (2.2, -2.4, 2.1)
    direction = Vector((0.05, 0.0, 0.35)) - cam.location
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


def main():
    args = parse_args()
    os.makedirs(args.out, exist_ok=True)
    scene = reset_scene()
    cloth, mod = make_cloth(scene)
    make_obstacles(scene)

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
    print("cloth: %d vertices, %d quads, %d triangles" % (nverts, len(me.polygons), len(tris)))

    quads = [tuple(p.vertices) for p in me.polygons]
    preview_frames = [int(x) for x in args.preview_frames.split(",")] if args.preview else []
    preview_pos = {}
    frames = []
    report = []
    t0 = time.time()
    for fr in range(SIM_START, SIM_END + 1):        # step sequentially so the solver advances
        scene.frame_set(fr)
        dg = bpy.context.evaluated_depsgraph_get()
        pos = evaluated_positions(cloth, dg)
        if len(pos) != nverts:
            raise RuntimeError("frame %d: evaluated mesh has %d vertices, expected %d"
                               % (fr, len(pos), nverts))
        if fr in preview_frames:
            preview_pos[fr] = pos
        if fr < KEEP_START or fr > KEEP_END:
            print("frame %3d simulated (%.1fs)" % (fr, time.time() - t0), flush=True)
            continue
        frames.append(pos)
        line = "frame %3d" % fr
        if not args.no_check:
            nint = self_intersections(pos, tris, tri_sets)
            dmin = min_nonadjacent_vertex_distance(pos, ring2)
            pen = max(0.0, max(min(TABLE_R - p.xy.length, TABLE_H - p.z) for p in pos))
            below = max(0.0, -min(p.z for p in pos))
            line += ("  self-intersecting triangle pairs %d  min non-adjacent vertex dist %.4f m"
                     "  table penetration %.4f m  below ground %.4f m" % (nint, dmin, pen, below))
            report.append((fr, nint, dmin, pen, below))
        print(line + "  (%.1fs)" % (time.time() - t0), flush=True)

    base = os.path.join(args.out, args.name)
    write_obj(base + ".obj", rest, tris, "the vertex order of %s.pc2" % args.name)
    write_pc2(base + ".pc2", frames, KEEP_START)
    print("wrote %s.obj and %s.pc2: %d vertices, %d triangles, %d frames (Blender frames %d-%d)"
          % (base, base, nverts, len(tris), len(frames), KEEP_START, KEEP_END))

    if report:
        bad = [r for r in report if r[1] > 0]
        with open(os.path.join(args.out, "self_intersections.txt"), "w") as f:
            f.write("frame intersecting_pairs min_nonadjacent_vertex_dist table_penetration below_ground\n")
            for r in report:
                f.write("%d %d %.5f %.5f %.5f\n" % r)
        print("self-intersection check: %d of %d frames have intersecting triangle pairs, "
              "total %d pairs, max %d; min non-adjacent vertex distance %.4f m"
              % (len(bad), len(report), sum(r[1] for r in report), max(r[1] for r in report),
                 min(r[2] for r in report)))

    if args.preview:
        render_previews(scene, cloth, quads, preview_pos, args.out)


if __name__ == "__main__":
    main()

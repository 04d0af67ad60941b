"""Check the bundled colliders (`data/<scene>/<scene>_colliders.obj` [+ `.pc2`]) against the cloth
they were simulated with (`data/<scene>/<scene>.obj` + `.pc2`), reading only the files.

Run headless from the repository root (Blender 3.4, for mathutils.bvhtree):

    blender -b --factory-startup --python-exit-code 1 \
        --python data/blender/check_colliders.py -- [--scene drape|pile|rucked|layered] [--preview DIR]

Checks, in the files' Y-up coordinates: the colliders' OBJ and PC2 have the same number of vertices;
the colliders' PC2 has the cloth PC2's startFrame, sampleRate and number of samples; the collider mesh
is closed with outward normals (positive volume); per sample, the distance from every cloth vertex to
the collider surface (negative = inside), its minimum and the
number of cloth vertices within 3 cm; the lowest cloth y (the ground is y = 0); for a table, the
clearance of the cloth above its top and the angle it has turned. With --preview DIR, one Workbench
render of the last sample (cloth, colliders and, if the scene has one, the ground) from the files.
Exit status 1 if a structural check fails.
"""

import math
import os
import struct
import sys

import bpy
from mathutils import Vector
from mathutils.bvhtree import BVHTree

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_cloth_sequence as mcs   # noqa: E402  (the scene dicts)


def read_obj(path):
    verts, tris = [], []
    with open(path) as f:
        for line in f:
            w = line.split()
            if not w:
                continue
            if w[0] == "v":
                verts.append(Vector([float(x) for x in w[1:4]]))
            elif w[0] == "f":
                tris.append(tuple(int(x.split("/")[0]) - 1 for x in w[1:]))
    return verts, tris


def read_pc2(path):
    with open(path, "rb") as f:
        data = f.read()
    magic, version, n, start, rate, ns = struct.unpack_from("<12siiffi", data, 0)
    assert magic == b"POINTCACHE2\0" and version == 1, path
    assert len(data) == 32 + 12 * n * ns, "%s: %d bytes, expected %d" % (path, len(data), 32 + 12 * n * ns)
    frames = []
    for k in range(ns):
        flat = struct.unpack_from("<%df" % (3 * n), data, 32 + 12 * n * k)
        frames.append([Vector(flat[3 * i:3 * i + 3]) for i in range(n)])
    return dict(n=n, start=start, rate=rate, ns=ns, frames=frames)


def signed_distances(cloth_pos, coll_pos, coll_tris):
    tree = BVHTree.FromPolygons(coll_pos, coll_tris, all_triangles=True)
    out = []
    for p in cloth_pos:
        loc, normal, _, dist = tree.find_nearest(p)
        # Inside: the nearest point is the foot of a perpendicular on a face, behind it. (Outside
        # a convex edge the nearest point is on the edge and either face's normal may be returned:
        # a point level with the table top, beyond its rim, gives a dot product of about -1e-8.)
        out.append(-dist if (p - loc).dot(normal) < -0.5 * dist else dist)
    return out


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    scene_name = argv[argv.index("--scene") + 1] if "--scene" in argv else "drape"
    preview = argv[argv.index("--preview") + 1] if "--preview" in argv else None
    P = mcs.SCENES[scene_name]
    d = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), scene_name)
    base = os.path.join(d, scene_name)
    ok = True

    def fail(msg):
        nonlocal ok
        ok = False
        print("FAIL " + msg)

    cloth_v, cloth_t = read_obj(base + ".obj")
    cloth = read_pc2(base + ".pc2")
    print("scene %s: cloth %d vertices, %d triangles; PC2 %d points, startFrame %g, sampleRate %g, %d samples"
          % (scene_name, len(cloth_v), len(cloth_t), cloth["n"], cloth["start"], cloth["rate"], cloth["ns"]))
    lowest = [min(p.y for p in pos) for pos in cloth["frames"]]
    print("  lowest cloth y: %.4f m over all samples, %.4f m in the last; ground in the scene: %s"
          % (min(lowest), lowest[-1], "yes (y = 0)" if "ground" in P else "no"))

    coll_path = base + "_colliders.obj"
    if not os.path.exists(coll_path):
        if "table" in P or "arm" in P:
            fail("%s missing" % coll_path)
        else:
            print("  no collider mesh (the scene's only obstacle is the ground)")
        return ok
    coll_v, coll_t = read_obj(coll_path)
    size = os.path.getsize(coll_path)
    if os.path.exists(base + "_colliders.pc2"):
        coll = read_pc2(base + "_colliders.pc2")
        size += os.path.getsize(base + "_colliders.pc2")
        print("  colliders: OBJ %d vertices, %d triangles; PC2 %d points, startFrame %g, sampleRate %g, "
              "%d samples (%d bytes in all)" % (len(coll_v), len(coll_t), coll["n"], coll["start"],
                                                coll["rate"], coll["ns"], size))
        if coll["n"] != len(coll_v):
            fail("collider OBJ has %d vertices, PC2 %d" % (len(coll_v), coll["n"]))
        for k in ("start", "rate", "ns"):
            if coll[k] != cloth[k]:
                fail("collider PC2 %s %g != cloth's %g" % (k, coll[k], cloth[k]))
        coll_frames = coll["frames"]
        print("  OBJ vs first PC2 sample: max difference %.2e m"
              % max((a - b).length for a, b in zip(coll_v, coll_frames[0])))
    else:
        print("  colliders: OBJ %d vertices, %d triangles, static (%d bytes)" % (len(coll_v), len(coll_t), size))
        coll_frames = [coll_v] * cloth["ns"]

    # Closed, outward: every edge used twice in opposite directions, positive volume.
    edges = {}
    for t in coll_t:
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            edges[(a, b)] = edges.get((a, b), 0) + 1
    closed = all(c == 1 and edges.get((b, a)) == 1 for (a, b), c in edges.items())
    vol = sum(coll_v[a].dot(coll_v[b].cross(coll_v[c])) for a, b, c in coll_t) / 6.0
    print("  collider mesh closed and consistently wound: %s; volume %.5f m^3" % (closed, vol))
    if not closed or vol <= 0:
        fail("collider mesh not closed or not outward")
    ys = [p.y for p in coll_v]
    print("  collider y range %.4f .. %.4f m" % (min(ys), max(ys)))

    if "table" in P:
        T = P["table"]
        expect = math.pi * T["r"] ** 2 * T["h"]
        print("  table: expected volume %.5f m^3 (the 96-gon's is %.5f)"
              % (expect, 0.5 * 96 * math.sin(2 * math.pi / 96) * T["r"] ** 2 * T["h"]))
        i0 = max(range(len(coll_v)), key=lambda i: coll_v[i].y)      # a top-rim vertex
        ang = [math.degrees(math.atan2(f[i0].x, f[i0].z) - math.atan2(coll_v[i0].x, coll_v[i0].z))
               for f in coll_frames]
        ang = [(a + 180.0) % 360.0 - 180.0 for a in ang]
        print("  table turned (from the OBJ, about +y): %.2f deg at the first sample, %.2f deg at the last "
              "(keys: %s)" % (ang[0], ang[-1], T["spin"]))

    thick = P["obstacle_thickness"]
    dmin_obj = P["collision"]["distance_min"]
    print("  solver: obstacle outer thickness %.3f m, cloth object distance %.3f m" % (thick, dmin_obj))
    rows = []
    for k, (cpos, opos) in enumerate(zip(cloth["frames"], coll_frames)):
        sd = signed_distances(cpos, opos, coll_t)
        rows.append((k, min(sd), sum(1 for s in sd if s < 0.03)))
    worst = min(rows, key=lambda r: r[1])
    print("  cloth-to-collider signed distance: min %.4f m (sample %d, frame %g); last sample min %.4f m, "
          "%d cloth vertices within 3 cm" % (worst[1], worst[0], cloth["start"] + worst[0], rows[-1][1], rows[-1][2]))
    for k in (0, len(rows) // 2, len(rows) - 1):
        print("    sample %3d (frame %g): min %.4f m, %d within 3 cm"
              % (k, cloth["start"] + k, rows[k][1], rows[k][2]))
    if worst[1] < 0:
        fail("a cloth vertex is inside the colliders")
    if "table" in P:
        r, h = P["table"]["r"], P["table"]["h"]
        for k in (0, len(rows) - 1):
            above = [p.y - h for p in cloth["frames"][k] if math.hypot(p.x, p.z) < r - 0.02 and p.y > h - 0.05]
            print("    sample %3d: %d cloth vertices over the table top, clearance min %.4f m, max %.4f m"
                  % (k, len(above), min(above) if above else float("nan"), max(above) if above else float("nan")))
    if "arm" in P:
        A = P["arm"]
        c = mcs.to_file_axes(A["centre"])
        for k in (0, len(rows) - 1):
            rad = [math.hypot(p.y - c[1], p.z - c[2]) - A["r"] for p in cloth["frames"][k]
                   if abs(p.x - c[0]) < A["length"] / 2]
            print("    sample %3d: clearance of the cloth from the arm's side min %.4f m" % (k, min(rad)))

    if preview:
        render(P, scene_name, cloth_t, cloth["frames"][-1], coll_t, coll_frames[-1],
               cloth["start"] + cloth["ns"] - 1, preview)
    return ok


def render(P, scene_name, cloth_t, cloth_pos, coll_t, coll_pos, frame, outdir):
    """The last sample, from the files, back in Blender's Z-up axes."""
    scene = mcs.reset_scene(P)
    back = lambda p: (p.x, -p.z, p.y)                  # file (x, y, z) -> Blender (x, -z, y)
    for name, pos, tris in (("cloth", cloth_pos, cloth_t), ("colliders", coll_pos, coll_t)):
        me = bpy.data.meshes.new(name)
        me.from_pydata([back(p) for p in pos], [], tris)
        me.update()
        ob = bpy.data.objects.new(name, me)
        scene.collection.objects.link(ob)
    if "ground" in P:
        bpy.ops.mesh.primitive_plane_add(size=P["ground"], location=(0.0, 0.0, 0.0))
    dummy = bpy.data.objects.new("dummy", None)
    scene.collection.objects.link(dummy)
    os.makedirs(outdir, exist_ok=True)
    # render_previews hides its first argument and renders the given frame's cloth mesh: here the
    # cloth is already in the scene, so it gets an empty cloth mesh.
    mcs.render_previews(scene, dummy, [], {frame: []}, outdir, P["camera"])
    src = os.path.join(outdir, "preview_%03d.png" % frame)
    dst = os.path.join(outdir, "%s_colliders_%03d.png" % (scene_name, frame))
    os.replace(src, dst)
    print("  rendered %s" % dst)


if __name__ == "__main__":
    sys.exit(0 if main() else 1)

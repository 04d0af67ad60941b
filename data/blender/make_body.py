#!/usr/bin/env python3
"""A torso for the rucked sleeve's arm: the occluding body of about 20k triangles that the occluder cost
benchmark uses (bench/occluders_bench.cpp --body). A closed capsule (a cylinder with hemispherical ends),
vertical, at the end of the sleeve's arm where a shoulder would be, in the data's Y-up metres.

Usage: python3 data/blender/make_body.py data/rucked/rucked_body.obj
"""
import math
import sys

AROUND, RINGS = 160, 64            # 160 x 64 quads -> 20,160 triangles with the poles' fans
RADIUS, HALF_HEIGHT = 0.17, 0.25   # capsule: radius, half the height of its cylinder part
CENTRE = (0.93, 0.80, 0.0)         # the arm runs along x over [-0.75, 0.75] at y = 0.90, radius 0.06


def main(path):
    verts, faces = [], []
    # Rings from the bottom pole to the top one: a hemisphere, the cylinder, a hemisphere.
    profile = []
    for i in range(1, RINGS // 2):
        a = -math.pi / 2 + math.pi * i / RINGS
        profile.append((RADIUS * math.cos(a), -HALF_HEIGHT + RADIUS * math.sin(a)))
    for i in range(RINGS // 2, RINGS):
        a = -math.pi / 2 + math.pi * i / RINGS
        profile.append((RADIUS * math.cos(a), HALF_HEIGHT + RADIUS * math.sin(a)))
    for r, y in profile:
        for j in range(AROUND):
            t = 2 * math.pi * j / AROUND
            verts.append((CENTRE[0] + r * math.cos(t), CENTRE[1] + y, CENTRE[2] + r * math.sin(t)))
    bottom = len(verts)
    verts.append((CENTRE[0], CENTRE[1] - HALF_HEIGHT - RADIUS, CENTRE[2]))
    top = len(verts)
    verts.append((CENTRE[0], CENTRE[1] + HALF_HEIGHT + RADIUS, CENTRE[2]))
    rings = len(profile)
    for i in range(rings - 1):  # outward winding
        for j in range(AROUND):
            a, b = i * AROUND + j, i * AROUND + (j + 1) % AROUND
            c, d = a + AROUND, b + AROUND
            faces += [(a, c, b), (b, c, d)]
    for j in range(AROUND):
        faces.append((bottom, j, (j + 1) % AROUND))
        last = (rings - 1) * AROUND
        faces.append((top, last + (j + 1) % AROUND, last + j))
    with open(path, "w") as out:
        out.write("# pleat: a capsule torso for the rucked sleeve (data/blender/make_body.py), Y-up metres\n")
        for v in verts:
            out.write("v %.6f %.6f %.6f\n" % v)
        for f in faces:
            out.write("f %d %d %d\n" % (f[0] + 1, f[1] + 1, f[2] + 1))
    print(f"wrote {path}: {len(verts)} vertices, {len(faces)} triangles")


if __name__ == "__main__":
    main(sys.argv[1])

#!/usr/bin/env python3
"""Writes data/envmaps/sky_sun.hdr: a small procedural equirectangular sky (Radiance RGBE, 128 x 64).

Y-up (the bundled drape's convention): a blue-white gradient brighter towards the zenith, a warm sun disc
about 35 degrees above the horizon, a dim ground below. Deterministic; no dependencies beyond python3.
Run from the repository root:  python3 data/envmaps/make_sky_hdr.py [WIDTH HEIGHT OUT.hdr]
"""
import math
import os
import sys

WIDTH, HEIGHT = 128, 64
SUN = (math.cos(math.radians(35)) * math.cos(math.radians(40)), math.sin(math.radians(35)),
       math.cos(math.radians(35)) * math.sin(math.radians(40)))


def radiance(x, y, z):
    if y < 0:
        return (0.25, 0.22, 0.18)  # ground
    sky = (0.35 + 0.65 * y, 0.45 + 0.55 * y, 0.75 + 0.25 * y)
    cos_sun = x * SUN[0] + y * SUN[1] + z * SUN[2]
    sun = 60.0 if cos_sun > math.cos(math.radians(4)) else 0.0
    return (sky[0] + sun, sky[1] + 0.9 * sun, sky[2] + 0.7 * sun)


def rgbe(r, g, b):
    m = max(r, g, b)
    if m < 1e-32:
        return bytes((0, 0, 0, 0))
    mantissa, exponent = math.frexp(m)
    scale = mantissa * 256.0 / m
    return bytes((int(r * scale), int(g * scale), int(b * scale), exponent + 128))


def main():
    global WIDTH, HEIGHT
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "sky_sun.hdr")
    if len(sys.argv) == 4:
        WIDTH, HEIGHT, out = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    rows = []
    for j in range(HEIGHT):
        theta = math.pi * (j + 0.5) / HEIGHT  # from the zenith (+y) down
        row = b""
        for i in range(WIDTH):
            phi = 2 * math.pi * (i + 0.5) / WIDTH
            x, y, z = math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi)
            row += rgbe(*radiance(x, y, z))
        rows.append(row)
    header = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (HEIGHT, WIDTH)
    tmp = out + ".tmp"
    with open(tmp, "wb") as f:
        f.write(header + b"".join(rows))
    os.replace(tmp, out)
    print("wrote", out)


if __name__ == "__main__":
    main()

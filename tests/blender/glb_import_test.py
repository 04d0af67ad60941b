# pleat's glb in Blender, run by ctest in Blender headless:
#   blender -b --factory-startup --python-exit-code 1 --python tests/blender/glb_import_test.py -- \
#       --pleat PLEAT_EXECUTABLE --work SCRATCH_DIR
# A Z-up cloth (Blender's axes: a sheet over z = 0 sagging as it falls, written as a numbered OBJ sequence in
# world coordinates) shaded by `pleat shade` and imported with Blender's own glTF importer must stand as it
# was: the imported first frame's world coordinates equal the input's. --up auto takes the ground's side
# (--ground z=0); without a ground it takes y, warning that the cloth falls along -z; --up z; --up y (the
# input taken for Y-up) imports it on its side, with a warning since the ground says otherwise. Both layouts.
# Blender 3.4's importer uses numpy.bool, gone from numpy 1.24: the workaround the README gives is applied.

import argparse
import os
import shutil
import subprocess
import sys

import bpy
import numpy as np

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
parser = argparse.ArgumentParser()
parser.add_argument("--pleat", required=True)
parser.add_argument("--work", required=True)
args = parser.parse_args(argv)
failures = []


def expect(condition, message):
    if not condition:
        failures.append(message)
        print("FAILED:", message)


if not hasattr(np, "bool"):  # Blender 3.4's glTF importer with numpy >= 1.24 (README, In Blender)
    np.bool = bool

shutil.rmtree(args.work, ignore_errors=True)
os.makedirs(args.work)
# The cloth: 12 x 12 vertices over [-1, 1]^2, sagging in z as it falls from z = 1.2 (Z-up).
n = 12
u, v = np.meshgrid(np.linspace(-1, 1, n), np.linspace(-1, 1, n), indexing="ij")
faces = [(i * n + j, (i + 1) * n + j, (i + 1) * n + j + 1) for i in range(n - 1) for j in range(n - 1)]
faces += [(i * n + j, (i + 1) * n + j + 1, i * n + j + 1) for i in range(n - 1) for j in range(n - 1)]
frames = {}
for k in range(4):
    z = 1.2 - 0.15 * k - 0.3 * (1 - u ** 2) * (1 - v ** 2) * k / 3
    frames[k + 1] = np.stack([u.ravel(), v.ravel() * 0.8, z.ravel()], axis=1)
    with open(os.path.join(args.work, f"cloth_{k + 1:04d}.obj"), "w") as out:
        out.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in frames[k + 1])
        out.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces)
sequence = os.path.join(args.work, "cloth_%04d.obj")


def shade(name, *options):
    """`pleat shade` of the cloth into NAME.glb; its stderr."""
    path = os.path.join(args.work, name + ".glb")
    run = subprocess.run([args.pleat, "shade", sequence, "-o", path, *options], capture_output=True, text=True)
    expect(run.returncode == 0, f"{name}: pleat shade failed: {run.stderr}")
    return path, run.stdout + run.stderr


def imported_first_frame(path):
    """World coordinates of the imported glb's first frame (node frame_0001), in its vertex order."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=path)
    obj = bpy.data.objects["frame_0001"]
    matrix = np.array(obj.matrix_world, dtype=np.float64)
    local = np.array([p.co[:] for p in obj.data.vertices], dtype=np.float64)
    return local @ matrix[:3, :3].T + matrix[:3, 3]


def upright(points):
    """The imported points are the input's first frame: in order for the input layout; for the sides layout,
    whose front and back primitives Blender may import as vertices of their own, as a set."""
    if points.shape == frames[1].shape and np.allclose(points, frames[1], atol=1e-5):
        return True
    unique = np.unique(np.round(points, 5), axis=0)
    return np.array_equal(unique, np.unique(np.round(frames[1], 5), axis=0))


for layout in ("input", "sides"):
    path, said = shade(f"ground_{layout}", "--ground", "z=0", "--glb-layout", layout)
    expect("up +z, from --ground z=0" in said, f"{layout}: the up chosen is not reported: {said}")
    expect(upright(imported_first_frame(path)), f"{layout}: the cloth shaded with --ground z=0 is not upright")

path, said = shade("falling", "--glb-layout", "input")  # no ground: Y-up assumed, the cloth's fall warns
expect("pleat: warning: up +y (the default), but the cloth falls along -z: if +z is up, give --up z" in said,
       f"falling: {said}")
path, said = shade("told_z", "--up", "z")
expect("up +z, from --up" in said and "warning" not in said, f"told z: {said}")
expect(upright(imported_first_frame(path)), "the cloth shaded with --up z is not upright")

path, said = shade("told_y", "--ground", "z=0", "--up", "y", "--glb-layout", "input")
expect("pleat: warning: --up y, but the cloth stands on --ground z=0 (up +z)" in said, f"told y: {said}")
on_side = imported_first_frame(path)  # Blender reads y as up: the input's y is now z
expect(np.allclose(on_side[:, 2], frames[1][:, 1], atol=1e-5), "--up y did not keep the coordinates as given")

print(f"glb import: failures: {len(failures)}")
if failures:
    sys.exit(1)

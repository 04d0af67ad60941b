"""Installs the Blender add-on pleat_bake for the user's Blender and makes the Python module pleat importable
from Blender's Python; enables the add-on and saves the preferences. One command, headless:

    /usr/bin/python3 python/blender/install.py [--blender PATH] [--module DIR] [--link]

Run with a python3 that imports pleat (README, Python), or give --module DIR, a folder holding the package
pleat/ with its compiled core (build/python after a build; used when this python3 has no pleat). The
add-on goes to Blender's user add-ons folder and the package to its user modules folder (both made when
missing, as for a user who never saved preferences), copied, or linked with --link (a developer's clone:
rebuilds and edits show at once). Blender itself says where those folders are, so BLENDER_USER_SCRIPTS and
BLENDER_USER_CONFIG (what CI sets) are honoured. Then, inside Blender, the module is imported and run on a
small sheet, and the add-on enabled; anything that fails (a Blender older than 3.4, a Blender whose Python
is not the module's: the module is built for one CPython version) is said in one line, exit status 1.

Supported: Blender 3.4 to 4.x whose Python has the module's version (Debian 12's blender 3.4 and python3 are
both 3.11; blender.org's builds bundle Python 3.10 up to 4.0 and 3.11 from 4.1).

The same file runs inside Blender (blender -b --python install.py -- ...), where it does the installing.
"""
import argparse
import glob
import os
import shutil
import subprocess
import sys

ADDON = "pleat_bake"
HERE = os.path.dirname(os.path.abspath(__file__))
MINIMUM_BLENDER = (3, 4, 0)


def fail(message):
    print(f"pleat install: {message}", file=sys.stderr)
    sys.exit(1)


def module_folder(given):
    """The folder holding pleat/ (with its compiled _pleat) to install: --module, this python's pleat, or the
    build tree's."""
    candidates = []
    if given:
        candidates.append(os.path.abspath(given))
    else:
        try:
            import pleat  # noqa: F401  (this python's, e.g. installed by pip)

            candidates.append(os.path.dirname(os.path.dirname(os.path.abspath(pleat.__file__))))
        except ImportError:
            pass
        candidates.append(os.path.join(os.path.dirname(os.path.dirname(HERE)), "build", "python"))
    for folder in candidates:
        if glob.glob(os.path.join(folder, "pleat", "_pleat*.so")) and os.path.isfile(
                os.path.join(folder, "pleat", "__init__.py")):
            return folder
    fail(f"no built module pleat in {' or '.join(candidates)}: install it first (README, Python) or give "
         "--module DIR (a folder with pleat/__init__.py and pleat/_pleat*.so)")


def outside_blender(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--blender", default=shutil.which("blender"),
                        help="the Blender to install for (default: blender on PATH)")
    parser.add_argument("--module", help="folder holding the package pleat/ (default: this python's pleat, "
                                         "else build/python)")
    parser.add_argument("--link", action="store_true",
                        help="link the add-on and the module instead of copying them (for a developer's clone)")
    args = parser.parse_args(argv)
    if not args.blender or not os.access(args.blender, os.X_OK):
        fail("no Blender found: install it (Debian: apt install blender) or give --blender PATH")
    module = module_folder(args.module)
    command = [args.blender, "-b", "--python-exit-code", "1", "--python", os.path.abspath(__file__), "--",
               "--addon-source", os.path.join(HERE, ADDON), "--module-source", os.path.join(module, "pleat")]
    if args.link:
        command.append("--link")
    # Blender prints its own lines on stdout; ours (prefixed) go through as they are.
    run = subprocess.run(command, capture_output=True, text=True)
    for line in (run.stdout + run.stderr).splitlines():
        if line.startswith("pleat install:"):
            print(line, file=sys.stderr if run.returncode else sys.stdout)
    if run.returncode != 0:
        if "pleat install:" not in run.stdout + run.stderr:
            print(run.stdout + run.stderr, file=sys.stderr)
        sys.exit(1)


def place(source, target, link):
    """Puts `source` (a folder) at `target`, replacing what was there (a link, a folder or a file)."""
    if os.path.islink(target) or os.path.isfile(target):
        os.unlink(target)
    elif os.path.isdir(target):
        shutil.rmtree(target)
    if link:
        os.symlink(source, target)
    else:
        shutil.copytree(source, target, ignore=shutil.ignore_patterns("__pycache__"))


def check_module(modules, source):
    """Imports pleat from Blender's Python (the copy in `modules`, or `source` itself where Blender's Python
    already sees it) and computes a flat sheet (A = 1 on both sides)."""
    import importlib.machinery

    built = [os.path.basename(p) for p in glob.glob(os.path.join(modules, "pleat", "_pleat*.so"))]
    if not any(name.endswith(suffix) for name in built for suffix in importlib.machinery.EXTENSION_SUFFIXES):
        fail(f"the module is built for another Python ({', '.join(built)}); this Blender's Python is "
             f"{sys.version.split()[0]} (it loads {' '.join(importlib.machinery.EXTENSION_SUFFIXES)}): build "
             "pleat with the python3 of that version")
    import numpy as np

    try:
        import pleat
    except ImportError as e:
        fail(f"Blender's Python cannot import pleat from {modules}: {e}")
    imported = os.path.realpath(os.path.dirname(pleat.__file__))
    if imported not in (os.path.realpath(os.path.join(modules, "pleat")), os.path.realpath(source)):
        fail(f"Blender's Python imports another pleat first ({pleat.__file__}); remove it or its path")
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    square = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=np.float64)
    sky = pleat.sky_visibility(faces, square)
    if not np.allclose(sky, 1.0):
        fail(f"pleat computed {sky.tolist()} for a flat square (expected 1 everywhere)")
    return pleat


def inside_blender(argv):
    import bpy

    parser = argparse.ArgumentParser()
    parser.add_argument("--addon-source", required=True)
    parser.add_argument("--module-source", required=True)
    parser.add_argument("--link", action="store_true")
    args = parser.parse_args(argv)
    version = bpy.app.version
    if tuple(version) < MINIMUM_BLENDER:
        fail(f"Blender {bpy.app.version_string} is older than the add-on needs "
             f"({'.'.join(map(str, MINIMUM_BLENDER))})")
    addons = bpy.utils.user_resource("SCRIPTS", path="addons", create=True)
    modules = bpy.utils.user_resource("SCRIPTS", path="modules", create=True)
    if not addons or not modules:
        fail("Blender has no user scripts folder (set BLENDER_USER_SCRIPTS)")
    place(os.path.abspath(args.addon_source), os.path.join(addons, ADDON), args.link)
    place(os.path.abspath(args.module_source), os.path.join(modules, "pleat"), args.link)
    bpy.utils.refresh_script_paths()
    if modules not in sys.path:
        sys.path.append(modules)
    pleat = check_module(modules, args.module_source)
    bpy.ops.preferences.addon_enable(module=ADDON)
    if ADDON not in bpy.context.preferences.addons:
        fail(f"Blender did not enable the add-on {ADDON} (see its console output)")
    bpy.ops.wm.save_userpref()
    how = "linked" if args.link else "copied"
    print(f"pleat install: Blender {bpy.app.version_string} (Python {sys.version.split()[0]}): add-on {ADDON} "
          f"{how} to {addons} and enabled; module pleat {pleat.__version__} {how} to {modules}; preferences "
          "saved")


if __name__ == "__main__":
    try:
        import bpy  # noqa: F401
    except ImportError:
        outside_blender(sys.argv[1:])
    else:
        inside_blender(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])

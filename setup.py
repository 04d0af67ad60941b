"""Builds the Python module pleat for `pip install --no-build-isolation .` (metadata: pyproject.toml): the
package python/pleat/ and its compiled core pleat._pleat, built by the project's CMake (target pleat_python,
python/CMakeLists.txt). Where build/ is a Release build of this tree for this python (scripts/setup.sh makes
one), its target is brought up to date there, reusing everything built; otherwise build-python/ is configured
without the tests and benchmarks (CMAKE_ARGS adds configure options). The build runs as many jobs as
CMAKE_BUILD_PARALLEL_LEVEL says (cmake --build reads it; unset: the generator's default)."""
import os
import pathlib
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


def cache_entries(cache):
    """NAME -> value of a CMakeCache.txt."""
    entries = {}
    for line in cache.read_text(errors="replace").splitlines():
        name, typed, value = line.partition("=")
        if typed and not name.startswith(("#", "//")):
            entries[name.split(":")[0]] = value
    return entries


def reusable_build():
    """build/ when it is a Release build of this tree with the module on, for this python; else None."""
    cache = ROOT / "build" / "CMakeCache.txt"
    if not cache.is_file() or os.environ.get("CMAKE_ARGS"):
        return None
    entries = cache_entries(cache)
    python = entries.get("_Python3_EXECUTABLE") or entries.get("Python3_EXECUTABLE") or ""
    same = (entries.get("CMAKE_BUILD_TYPE") == "Release" and entries.get("PLEAT_BUILD_PYTHON") == "ON"
            and os.path.realpath(entries.get("CMAKE_HOME_DIRECTORY", "")) == os.path.realpath(ROOT)
            and python and os.path.realpath(python) == os.path.realpath(sys.executable))
    return ROOT / "build" if same else None


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = reusable_build()
        if build is not None:
            print(f"pleat: reusing the Release build in {build}", flush=True)
            self.build_in(build, ext)
            return
        build = ROOT / "build-python"  # kept between installs; beside build/, so ccache serves both
        configure = ["cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                     "-DPLEAT_BUILD_TESTS=OFF", "-DPLEAT_BUILD_BENCH=OFF", "-DPLEAT_BUILD_PYTHON=ON",
                     f"-DPython3_EXECUTABLE={sys.executable}"]
        if shutil.which("ccache"):
            configure += ["-DCMAKE_CXX_COMPILER_LAUNCHER=ccache", "-DCMAKE_C_COMPILER_LAUNCHER=ccache"]
        configure += shlex.split(os.environ.get("CMAKE_ARGS", ""))
        subprocess.run(configure, check=True)
        self.build_in(build, ext)

    def build_in(self, build, ext):
        subprocess.run(["cmake", "--build", str(build), "--target", "pleat_python"], check=True)
        built = sorted((build / "python" / "pleat").glob("_pleat*.so"))
        if len(built) != 1:
            raise RuntimeError(f"expected one _pleat module in {build / 'python' / 'pleat'}, found {built}")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[0], target)


setup(packages=["pleat"], package_dir={"": "python"},
      ext_modules=[Extension("pleat._pleat", sources=[])], cmdclass={"build_ext": CMakeBuild})

"""Builds the Python module pleat for `pip install --no-build-isolation .` (metadata: pyproject.toml): the
package python/pleat/ and its compiled core pleat._pleat, built by the project's CMake (target pleat_python,
python/CMakeLists.txt) in build-python/, without the tests and benchmarks. CMAKE_ARGS adds configure options."""
import os
import pathlib
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = ROOT / "build-python"  # kept between installs; beside build/, so ccache serves both
        configure = ["cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                     "-DPLEAT_BUILD_TESTS=OFF", "-DPLEAT_BUILD_BENCH=OFF", "-DPLEAT_BUILD_PYTHON=ON",
                     f"-DPython3_EXECUTABLE={sys.executable}"]
        if shutil.which("ccache"):
            configure += ["-DCMAKE_CXX_COMPILER_LAUNCHER=ccache", "-DCMAKE_C_COMPILER_LAUNCHER=ccache"]
        configure += shlex.split(os.environ.get("CMAKE_ARGS", ""))
        subprocess.run(configure, check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 2))
        subprocess.run(["cmake", "--build", str(build), "--target", "pleat_python", "-j", jobs], check=True)
        built = sorted((build / "python" / "pleat").glob("_pleat*.so"))
        if len(built) != 1:
            raise RuntimeError(f"expected one _pleat module in {build / 'python' / 'pleat'}, found {built}")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[0], target)


setup(packages=["pleat"], package_dir={"": "python"},
      ext_modules=[Extension("pleat._pleat", sources=[])], cmdclass={"build_ext": CMakeBuild})

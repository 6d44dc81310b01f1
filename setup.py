"""`pip install .`: the module `aggpack` of a CMake build, as a wheel for this interpreter.

The module is the CMake target aggpack_python (python/CMakeLists.txt). Its build is reused:
AGGPACK_BUILD_DIR, else ./build when it holds a CMake build (only the module's target is
brought up to date); else a Release build is configured there first (minutes: the library
entire). setuptools' own build files go inside that build folder, not into the checkout.
"""
import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Distribution, setup
from setuptools.command.build_py import build_py

HERE = pathlib.Path(__file__).resolve().parent
BUILD = pathlib.Path(os.environ.get("AGGPACK_BUILD_DIR", HERE / "build")).resolve()


class BuildWithCMake(build_py):
    """The package's Python files, and beside them the extension CMake built."""

    def run(self):
        super().run()
        if not (BUILD / "CMakeCache.txt").exists():
            subprocess.check_call(["cmake", "-S", str(HERE), "-B", str(BUILD), "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
                                   f"-DPython3_EXECUTABLE={sys.executable}"])
        subprocess.check_call(["cmake", "--build", str(BUILD), "--target", "aggpack_python"])
        built = sorted((BUILD / "python" / "aggpack").glob("_aggpack*.so"))
        if not built:
            raise SystemExit(f"aggpack: no _aggpack*.so in {BUILD / 'python' / 'aggpack'}: was the module built "
                             "(pybind11-dev and python3-dev installed)?")
        target = pathlib.Path(self.build_lib) / "aggpack"
        target.mkdir(parents=True, exist_ok=True)
        shutil.copy2(built[0], target / built[0].name)


class BinaryDistribution(Distribution):
    """A wheel for this platform and interpreter: the package holds a compiled module."""

    def has_ext_modules(self):
        return True


(BUILD / "setuptools").mkdir(parents=True, exist_ok=True)
setup(cmdclass={"build_py": BuildWithCMake}, distclass=BinaryDistribution,
      options={"build": {"build_base": str(BUILD / "setuptools")},
               "egg_info": {"egg_base": str(BUILD / "setuptools")}})

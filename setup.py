"""Builds the cmkit Python package with the project's CMake build.

pyproject.toml names setuptools as the build backend; this file only hands
the extension module over to CMake (python/CMakeLists.txt builds it), so
there is one build description, not two. Environment variables:

  CMKIT_BUILD_JOBS       parallel compile jobs (default: the processors)
  CMKIT_CMAKE_ARGS       more arguments for CMake's configure step
  CMKIT_CMAKE_BUILD_DIR  an already configured build tree with
                         -DCMKIT_PYTHON=ON to build the module in (and take
                         it from) instead of a fresh one under build/
"""

import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


def project_version():
    """The version of CMakeLists.txt's project() call."""
    text = (ROOT / "CMakeLists.txt").read_text(encoding="utf-8")
    match = re.search(r"project\(cmkit\s+VERSION\s+([0-9.]+)", text)
    if not match:
        sys.exit("setup.py: no `project(cmkit VERSION x.y.z` in CMakeLists.txt")
    return match.group(1)


class CMakeExtension(Extension):
    """The extension module cmkit._cmkit, built by CMake, not by setuptools."""

    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    """Configures and builds the CMake target cmkit_python, then copies the module."""

    def run(self):
        if shutil.which("cmake") is None:
            sys.exit("setup.py: cmake was not found (Debian: apt-get install cmake ninja-build g++)")
        for ext in self.extensions:
            self.build_cmake(ext)

    def build_cmake(self, ext):
        given = os.environ.get("CMKIT_CMAKE_BUILD_DIR")
        build_dir = Path(given).resolve() if given else Path(self.build_temp).resolve() / "cmake"
        if not given:
            self.configure(build_dir)
        jobs = os.environ.get("CMKIT_BUILD_JOBS", str(os.cpu_count() or 1))
        self.spawn(["cmake", "--build", str(build_dir), "--target", "cmkit_python", "-j", jobs])
        built = sorted((build_dir / "python" / "cmkit").glob("_cmkit*.so"))
        if not built:
            sys.exit(f"setup.py: the CMake build left no _cmkit*.so in {build_dir / 'python' / 'cmkit'}")
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[-1], target)

    def configure(self, build_dir):
        build_dir.mkdir(parents=True, exist_ok=True)
        args = [
            "cmake", "-S", str(ROOT), "-B", str(build_dir),
            "-DCMAKE_BUILD_TYPE=Release",
            "-DCMKIT_PYTHON=ON",
            f"-DPython3_EXECUTABLE={sys.executable}",
            "-DCMKIT_BUILD_TESTS=OFF", "-DCMKIT_BUILD_BENCH=OFF", "-DCMKIT_BUILD_CLI=OFF",
            "-DCMKIT_BUILD_FUZZ=OFF", "-DCMKIT_BUILD_EXAMPLES=OFF",
        ]
        if shutil.which("ninja"):
            args += ["-G", "Ninja"]
        args += shlex.split(os.environ.get("CMKIT_CMAKE_ARGS", ""))
        self.spawn(args)


setup(
    version=project_version(),
    packages=["cmkit"],
    package_dir={"cmkit": "python/cmkit"},
    package_data={"cmkit": ["__init__.pyi", "py.typed"]},
    ext_modules=[CMakeExtension("cmkit._cmkit")],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
)

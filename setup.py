"""Builds the compiled module pushpred._core with CMake, for the interpreter that runs this file.

`pip install --no-build-isolation .` (Debian's python3-setuptools, python3-wheel and the packages of
scripts/install-deps.sh; no network) configures the project with -DPython3_EXECUTABLE set to that interpreter and
without the tests, benchmarks and examples, builds it, installs it into a staging folder and takes from there the
module and libpushpred, which goes beside the module (the module's RUNPATH starts with $ORIGIN). The package's
Python files come from python/pushpred.

Environment: CMAKE_ARGS, extra configure arguments (e.g. -DCMAKE_CXX_COMPILER_LAUNCHER=ccache);
CMAKE_BUILD_PARALLEL_LEVEL, build jobs (default: every core); PUSHPRED_CMAKE_BUILD_DIR, an existing CMake build
folder to take the module from instead of configuring a new one (it must be built for this interpreter).
"""
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


def project_version():
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(pushpred VERSION ([0-9.]+)", text).group(1)


def cached_python(build):
    """The interpreter a configured CMake build folder builds the module for."""
    cache = Path(build) / "CMakeCache.txt"
    if not cache.is_file():
        sys.exit(f"pushpred: {build} is not a CMake build folder (no CMakeCache.txt)")
    match = re.search(r"^Python3_EXECUTABLE:FILEPATH=(.*)$", cache.read_text(), re.M)
    return match.group(1) if match else ""


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = os.environ.get("PUSHPRED_CMAKE_BUILD_DIR")
        if build:
            build = Path(build).resolve()
            built_for = cached_python(build)
            if os.path.realpath(built_for) != os.path.realpath(sys.executable):
                sys.exit(f"pushpred: {build} builds the module for {built_for or 'no Python'}, not for "
                         f"{sys.executable}; unset PUSHPRED_CMAKE_BUILD_DIR to build for this one")
        else:
            build = Path(self.build_temp).resolve() / "cmake"
            configure = ["cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                         f"-DPython3_EXECUTABLE={sys.executable}", "-DPUSHPRED_BUILD_PYTHON=ON",
                         "-DPUSHPRED_BUILD_TESTS=OFF", "-DPUSHPRED_BUILD_BENCHMARKS=OFF",
                         "-DPUSHPRED_BUILD_EXAMPLES=OFF", *shlex.split(os.environ.get("CMAKE_ARGS", ""))]
            subprocess.run(configure, check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        # What `cmake --install` installs: the library, the program and the module (not the tests of a reused build).
        subprocess.run(["cmake", "--build", str(build), "-j", jobs, "--target", "pushpred_python", "pushpred"],
                       check=True)
        with tempfile.TemporaryDirectory() as staging:
            subprocess.run(["cmake", "--install", str(build), "--prefix", staging], check=True,
                           stdout=subprocess.DEVNULL)
            modules = sorted(Path(staging).glob("**/pushpred/_core*.so"))
            if not modules:
                sys.exit(f"pushpred: the build in {build} made no Python module (is pybind11-dev installed? "
                         "bash scripts/install-deps.sh)")
            package = modules[0].parent
            library = sorted(Path(staging).glob("**/libpushpred.so.*[0-9]"))
            target = Path(self.get_ext_fullpath(ext.name))
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(modules[0], target)
            shutil.copyfile(package / "_build.py", target.parent / "_build.py")
            # The library under its SONAME (libpushpred.so.0), which the module's DT_NEEDED names.
            soname = min(library, key=lambda p: len(p.name))
            shutil.copyfile(soname.resolve(), target.parent / soname.name)


setup(version=project_version(), ext_modules=[Extension("pushpred._core", sources=[])],
      cmdclass={"build_ext": CMakeBuild})

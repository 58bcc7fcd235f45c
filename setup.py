"""pip install --no-build-isolation . : builds the _madsfm extension with CMake (target _madsfm only: the two static
libraries and the bindings, no tests or benchmarks) and installs it with the pure-Python package python/madsfm.

Environment:
  MADSFM_CMAKE_BUILD_DIR  an existing madsfm build tree to build _madsfm in (e.g. build/, where it usually is up to
                          date already: nothing is recompiled); default build/pip, configured on first use.
The extension is built for the interpreter that runs pip (-DPython3_EXECUTABLE).
"""

import glob
import os
import re
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = os.path.dirname(os.path.abspath(__file__))


def version():
    with open(os.path.join(ROOT, "CMakeLists.txt")) as f:
        m = re.search(r"project\(madsfm VERSION (\S+)", f.read())
    if not m:
        sys.exit("setup.py: no 'project(madsfm VERSION ...)' in CMakeLists.txt")
    return m.group(1)


def cmake_build_dir():
    return os.path.abspath(os.environ.get("MADSFM_CMAKE_BUILD_DIR") or os.path.join(ROOT, "build", "pip"))


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build_dir = cmake_build_dir()
        if not os.path.exists(os.path.join(build_dir, "CMakeCache.txt")):
            subprocess.check_call(["cmake", "-S", ROOT, "-B", build_dir, "-DCMAKE_BUILD_TYPE=Release",
                                   "-DMADSFM_BUILD_TESTS=OFF", "-DMADSFM_BUILD_BENCHMARKS=OFF",
                                   f"-DPython3_EXECUTABLE={sys.executable}"])
        cache = open(os.path.join(build_dir, "CMakeCache.txt")).read()
        m = re.search(r"^Python3_EXECUTABLE:\w+=(.*)$", cache, flags=re.M)
        if m and os.path.realpath(m.group(1)) != os.path.realpath(sys.executable):
            sys.exit(f"setup.py: {build_dir} builds the module for {m.group(1)}, not for {sys.executable} "
                     "(set MADSFM_CMAKE_BUILD_DIR to another directory)")
        subprocess.check_call(["cmake", "--build", build_dir, "--target", "_madsfm", "-j", str(os.cpu_count() or 1)])
        built = glob.glob(os.path.join(build_dir, "python", "madsfm", "_madsfm*.so"))
        if len(built) != 1:
            sys.exit(f"setup.py: expected one _madsfm*.so in {build_dir}/python/madsfm, found {built} "
                     "(pybind11-dev or python3-dev missing? see the CMake output)")
        dest = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(dest), exist_ok=True)
        shutil.copyfile(built[0], dest)


# setuptools' own scratch files next to the CMake build, not in the source tree.
scratch = os.path.join(cmake_build_dir(), "setuptools")
os.makedirs(scratch, exist_ok=True)
setup(
    name="madsfm",
    version=version(),
    description="Relative pose with affine-corrected monocular depth priors (madsfm's C++ estimator)",
    license="BSD-3-Clause",
    python_requires=">=3.8",
    install_requires=["numpy"],
    packages=["madsfm"],
    package_dir={"": "python"},
    ext_modules=[Extension("madsfm._madsfm", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": scratch}, "egg_info": {"egg_base": scratch}},
    zip_safe=False,
)

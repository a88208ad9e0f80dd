"""pip install . for the rockwatch Python module: the extension is built by CMake (target rockwatch_python), never
by setuptools' compiler, so the wheel holds the same code as the command line and the Debian package.

ROCKWATCH_CMAKE_BUILD_DIR: a configured build tree to build the target in (e.g. build/release); by default build/pip
is configured (Release, no tests, no benchmarks) with this interpreter.
"""
import os
import re
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


def project_version():
    text = (ROOT / "CMakeLists.txt").read_text()
    m = re.search(r"project\(rockwatch VERSION ([0-9.]+)", text)
    if not m:
        raise RuntimeError("setup.py: no `project(rockwatch VERSION x.y.z` in CMakeLists.txt")
    return m.group(1)


def build_dir():
    given = os.environ.get("ROCKWATCH_CMAKE_BUILD_DIR")
    return Path(given).resolve() if given else ROOT / "build" / "pip"


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        tree = build_dir()
        if not (tree / "CMakeCache.txt").exists():
            if os.environ.get("ROCKWATCH_CMAKE_BUILD_DIR"):
                raise RuntimeError(f"setup.py: ROCKWATCH_CMAKE_BUILD_DIR={tree} is not a configured CMake build tree "
                                   "(no CMakeCache.txt)")
            generator = ["-G", "Ninja"] if shutil.which("ninja") else []
            subprocess.check_call(["cmake", "-S", str(ROOT), "-B", str(tree), *generator,
                                   "-DCMAKE_BUILD_TYPE=Release", "-DROCKWATCH_BUILD_TESTS=OFF",
                                   "-DROCKWATCH_BUILD_BENCH=OFF", f"-DPython3_EXECUTABLE={sys.executable}"])
        subprocess.check_call(["cmake", "--build", str(tree), "--target", "rockwatch_python"])
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        built = tree / "python" / f"rockwatch{suffix}"
        if not built.exists():
            found = sorted(p.name for p in (tree / "python").glob("rockwatch*.so"))
            raise RuntimeError(f"setup.py: {built} was not built for this interpreter ({sys.executable}, {suffix}); "
                               f"the tree has {found or 'no module'}: the module is built for the interpreter CMake "
                               "found (host_tools/python/CMakeLists.txt), or python3-dev/pybind11-dev are missing")
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)


# setuptools' own build and egg-info files go into the CMake tree, not into the sources.
_work = build_dir() / "setuptools"
(_work / "egg-info").mkdir(parents=True, exist_ok=True)

setup(
    name="rockwatch",
    version=project_version(),
    description="Real-time rocking monitor for unreinforced masonry walls: the engine for Python",
    packages=["rockwatch"],
    package_dir={"": "python"},
    ext_modules=[Extension("rockwatch.rockwatch", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    install_requires=["numpy"],
    python_requires=">=3.9",
    options={"build": {"build_base": str(_work / "build")}, "egg_info": {"egg_base": str(_work / "egg-info")}},
    zip_safe=False,
)

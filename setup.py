"""pip route to the polydem Python package, for Debian's pip and setuptools without network:

    pip install --no-build-isolation --break-system-packages .      # into /usr/local
    pip install --no-build-isolation --prefix /opt/polydem .          # elsewhere

Build isolation must be off: it would fetch setuptools from PyPI. The package is built by CMake
(the same build as `cmake --build build --target polydem_python`, in build/pip/) and this file
only copies what CMake made into the wheel: the extension, linked against polydem's static
libraries, and the pure-Python files of python_coupling/polydem/. `cmake --install` (docs/python.md,
"Install") is the other route and needs no pip.
"""
import os
import re
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = os.path.dirname(os.path.abspath(__file__))


def version():
    """The project version of CMakeLists.txt, which the extension reports too."""
    with open(os.path.join(ROOT, "CMakeLists.txt"), encoding="utf-8") as f:
        return re.search(r"project\(\s*polydem\s+VERSION\s+([0-9.]+)", f.read()).group(1)


class CMakeBuild(build_ext):
    """Builds the extension with CMake for the interpreter running pip, then copies it."""

    def build_extension(self, ext):
        build = os.path.join(ROOT, "build", "pip")
        configure = ["cmake", "-S", ROOT, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
                     "-DPython3_EXECUTABLE=" + sys.executable, "-DPOLYDEM_BUILD_TESTS=OFF",
                     "-DPOLYDEM_BUILD_BENCHMARKS=OFF"]
        if shutil.which("ccache"):
            configure.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
        subprocess.check_call(configure)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 2))
        subprocess.check_call(["cmake", "--build", build, "--target", "polydem_python", "-j", jobs])
        built = os.path.join(build, "python", "polydem")
        target = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        extensions = [n for n in os.listdir(built)
                      if n.startswith("_polydem.") and n.endswith(".so")]
        if len(extensions) != 1:
            raise RuntimeError("CMake built %d extensions in %s, expected one" % (len(extensions),
                                                                                 built))
        shutil.copy2(os.path.join(built, extensions[0]), target)
        # plots.py imports python_coupling/plots/plot_series.py under this name (CMake copies it).
        shutil.copy2(os.path.join(built, "_plot_series.py"),
                     os.path.join(os.path.dirname(target), "_plot_series.py"))


os.makedirs(os.path.join(ROOT, "build"), exist_ok=True)  # setuptools' files go there
setup(
    name="polydem",
    version=version(),
    description="Polyhedral discrete element method for rock-slope failure and runout",
    packages=["polydem"],
    package_dir={"polydem": "python_coupling/polydem"},
    ext_modules=[Extension("polydem._polydem", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    python_requires=">=3.9",
    options={"build": {"build_base": "build/setuptools"}, "egg_info": {"egg_base": "build"}},
    zip_safe=False,
)

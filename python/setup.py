"""pip install ./python: the softbond package built against an installed softbond.

The C extension is compiled from src/*.c with setuptools against the headers and
libraries that `cmake --install` put in a prefix, found through pkg-config
(softbond_scene.pc; set PKG_CONFIG_PATH=PREFIX/lib/pkgconfig for a prefix other
than /usr or /usr/local), with an RPATH to that library directory. Offline, let
pip use the installed setuptools: pip install --no-build-isolation ./python
"""

import glob
import os
import subprocess

import numpy
from setuptools import Extension, setup

HERE = os.path.dirname(os.path.abspath(__file__))


def pkg_config(*args):
    try:
        return subprocess.check_output(["pkg-config", *args, "softbond_scene"], text=True).split()
    except (OSError, subprocess.CalledProcessError) as error:
        raise SystemExit(
            "softbond's Python package needs the library installed (cmake --install build) and its "
            f"pkg-config file softbond_scene.pc on PKG_CONFIG_PATH: {error}"
        )


libdir = pkg_config("--variable=libdir")[0]
core = Extension(
    "softbond._core",
    sources=sorted(glob.glob(os.path.join("src", "*.c"))),
    include_dirs=[numpy.get_include()] + [flag[2:] for flag in pkg_config("--cflags") if flag.startswith("-I")],
    library_dirs=[libdir],
    libraries=["softbond_scene", "softbond_io", "softbond"],
    runtime_library_dirs=[libdir],
    extra_compile_args=["-std=c11", "-Wall", "-Wextra"],
)

setup(
    name="softbond",
    version=pkg_config("--modversion")[0],
    description="Real-time soft-body simulation: Python interface to the softbond C library",
    license="MIT",
    packages=["softbond"],
    package_data={"softbond": ["*.pyi", "py.typed"]},
    ext_modules=[core],
    python_requires=">=3.9",
    install_requires=["numpy"],
)

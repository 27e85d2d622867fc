"""Build of the Python module gigatet: one C extension, gigatet._gigatet, that compiles the
binding (python/gigatet/_gigatet.c and _gigatet_arrays.c) together with the C library's own
sources (every .c of src/ and its sub-folders except the command line tool's src/cli/), with
the library's floating-point flags.  Metadata is in pyproject.toml.

    /usr/bin/python3 -m venv --system-site-packages V
    V/bin/pip install --no-build-isolation --no-index .

Environment:
    GTET_PY_BUILD_DIR  setuptools' build directory (default build-py/setuptools: never the
                       CMake trees build*/ of ./dev)
    GTET_PY_JOBS       parallel compiler processes (default: the number of cores)
    GTET_PY_WERROR=1   warnings are errors (the ctest build)
"""
import glob
import os
import platform
import re
import shlex
import sys
import sysconfig
from concurrent.futures import ThreadPoolExecutor

import numpy
from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = os.path.dirname(os.path.abspath(__file__))
BUILD_DIR = os.environ.get("GTET_PY_BUILD_DIR", os.path.join("build-py", "setuptools"))


def library_sources():
    """The library's sources as CMakeLists.txt globs them (GTET_LIB_SOURCES: the layout is
    moving), plus the file formats of src/io/.  Without a readable list: every src/*.c and
    src/<folder>/*.c except the CLI's and optional layers' folders."""
    found = []
    try:
        with open(os.path.join(HERE, "CMakeLists.txt"), encoding="utf-8") as f:
            m = re.search(r"file\(GLOB\s+GTET_LIB_SOURCES\s+(?:CONFIGURE_DEPENDS\s+)?([^)]*)\)",
                          f.read())
        for pattern in (m.group(1).split() if m else []):
            if pattern.startswith("src/") and pattern.endswith(".c"):
                found += glob.glob(pattern)
    except OSError:
        pass
    if found:
        found += glob.glob(os.path.join("src", "io", "*.c"))
    else:
        found = glob.glob(os.path.join("src", "*.c")) + \
            [p for p in glob.glob(os.path.join("src", "*", "*.c"))
             if p.split(os.sep)[1] not in ("cli", "mpi")]
    found = [os.path.normpath(p) for p in found]
    if not AVX2_UNIT:
        found = [p for p in found if p != AVX2_SOURCE]
    return sorted(set(found))


# km_insert compiled a second time with AVX2 (CMakeLists.txt GTET_AVX2_TU): on x86-64 this
# one source gets -mavx2 and the library the macro that makes it call it
AVX2_SOURCE = os.path.join("src", "kernel", "insert_avx2.c")
AVX2_UNIT = platform.machine().lower() in ("x86_64", "amd64")


def include_dirs():
    dirs = []
    if os.path.isdir(os.path.join(HERE, "include")):  # the public header, once it moves
        dirs.append("include")
    dirs += ["src", numpy.get_include()]
    return dirs


def library_macros():
    """GTET_HAVE_CANCEL when the public header has gtet_options.cancel (KeyboardInterrupt)."""
    for d in ("include", "src"):
        h = os.path.join(HERE, d, "gigatet.h")
        if os.path.exists(h):
            with open(h, encoding="utf-8") as f:
                return [("GTET_HAVE_CANCEL", "1")] if "cancel_user" in f.read() else []
    return []


FP_FLAGS = ["-ffp-contract=off", "-fno-fast-math", "-fno-unsafe-math-optimizations",
            "-frounding-math"]
WARN_FLAGS = ["-Wall", "-Wextra", "-Wshadow", "-Wstrict-prototypes", "-Wmissing-prototypes",
              "-Wpointer-arith", "-Wvla", "-Wundef"]
FORBIDDEN = ("-ffast-math", "-Ofast", "-ffp-contract=fast", "-funsafe-math-optimizations")


class BuildExt(build_ext):
    """Adds the compiler-specific floating-point flags, refuses fast-math, compiles the
    sources in parallel."""

    def build_extensions(self):
        cc = self.compiler.compiler_so
        name = os.path.basename(cc[0])
        words = list(cc) + shlex.split(os.environ.get("CFLAGS", "")) + \
            shlex.split(sysconfig.get_config_var("CFLAGS") or "")
        bad = [w for w in words if w in FORBIDDEN]
        if bad:
            sys.exit("gigatet must not be built with %s (its exact predicates assume IEEE "
                     "arithmetic without contraction)" % " ".join(bad))
        extra = list(FP_FLAGS)
        if "clang" not in name:  # gcc: no excess precision on any target
            extra.append("-fexcess-precision=standard")
        if os.environ.get("GTET_PY_WERROR") == "1":
            extra.append("-Werror")
        for ext in self.extensions:
            ext.extra_compile_args = ext.extra_compile_args + extra
        self.compiler.compile = parallel_compile(self.compiler)
        super().build_extensions()


def parallel_compile(compiler):
    """compiler.compile with one process per core (setuptools compiles one file at a time);
    AVX2_SOURCE with -mavx2 added."""
    serial = compiler.compile
    needed = ("_setup_compile", "_get_cc_args", "_compile")
    if not all(hasattr(compiler, a) for a in needed):
        def serial_avx2(sources, *args, extra_postargs=None, **kw):
            rest = [p for p in sources if os.path.normpath(p) != AVX2_SOURCE]
            objects = serial(rest, *args, extra_postargs=extra_postargs, **kw)
            if len(rest) < len(sources):
                objects += serial([AVX2_SOURCE], *args,
                                  extra_postargs=list(extra_postargs or []) + ["-mavx2"], **kw)
            return objects
        return serial_avx2
    jobs = int(os.environ.get("GTET_PY_JOBS", "0") or 0) or (os.cpu_count() or 1)

    def compile_all(sources, output_dir=None, macros=None, include_dirs=None, debug=0,
                    extra_preargs=None, extra_postargs=None, depends=None):
        macros, objects, extra_postargs, pp_opts, build = compiler._setup_compile(
            output_dir, macros, include_dirs, sources, depends, extra_postargs)
        cc_args = compiler._get_cc_args(pp_opts, debug, extra_preargs)

        def one(obj):
            src, ext = build[obj]
            post = extra_postargs
            if os.path.normpath(src) == AVX2_SOURCE:
                post = list(extra_postargs or []) + ["-mavx2"]
            compiler._compile(obj, src, ext, cc_args, post, pp_opts)

        with ThreadPoolExecutor(max_workers=jobs) as pool:
            list(pool.map(one, objects))
        return objects

    return compile_all


os.makedirs(BUILD_DIR, exist_ok=True)

ext = Extension(
    "gigatet._gigatet",
    sources=[os.path.join("python", "gigatet", f) for f in ("_gigatet.c", "_gigatet_arrays.c")]
    + library_sources(),
    depends=sorted(glob.glob(os.path.join("src", "**", "*.h"), recursive=True))
    + [os.path.join("python", "gigatet", "_gigatet.h")],
    include_dirs=include_dirs(),
    define_macros=[("NPY_NO_DEPRECATED_API", "NPY_1_7_API_VERSION")] + library_macros() +
    ([("GTET_AVX2_TU", "1")] if AVX2_UNIT and AVX2_SOURCE in library_sources() else []),
    # -O3 as CMake's Release build; -fno-wrapv undoes Python's -fwrapv (the kernel's loops
    # are written for C's rules); the library's warnings
    extra_compile_args=["-std=c17", "-O3", "-fno-wrapv", "-fopenmp"] + WARN_FLAGS,
    extra_link_args=["-fopenmp"],
    libraries=["gmp", "z", "m"],
)

setup(
    package_dir={"": "python"},
    packages=["gigatet"],
    include_package_data=False,
    exclude_package_data={"gigatet": ["*.c", "*.h"]},
    ext_modules=[ext],
    cmdclass={"build_ext": BuildExt},
    # build products and the egg-info stay out of the source tree
    options={"build": {"build_base": BUILD_DIR}, "egg_info": {"egg_base": BUILD_DIR}},
)

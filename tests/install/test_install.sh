#!/usr/bin/env bash
# test_install.sh -- the ctest install_consumers (tests/install.cmake): `cmake --install` the
# build into a temporary prefix, check what landed there, then build and run
# tests/install/consumer.c against the installed library
#   1. through pkg-config (PKG_CONFIG_PATH=<prefix>/<libdir>/pkgconfig), shared library;
#   2. through find_package(gigatet) (tests/install/CMakeLists.txt, CMAKE_PREFIX_PATH=<prefix>):
#      gigatet::gigatet (shared) and gigatet::gigatet_static;
# and check that the shared library exports exactly the GTET_API functions of gigatet.h
# (`nm -D --defined-only`: nothing outside gtet_), with a versioned SONAME.
# Usage: test_install.sh BUILD_DIR CC CMAKE MPI(0|1) [EXTRA_CFLAGS]
set -euo pipefail
build=$1 cc=$2 cmake=$3 mpi=$4 extra=${5:-}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
work=$build/install-test
rm -rf "$work"; mkdir -p "$work"
prefix=$work/prefix
fail() { echo "install_consumers: FAIL: $*" >&2; exit 1; }

echo "== cmake --install $build --prefix $prefix"
"$cmake" --install "$build" --prefix "$prefix" >"$work/install.log" || { cat "$work/install.log"; fail "cmake --install"; }

# ---- what is installed
lib=$(find "$prefix" -name 'libgigatet.so.*.*.*' -type f | head -n 1)
[ -n "$lib" ] || fail "no libgigatet.so.MAJOR.MINOR.PATCH under $prefix"
libdir=$(dirname "$lib")
for f in "$prefix/include/gigatet.h" "$libdir/libgigatet.a" "$libdir/libgigatet.so" \
         "$prefix/bin/gigatet" "$libdir/pkgconfig/gigatet.pc" \
         "$libdir/cmake/gigatet/gigatetConfig.cmake" "$libdir/cmake/gigatet/gigatetConfigVersion.cmake" \
         "$prefix/share/man/man1/gigatet.1"; do
  [ -e "$f" ] || fail "not installed: ${f#$prefix/}"
done
if [ "$mpi" = 1 ]; then
  for f in "$prefix/include/gigatet_mpi.h" "$prefix/bin/gigatet-mpi" "$libdir/libgigatet_mpi.a"; do
    [ -e "$f" ] || fail "not installed (GTET_MPI): ${f#$prefix/}"
  done
fi
for f in $(cd "$prefix/include" && ls); do
  case $f in gigatet.h|gigatet_mpi.h) ;; *) fail "a header that is not public was installed: include/$f" ;; esac
done
soname=$(readelf -d "$lib" | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')
[[ $soname =~ ^libgigatet\.so\.[0-9]+$ ]] || fail "SONAME is '$soname', not libgigatet.so.MAJOR"
[ -e "$libdir/$soname" ] || fail "no $soname link next to the library"
echo "installed: ${libdir#$prefix/}, SONAME $soname"
"$prefix/bin/gigatet" --version >/dev/null || fail "the installed CLI does not run"
if command -v groff >/dev/null; then
  warn=$(groff -man -ww -z "$prefix/share/man/man1/gigatet.1" 2>&1) || true
  [ -z "$warn" ] || fail "groff warns on gigatet.1: $warn"
fi

# ---- exported symbols: exactly the GTET_API functions of the public header
nm -D --defined-only "$lib" | awk '{print $NF}' | sort -u >"$work/exported"
grep -vE '^(gtet_.*|_init|_fini|_edata|_end|__bss_start)$' "$work/exported" >"$work/foreign" || true
[ ! -s "$work/foreign" ] || fail "libgigatet.so exports symbols outside gtet_: $(tr '\n' ' ' <"$work/foreign")"
tr '\n' ' ' <"$prefix/include/gigatet.h" | grep -oE 'GTET_API [^;(]*\bgtet_[a-z0-9_]+\(' |
  grep -oE 'gtet_[a-z0-9_]+\($' | tr -d '(' | sort -u >"$work/declared"
grep '^gtet_' "$work/exported" >"$work/exported_gtet" || true
diff "$work/declared" "$work/exported_gtet" >"$work/symdiff" ||
  fail "exported gtet_ symbols differ from the GTET_API declarations (< declared, > exported): $(cat "$work/symdiff")"
echo "exports: $(wc -l <"$work/exported_gtet") gtet_ functions, nothing else"

# ---- consumer 1: pkg-config, shared library
echo "== pkg-config consumer"
export PKG_CONFIG_PATH=$libdir/pkgconfig
ver=$(pkg-config --modversion gigatet) || fail "pkg-config does not find gigatet"
cflags=$(pkg-config --cflags gigatet) libs=$(pkg-config --libs gigatet)
pkg-config --static --libs gigatet >/dev/null || fail "pkg-config --static --libs gigatet"
echo "pkg-config: gigatet $ver, cflags '$cflags', libs '$libs'"
# shellcheck disable=SC2086
"$cc" -std=c17 -Wall -Wextra -Werror $extra $cflags "$here/consumer.c" -o "$work/consumer_pc" $libs ||
  fail "building the consumer through pkg-config"
LD_LIBRARY_PATH=$libdir "$work/consumer_pc" || fail "the pkg-config consumer failed"
deps=$(LD_LIBRARY_PATH=$libdir ldd "$work/consumer_pc")   # (no pipe into grep -q: pipefail)
grep -qF "$libdir/$soname" <<<"$deps" ||
  fail "the pkg-config consumer did not load the installed $soname"

# ---- consumer 2: find_package(gigatet)
echo "== find_package consumer"
"$cmake" -S "$here" -B "$work/consumer_cmake" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_C_COMPILER="$cc" \
  -DCMAKE_C_FLAGS="-Wall -Wextra -Werror $extra" -DCMAKE_BUILD_TYPE=Release \
  >"$work/consumer_cmake.log" 2>&1 || { cat "$work/consumer_cmake.log"; fail "configuring the find_package consumer"; }
"$cmake" --build "$work/consumer_cmake" >>"$work/consumer_cmake.log" 2>&1 ||
  { cat "$work/consumer_cmake.log"; fail "building the find_package consumer"; }
"$work/consumer_cmake/consumer_shared" || fail "the find_package consumer (gigatet::gigatet) failed"
deps=$(ldd "$work/consumer_cmake/consumer_shared")
grep -qF "$libdir/$soname" <<<"$deps" ||
  fail "the find_package consumer did not load the installed $soname (RPATH)"
"$work/consumer_cmake/consumer_static" || fail "the find_package consumer (gigatet::gigatet_static) failed"
deps=$(ldd "$work/consumer_cmake/consumer_static")
if grep -q libgigatet <<<"$deps"; then
  fail "the gigatet::gigatet_static consumer loads libgigatet.so"
fi
echo "install_consumers: ok"

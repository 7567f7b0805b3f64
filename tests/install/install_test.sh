#!/bin/sh
# Installs a build into a temporary prefix, then builds programs against that copy alone (never
# the build tree) and runs them:
#   - the installed runtime library: its needed libraries, soname and exports; the encode
#     library's exports;
#   - the CMake package: a consumer of each component, each looked for alone
#     (tests/install/CMakeLists.txt: runtime, runtime_static through COMPONENTS runtime,
#     preprocess, and gl when it was built);
#   - pkg-config: every installed .pc file resolves; a C loader links libpyramid-runtime, a C++
#     program the static libraries (--static);
#   - the samples (samples/README.md), each built the way its README says and run on data;
#   - the docs: README.md's links to doc/ hold where installed.
# Usage: install_test.sh BUILD_DIR DATA_DIR [C_COMPILER [CXX_COMPILER]]
set -eu
build=$1
data=$2
cc=${3:-cc}
cxx=${4:-c++}
here=$(cd "$(dirname "$0")" && pwd)
samples=$(cd "$here/../../samples" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
prefix=$tmp/prefix

cmake --install "$build" --prefix "$prefix" >/dev/null

# ---- The docs: README.md beside doc/, as in the sources, so that their relative links hold. ----
docs=$(find "$prefix" -path '*/share/doc/libpyramid/README.md' | head -n 1)
test -n "$docs" || { echo "no installed README.md" >&2; exit 1; }
docdir=$(dirname "$docs")
for link in $(grep -o '](doc/[^)#]*' "$docs" | sed 's/^](//' | sort -u); do
  test -e "$docdir/$link" || { echo "installed README.md links to $link, which is not installed" >&2; exit 1; }
done
test -e "$docdir/doc/c-api.md" || { echo "no installed doc/c-api.md" >&2; exit 1; }

# ---- The runtime library: libtiff, libdeflate and zlib only; the C API only. ----
lib=$(find "$prefix" -name 'libpyramid-runtime.so.*.*.*' | head -n 1)
test -n "$lib" || { echo "no installed libpyramid-runtime.so" >&2; exit 1; }
needed=$(readelf -d "$lib" | grep NEEDED)
echo "$needed"
if echo "$needed" | grep -E 'gomp|EGL|libGL|libOpenGL|png|Geographic|squish|stb|OpenImageIO'; then
  echo "the installed runtime library needs a library it must not" >&2
  exit 1
fi
readelf -d "$lib" | grep -q 'SONAME.*libpyramid-runtime\.so\.' || { echo "no soname" >&2; exit 1; }
others=$(nm -D --defined-only "$lib" | awk '{print $3}' | grep -v '^pyramid_' || true)
if [ -n "$others" ]; then
  echo "exports other than the C API:" >&2
  echo "$others" | head >&2
  exit 1
fi
# ---- The encode library, for FFIs (python/): pyramid_encode.h's functions and their errors only. ----
enc=$(find "$prefix" -name 'libpyramid-encode.so.*.*.*' | head -n 1)
test -n "$enc" || { echo "no installed libpyramid-encode.so" >&2; exit 1; }
readelf -d "$enc" | grep -q 'SONAME.*libpyramid-encode\.so\.' || { echo "libpyramid-encode.so: no soname" >&2; exit 1; }
exports=$(nm -D --defined-only "$enc" | awk '{print $3}' | LC_ALL=C sort | tr '\n' ' ')
expected="pyramid_dem_encode_defaults pyramid_encode_dem pyramid_encode_ortho pyramid_last_error \
pyramid_ortho_encode_defaults pyramid_status_name pyramid_version_number pyramid_version_string "
test "$exports" = "$expected" || { echo "libpyramid-encode.so exports: $exports" >&2; exit 1; }
# ---- Man pages: one per program, made from its --help and --version (when help2man is there). ----
if command -v help2man >/dev/null 2>&1; then
  programs=0
  for exe in "$prefix"/bin/*; do
    [ -f "$exe" ] && [ -x "$exe" ] || continue
    prog=$(basename "$exe")
    programs=$((programs + 1))
    page=$prefix/share/man/man1/$prog.1
    test -s "$page" || { echo "no man page $page" >&2; exit 1; }
    grep -q '^\.SH DESCRIPTION' "$page" && grep -q '\\-\\-help' "$page" ||
      { echo "$page does not hold the program's --help" >&2; exit 1; }
  done
  [ "$programs" -ge 7 ] || { echo "only $programs programs installed in $prefix/bin" >&2; exit 1; }
fi

# ---- Under mpirun, an installed program finds its MPI module in lib/libpyramid/ (when built with MPI). ----
if [ -n "$(find "$prefix" -name libpyramid_mpi.so)" ] && command -v mpirun >/dev/null 2>&1; then
  "$prefix/bin/preprocessDem" -q "$samples/dem.tif" -o "$tmp/mpi-one/DEM.dat"
  # The dynamic loader says which file each rank loaded: the installed one, not the build's.
  LD_DEBUG=files OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun -n 2 --oversubscribe \
    "$prefix/bin/preprocessDem" -q "$samples/dem.tif" -o "$tmp/mpi-two/DEM.dat" 2>"$tmp/mpi-loads.txt"
  cmp "$tmp/mpi-one/DEM.dat" "$tmp/mpi-two/DEM.dat" || { echo "two ranks of the installed preprocessDem differ from one" >&2; exit 1; }
  loaded=$(grep -c "file=$prefix/lib[^ ]*/libpyramid/libpyramid_mpi.so .*dynamically loaded" "$tmp/mpi-loads.txt" || true)
  [ "$loaded" = 2 ] || { echo "the installed ranks did not load the installed MPI module ($loaded of 2)" >&2; exit 1; }
fi

with_gl=OFF
if [ -n "$(find "$prefix" -name libpyramid-gl.a)" ]; then
  with_gl=ON
fi

# ---- CMake package: find_package(libpyramid 0.2 REQUIRED COMPONENTS ...) per component. ----
cmake -S "$here" -B "$tmp/cmake" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_C_COMPILER="$cc" -DCMAKE_CXX_COMPILER="$cxx" \
  -DLIBPYRAMID_CONSUMER_GL=$with_gl >/dev/null
cmake --build "$tmp/cmake" >/dev/null
"$tmp/cmake/runtime/consumer" "$data"
"$tmp/cmake/runtime_static/runtime_static_consumer" "$data"
mkdir "$tmp/encoded"
"$tmp/cmake/preprocess/preprocess_consumer" "$samples" "$tmp/encoded"
if [ $with_gl = ON ]; then
  "$tmp/cmake/gl/gl_consumer"
fi

# ---- pkg-config ----
pcdir=$(dirname "$(find "$prefix" -name libpyramid-runtime.pc | head -n 1)")
packages="libpyramid-runtime libpyramid-preprocess"
static_packages=libpyramid-preprocess
if [ $with_gl = ON ]; then
  packages="$packages libpyramid-gl"
  static_packages="$static_packages libpyramid-gl"
fi
# shellcheck disable=SC2086 # the lists are words
PKG_CONFIG_PATH=$pcdir pkg-config --exists --print-errors $packages
flags=$(PKG_CONFIG_PATH=$pcdir pkg-config --cflags --libs libpyramid-runtime)
libdir=$(PKG_CONFIG_PATH=$pcdir pkg-config --variable=libdir libpyramid-runtime)
# shellcheck disable=SC2086 # the flags are words
"$cc" -std=c99 -pedantic-errors -Wall -Wextra -Werror -o "$tmp/consumer-pc" "$here/runtime/consumer.c" $flags \
  -Wl,-rpath,"$libdir"
"$tmp/consumer-pc" "$data"
# shellcheck disable=SC2086
static_flags=$(PKG_CONFIG_PATH=$pcdir pkg-config --static --cflags --libs $static_packages)
# shellcheck disable=SC2086
"$cxx" -std=c++20 -Wall -Wextra -Werror -o "$tmp/consumer-pc-static" "$here/pkgconfig_consumer.cpp" $static_flags
"$tmp/consumer-pc-static" "$samples/dem.tif"

# ---- The samples ----
# sample BUILD NAME EXPECTED [ARGS...]: builds samples/NAME against the installed copy (once) and
# runs it with ARGS; its output must hold the line EXPECTED, and is left in $tmp/samples/NAME.out.
# BUILD is how samples/README.md builds it: make (its Makefile, through pkg-config) or cmake
# (its CMakeLists.txt, through find_package). The program is named as its folder.
sample() {
  kind=$1
  name=$2
  expected=$3
  shift 3
  dir=$tmp/samples/$name
  if [ ! -d "$dir" ]; then
    mkdir -p "$dir"
    case $kind in
      make) (cd "$dir" && PKG_CONFIG_PATH=$pcdir make -s -f "$samples/$name/Makefile" CC="$cc" \
               CFLAGS="-O2 -Wall -Wextra -pedantic-errors -Werror") ;;
      cmake) cmake -S "$samples/$name" -B "$dir" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_C_COMPILER="$cc" \
               -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_COMPILE_WARNING_AS_ERROR=ON >/dev/null &&
             cmake --build "$dir" >/dev/null ;;
      *) echo "sample $name: unknown build '$kind'" >&2; exit 1 ;;
    esac
  fi
  "$dir/$name" "$@" >"$dir.out" || { cat "$dir.out"; echo "sample $name $*: failed" >&2; exit 1; }
  cat "$dir.out"
  grep -Fqx "$expected" "$dir.out" || { echo "sample $name $*: no line '$expected'" >&2; exit 1; }
}

# The loader over the original tools' DEM.dat: every tile with residuals, and the height at the
# centre (pyramid height --grid 384,384 of that file).
sample make loader "tiles produced: 21" -a "$data/proland/DEM.dat"
grep -Fqx "height at (0.5, 0.5): 147.000 (level 2)" "$tmp/samples/loader.out"
# ... and over the pyramid the installed preprocessDem makes of samples/dem.tif, around a point:
# the height there must be what the installed `pyramid height` says.
"$prefix/bin/preprocessDem" -q "$samples/dem.tif" -o "$tmp/dem.dat"
height=$("$prefix/bin/pyramid" height "$tmp/dem.dat" --grid 96,307.2 2>/dev/null)
sample make loader "height at (0.25, 0.8): $(printf %.3f "$height") (level 1)" -p 0.25,0.8 -l 4 "$tmp/dem.dat"
# A file that is not there: a message and a failure.
if "$tmp/samples/loader/loader" "$tmp/none.dat" 2>"$tmp/loader.err"; then
  echo "sample loader: succeeded on a missing file" >&2
  exit 1
fi
grep -q 'loader: pyramid_open: file error: .*none.dat' "$tmp/loader.err"

# A procedural planet through the installed preprocess component's C++ API: six faces encoded
# from a function, then verified against it.
sample cmake procedural "all 6 faces verify within scale / 2" "$tmp/planet" 256

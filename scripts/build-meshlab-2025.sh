#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Builds the parts of MeshLab 2025.07 and PyMeshLab 2025.7 that sodt's plugin
# and its tests need, once per machine, into a cache folder outside the
# checkout keyed by version:
#
#   $SODT_CACHE_DIR/meshlab-2025.07-r<recipe>/
#     src/meshlab/            MeshLab 2025.07 tree (+ src/vcglib): the plugin SDK
#     pymeshlab/pymeshlab/    PyMeshLab 2025.7 (double precision, "2025.07d"),
#                             relocatable: put its parent folder on PYTHONPATH
#     gui/src/distrib/        the MeshLab 2025.07 GUI (float, "2025.07"), used in
#                             place: meshlab, libmeshlab-common.so, plugins/, shaders/
#
# Sources: the tarballs in ../shared/vendor (or $SODT_VENDOR_DIR) when present,
# checked against their SHA-256; otherwise the upstream tags from GitHub
# (cnr-isti-vclab/meshlab MeshLab-2025.07 with its vcglib submodule,
# cnr-isti-vclab/PyMeshLab v2025.7). Nothing is downloaded during the build:
# MeshLab's optional external libraries are switched off.
#
# Usage: scripts/build-meshlab-2025.sh [all|pymeshlab|gui|sources] [--print-dir]
#   SODT_CACHE_DIR  cache root (default: ${XDG_CACHE_HOME:-~/.cache}/sodt)
#   SODT_JOBS       parallel build jobs (default: nproc)
# Idempotent: a part that is already built is not built again.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
ML_VERSION=2025.07
PYML_VERSION=2025.7
# Bump when this recipe changes what lands in the cache.
RECIPE=1
CACHE_ROOT="${SODT_CACHE_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/sodt}"
DEST="$CACHE_ROOT/meshlab-$ML_VERSION-r$RECIPE"
VENDOR="${SODT_VENDOR_DIR:-$ROOT/../shared/vendor}"
JOBS="${SODT_JOBS:-$(nproc)}"

ML_TARBALL=meshlab-2025.07-src.tar.xz
ML_SHA256=6fc70cba30edb9f00b367efaf578f0a93c4565ab4295100843b53c9c4b009f1c
VCG_TARBALL=vcglib-c94ef4e.tar.xz
VCG_SHA256=34db2de741ed6e97948e17c0d0f07470705f96f07b639797b6e1874ca71144c9
PYML_TARBALL=PyMeshLab-2025.7-src.tar.xz
PYML_SHA256=ea744dc5a26df2ec90fc927e96b3d4c94f49676a3e07a269df2c6bd23435d63b
ML_GIT=https://github.com/cnr-isti-vclab/meshlab.git
ML_TAG=MeshLab-2025.07
PYML_GIT=https://github.com/cnr-isti-vclab/PyMeshLab.git
PYML_TAG=v2025.7

# Plugins the tests use: PLY/OFF/OBJ/STL input and output, the smoothers
# (filter_unsharp), isotropic remeshing (filter_meshing), planar edge flips
# (filter_trioptimize), measures (filter_measure), Hausdorff distance
# (filter_sampling) and selections (filter_select).
PYMESHLAB_TARGETS=(pmeshlab io_base filter_unsharp filter_meshing filter_trioptimize
                   filter_measure filter_sampling filter_select)
GUI_TARGETS=(meshlab copy-distrib-files io_base filter_unsharp filter_select)

log() { printf '[meshlab-2025] %s\n' "$*" >&2; }
die() { printf 'build-meshlab-2025.sh: %s\n' "$*" >&2; exit 1; }

what=all
print_dir=0
for arg in "$@"; do
  case "$arg" in
    all | pymeshlab | gui | sources) what="$arg" ;;
    --print-dir) print_dir=1 ;;
    -h | --help) sed -n '2,25p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) die "unknown argument '$arg' (expected all, pymeshlab, gui, sources or --print-dir)" ;;
  esac
done
if [ "$print_dir" = 1 ] && [ "$what" = all ] && [ "$#" = 1 ]; then
  echo "$DEST"
  exit 0
fi

PYTHON=/usr/bin/python3
for tool in cmake ninja "$PYTHON"; do
  command -v "$tool" >/dev/null 2>&1 || die "'$tool' is missing: run scripts/install-deps.sh first"
done
"$PYTHON" -c 'import numpy' 2>/dev/null || die "Debian's python3-numpy is missing: run scripts/install-deps.sh first"
[ -f /usr/lib/cmake/pybind11/pybind11Config.cmake ] || [ -f /usr/share/cmake/pybind11/pybind11Config.cmake ] ||
  die "Debian's pybind11-dev is missing: run scripts/install-deps.sh first"

mkdir -p "$DEST"
exec 9>"$DEST/.lock"
flock 9 || die "cannot lock $DEST/.lock"

check_sha() {  # file expected
  local got
  got="$(sha256sum "$1" | cut -d' ' -f1)"
  [ "$got" = "$2" ] || die "$1: SHA-256 $got, expected $2 (not the release this recipe builds)"
}

# src/meshlab (with src/vcglib) and src/PyMeshLab (its src/meshlab -> ../../meshlab).
get_sources() {
  local src="$DEST/src"
  if [ -f "$src/.done" ]; then return; fi
  rm -rf "$src" && mkdir -p "$src"
  if [ -f "$VENDOR/$ML_TARBALL" ] && [ -f "$VENDOR/$VCG_TARBALL" ] && [ -f "$VENDOR/$PYML_TARBALL" ]; then
    log "unpacking the vendored sources from $VENDOR"
    check_sha "$VENDOR/$ML_TARBALL" "$ML_SHA256"
    check_sha "$VENDOR/$VCG_TARBALL" "$VCG_SHA256"
    check_sha "$VENDOR/$PYML_TARBALL" "$PYML_SHA256"
    tar -xJf "$VENDOR/$ML_TARBALL" -C "$src"
    rmdir "$src/meshlab/src/vcglib" 2>/dev/null || true
    tar -xJf "$VENDOR/$VCG_TARBALL" -C "$src/meshlab/src"
    tar -xJf "$VENDOR/$PYML_TARBALL" -C "$src"
  else
    command -v git >/dev/null 2>&1 || die "no vendored sources in $VENDOR and git is missing"
    log "no vendored sources in $VENDOR: cloning $ML_TAG and $PYML_TAG from GitHub"
    git clone --quiet --depth 1 --branch "$ML_TAG" "$ML_GIT" "$src/meshlab" ||
      die "could not clone $ML_GIT (tag $ML_TAG); without network access put the release tarballs in $VENDOR"
    git -C "$src/meshlab" submodule update --quiet --init --depth 1 src/vcglib ||
      die "could not fetch the vcglib submodule of $ML_TAG"
    git clone --quiet --depth 1 --branch "$PYML_TAG" "$PYML_GIT" "$src/PyMeshLab" ||
      die "could not clone $PYML_GIT (tag $PYML_TAG)"
  fi
  [ -f "$src/meshlab/src/common/plugins/interfaces/filter_plugin.h" ] || die "$src/meshlab is not a MeshLab 2021.05+ tree"
  [ -f "$src/meshlab/src/vcglib/vcg/complex/complex.h" ] || die "$src/meshlab/src/vcglib holds no vcglib"
  [ "$(tr -d '[:space:]' < "$src/meshlab/ML_VERSION")" = "$ML_VERSION" ] || die "$src/meshlab is not MeshLab $ML_VERSION"
  # PyMeshLab's meshlab submodule is exactly the MeshLab tag above.
  rm -rf "$src/PyMeshLab/src/meshlab"
  ln -s ../../meshlab "$src/PyMeshLab/src/meshlab"
  # Debian's pybind11-dev instead of the absent pybind11 submodule.
  sed -i 's/^add_subdirectory(pybind11)$/find_package(pybind11 CONFIG REQUIRED)/' \
    "$src/PyMeshLab/src/pymeshlab/CMakeLists.txt"
  grep -q 'find_package(pybind11 CONFIG REQUIRED)' "$src/PyMeshLab/src/pymeshlab/CMakeLists.txt" ||
    die "could not point PyMeshLab at Debian's pybind11"
  touch "$src/.done"
}

COMMON_CMAKE=(-G Ninja -DCMAKE_BUILD_TYPE=Release
              -DMESHLAB_ALLOW_OPTIONAL_EXTERNAL_LIBRARIES=OFF
              -DMESHLAB_BUILD_MINI=ON
              -DPYTHON_EXECUTABLE="$PYTHON" -DPython_EXECUTABLE="$PYTHON")

build_pymeshlab() {
  local out="$DEST/pymeshlab"
  if [ -f "$out/.done" ]; then log "PyMeshLab $PYML_VERSION already built: $out/pymeshlab"; return; fi
  get_sources
  local b="$DEST/build-pymeshlab"
  log "building PyMeshLab $PYML_VERSION (double precision) in $b: ${PYMESHLAB_TARGETS[*]}"
  # Install RPATHs ($ORIGIN/lib) make the distrib folder relocatable.
  cmake -S "$DEST/src/PyMeshLab" -B "$b" "${COMMON_CMAKE[@]}" -DCMAKE_BUILD_WITH_INSTALL_RPATH=ON > "$DEST/build-pymeshlab.log" 2>&1 ||
    die "configuring PyMeshLab failed; see $DEST/build-pymeshlab.log"
  cmake --build "$b" -j"$JOBS" --target "${PYMESHLAB_TARGETS[@]}" >> "$DEST/build-pymeshlab.log" 2>&1 ||
    die "building PyMeshLab failed; see $DEST/build-pymeshlab.log"
  rm -rf "$out" && mkdir -p "$out"
  cp -a "$b/src/distrib/pymeshlab" "$out/"
  # The module must import with only this folder: check before declaring it built.
  (cd / && PYTHONPATH="$out" "$PYTHON" -c 'import pymeshlab; pymeshlab.MeshSet()') >> "$DEST/build-pymeshlab.log" 2>&1 ||
    die "the built pymeshlab does not import; see $DEST/build-pymeshlab.log"
  touch "$out/.done"
  rm -rf "$b"
  log "PyMeshLab ready: $out/pymeshlab"
}

build_gui() {
  # Built and used in place: the binary finds libmeshlab-common.so by its build RPATH.
  local out="$DEST/gui"
  if [ -f "$out/.done" ]; then log "MeshLab $ML_VERSION GUI already built: $out/src/distrib"; return; fi
  get_sources
  log "building the MeshLab $ML_VERSION GUI (single precision) in $out: ${GUI_TARGETS[*]}"
  cmake -S "$DEST/src/meshlab" -B "$out" "${COMMON_CMAKE[@]}" > "$DEST/build-gui.log" 2>&1 ||
    die "configuring MeshLab failed; see $DEST/build-gui.log"
  cmake --build "$out" -j"$JOBS" --target "${GUI_TARGETS[@]}" >> "$DEST/build-gui.log" 2>&1 ||
    die "building MeshLab failed; see $DEST/build-gui.log"
  [ -x "$out/src/distrib/meshlab" ] && [ -f "$out/src/distrib/libmeshlab-common.so" ] ||
    die "the MeshLab build left no meshlab binary or libmeshlab-common.so in $out/src/distrib"
  touch "$out/.done"
  log "MeshLab GUI ready: $out/src/distrib/meshlab"
}

case "$what" in
  sources) get_sources ;;
  pymeshlab) build_pymeshlab ;;
  gui) build_gui ;;
  all) build_pymeshlab; build_gui ;;
esac
[ "$print_dir" = 1 ] && echo "$DEST"
exit 0

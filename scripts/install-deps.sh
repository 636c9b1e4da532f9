#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Installs every build and test dependency of sodt from Debian 12's archive and
# fetches the MeshLab 2020.09 plugin SDK (src/common + vcglib) from Debian's
# `meshlab` source package into .deps/ (git-ignored). Safe to run repeatedly.
# MeshLab 2025.07 and PyMeshLab 2025.7 are built from these packages by
# scripts/build-meshlab-2025.sh, as the user who runs the tests (not as root).
#   --core  only what the `sodt` command needs (a compiler, CMake, Eigen, CLI11,
#           nlohmann-json) and the SDK, whose vcglib the core is built on: the
#           demo's first step, a few minutes on a fresh machine; run again
#           without it for the plugin, the tests and the benchmarks.
set -euo pipefail

CORE_ONLY=0
case "${1:-}" in
  --core) CORE_ONLY=1 ;;
  "") ;;
  *) echo "usage: install-deps.sh [--core]" >&2; exit 2 ;;
esac

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
DEPS_DIR="${SODT_DEPS_DIR:-$ROOT/.deps}"
SDK_LINK="$DEPS_DIR/meshlab-src"

# The `sodt` command: the core (Eigen, and vcglib from the SDK, which
# `apt-get source` unpacks with dpkg-dev), its command line (header-only
# CLI11) and its JSON reports.
CORE_PACKAGES=(
  cmake make g++ pkg-config libeigen3-dev dpkg-dev xz-utils
  libcli11-dev nlohmann-json3-dev
)
PACKAGES=(
  "${CORE_PACKAGES[@]}"
  meshlab xvfb xauth
  qtbase5-dev libqt5opengl5-dev libglew-dev
  libgtest-dev libbenchmark-dev
  # CGAL 5.5's remeshers, the peers of the local repair in bench/compare
  # (header-only; only the tool sodt_cgal_remesh includes it)
  libcgal-dev
  # the function-length check of the core (tests/scripts/function_length_test.sh)
  universal-ctags
  # fuzzing and sanitizer builds (clang's libFuzzer runtime)
  clang libclang-rt-14-dev
  # GUI smoke tests: drive MeshLab's window, take a screenshot
  xdotool imagemagick
  # MeshLab 2025.07 and PyMeshLab 2025.7 (scripts/build-meshlab-2025.sh), the
  # PyMeshLab tests (pytest with Debian's python3)
  ninja-build libglu1-mesa-dev pybind11-dev python3-dev python3-numpy python3-pytest
  # the noise benchmark (bench/noise) and its test: MeshDenoiser, the figure
  meshsdfilter-tools python3-matplotlib
  # the real-world corpus (bench/corpus/fetch.sh): renders OpenSCAD's bundled
  # examples to STL; the other meshes come from .deb files that fetch.sh
  # downloads with `apt-get download` without installing them
  openscad
  # bench/openmesh_compare.cpp: the default sweep against OpenMesh's
  # tangential Laplacian (built only when OpenMesh is found)
  libopenmesh-dev
)

if [ "$(id -u)" -eq 0 ] || [ "${SODT_APT_SOURCES_ONLY:-0}" = 1 ]; then
  SUDO=()
elif command -v sudo >/dev/null 2>&1; then
  SUDO=(sudo)
else
  echo "install-deps.sh: run as root or install sudo" >&2
  exit 1
fi

log() { printf '[install-deps] %s\n' "$*"; }

# apt-get source needs a deb-src line for bookworm. When none is configured,
# one is added in a file of our own (the system's sources are left alone),
# made from the system's own `deb` entries for bookworm: the same mirrors,
# suites, components and keys, so it works with any mirror. For the tests of
# this script: SODT_APT_DIR points at another tree than /etc/apt, and
# SODT_APT_SOURCES_ONLY=1 stops after this step (no root needed).
APT_DIR="${SODT_APT_DIR:-/etc/apt}"
has_deb_src() {
  grep -qsE '^[[:space:]]*deb-src[[:space:]].*bookworm' "$APT_DIR/sources.list" "$APT_DIR"/sources.list.d/*.list 2>/dev/null && return 0
  for f in "$APT_DIR"/sources.list.d/*.sources; do
    [ -e "$f" ] || continue
    # deb822: a stanza whose Types contain deb-src and whose Suites contain bookworm
    awk 'BEGIN{RS="";FS="\n"} /Types:[^\n]*deb-src/ && /Suites:[^\n]*bookworm/ {found=1} END{exit !found}' "$f" && return 0
  done
  return 1
}

# deb_src_stanzas: prints deb822 deb-src stanzas mirroring every enabled `deb`
# entry for a bookworm suite, from one-line .list files and deb822 .sources
# files alike; nothing when there is none.
deb_src_stanzas() {
  local f
  for f in "$APT_DIR/sources.list" "$APT_DIR"/sources.list.d/*.list; do
    [ -e "$f" ] || continue
    # deb [opt=value ...] URI SUITE COMPONENT...
    awk '
      /^[[:space:]]*deb[[:space:]]/ {
        sub(/^[[:space:]]*deb[[:space:]]+/, "")
        key = ""
        if ($0 ~ /^\[/) {
          opts = substr($0, 2, index($0, "]") - 2)
          $0 = substr($0, index($0, "]") + 1)
          n = split(opts, o, /[[:space:]]+/)
          for (i = 1; i <= n; ++i) if (o[i] ~ /^signed-by=/) key = substr(o[i], 11)
        }
        if (NF < 3 || $2 !~ /^bookworm/) next
        comps = $3
        for (i = 4; i <= NF; ++i) comps = comps " " $i
        printf "Types: deb-src\nURIs: %s\nSuites: %s\nComponents: %s\n", $1, $2, comps
        if (key != "") printf "Signed-By: %s\n", key
        printf "\n"
      }' "$f"
  done
  for f in "$APT_DIR"/sources.list.d/*.sources; do
    [ -e "$f" ] || continue
    case "$f" in */sodt-deb-src.sources) continue ;; esac
    # A stanza with Types deb, a bookworm suite and not Enabled: no: the
    # same stanza with Types deb-src (comment lines dropped).
    awk 'BEGIN { RS = ""; FS = "\n" }
      {
        types = ""; suites = ""; enabled = "yes"; out = ""
        for (i = 1; i <= NF; ++i) {
          line = $i
          if (line ~ /^[[:space:]]*#/) continue
          if (line ~ /^Types:/) { types = line; continue }
          if (line ~ /^Suites:/) suites = line
          if (line ~ /^Enabled:/) { enabled = tolower(line); sub(/^enabled:[[:space:]]*/, "", enabled) }
          out = out line "\n"
        }
        if (types ~ /[[:space:]]deb([[:space:]]|$)/ && suites ~ /bookworm/ && enabled != "no")
          printf "Types: deb-src\n%s\n", out
      }' "$f"
  done
}

need_update=0
if ! has_deb_src; then
  stanzas="$(deb_src_stanzas)"
  if [ -z "$stanzas" ]; then
    echo "install-deps.sh: no deb entry for bookworm in $APT_DIR/sources.list*; add the Debian 12 archive first" >&2
    exit 1
  fi
  log "no deb-src for bookworm configured: adding $APT_DIR/sources.list.d/sodt-deb-src.sources from the system's deb entries"
  printf '%s\n' "$stanzas" | "${SUDO[@]}" tee "$APT_DIR/sources.list.d/sodt-deb-src.sources" >/dev/null
  need_update=1
fi
[ "${SODT_APT_SOURCES_ONLY:-0}" = 1 ] && exit 0

[ "$CORE_ONLY" = 1 ] && PACKAGES=("${CORE_PACKAGES[@]}")
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ] || [ "$need_update" -eq 1 ]; then
  log "apt-get update"
  "${SUDO[@]}" apt-get update -qq
fi
if [ "${#missing[@]}" -gt 0 ]; then
  log "installing: ${missing[*]}"
  "${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  log "all packages already installed"
fi

# MeshLab SDK: headers of Debian's meshlab source package, same version as the
# installed binary (the plugin ABI must match it).
if [ -f "$SDK_LINK/src/common/interfaces.h" ] && [ -f "$SDK_LINK/vcglib/vcg/complex/complex.h" ]; then
  log "MeshLab SDK already present: $SDK_LINK"
else
  mkdir -p "$DEPS_DIR"
  log "fetching Debian's meshlab source package into $DEPS_DIR"
  # apt-get source as root warns about the unsandboxed download; harmless.
  (cd "$DEPS_DIR" && apt-get source -qq meshlab 2>&1 | grep -v 'unsandboxed' || true)
  src="$(find "$DEPS_DIR" -maxdepth 1 -mindepth 1 -type d -name 'meshlab-*' | sort | tail -n1)"
  if [ -z "$src" ] || [ ! -f "$src/src/common/interfaces.h" ]; then
    echo "install-deps.sh: 'apt-get source meshlab' did not produce src/common/interfaces.h under $DEPS_DIR" >&2
    exit 1
  fi
  ln -sfn "$(basename "$src")" "$SDK_LINK"
  rm -f "$DEPS_DIR"/meshlab_*.tar.* "$DEPS_DIR"/meshlab_*.dsc
  log "MeshLab SDK ready: $SDK_LINK -> $(basename "$src")"
fi
log "done"

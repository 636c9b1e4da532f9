#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Shows that a change leaves every result of the `sodt` command bit for bit
# the same: runs a fixed set of commands (every algorithm, guard and option
# that changes the result) on the bundled meshes and, when present, the
# shared ones, and prints one digest line per output file. The report's
# timing fields and file names are left out of its digest.
#
#   scripts/check-identical.sh [--sodt BIN] [--shared DIR] > digests.txt
#       digests of BIN (default build/cli/sodt)
#   scripts/check-identical.sh --base REV [--sodt BIN] [--shared DIR]
#       builds REV's `sodt` in a temporary worktree, digests both and
#       compares; exit status 0 when every digest is the same, 1 otherwise
#   scripts/check-identical.sh --base-sodt BASEBIN [--sodt BIN] [--shared DIR]
#       the same against an already built `sodt`
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
sodt="$root/build/cli/sodt"
shared="$root/../shared/meshes"
base=""
base_sodt=""
usage() { sed -n '2,/^set -euo/{/^#/s/^# \{0,1\}//p}' "$0" | sed 1d; }
while [ $# -gt 0 ]; do
  case "$1" in
    --sodt) sodt="$2"; shift 2 ;;
    --shared) shared="$2"; shift 2 ;;
    --base) base="$2"; shift 2 ;;
    --base-sodt) base_sodt="$2"; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "check-identical: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
python=/usr/bin/python3
[ -x "$python" ] || python=python3

# One digest per output: the mesh files' bytes, the report without the
# fields that name files or time the run. Numbers are compared as values
# (2, 2.0 and 2e0 are the same), not as the text a JSON writer chose.
digest_report() {
  "$python" - "$1" <<'EOF'
import hashlib, json, sys
d = json.load(open(sys.argv[1]), parse_int=float)
for k in ("seconds", "threads", "input", "output", "classes_output"):
    d.pop(k, None)
print(hashlib.sha256(json.dumps(d, sort_keys=True).encode()).hexdigest())
EOF
}

digests() {  # $1 = sodt binary; prints "run file digest" lines
  local bin="$1" work
  work="$(mktemp -d)"
  # Cleared as it fires: a RETURN trap set in a function stays set after it,
  # and would fire again on the caller's return, with work out of scope.
  trap 'rm -rf "$work"; trap - RETURN' RETURN
  local meshes=("$root"/meshes/*.ply "$root"/meshes/*.off "$root"/meshes/*.obj "$root"/meshes/*.stl)
  local small=("${meshes[@]}")
  if [ -d "$shared" ]; then
    meshes+=("$shared"/*.ply)
  else
    echo "check-identical: no shared meshes at $shared; bundled meshes only" >&2
  fi
  local configs=(
    "basic|--threads 2"
    "basic1|--threads 1"
    "guard_none|--guard none"
    "guard_fold|--guard fold --max-deviation 0"
    "no_fallback|--laplacian-fallback off --max-backtracks 0"
    "feature|--algorithm feature"
    "feature_flips|--algorithm feature --flips --flip-max-dihedral 30"
    "basic_flips_best|--flips --keep-best"
    "feature_best_tol|--algorithm feature --keep-best --tolerance 0.01 --epsilon 3 --eta 1.5"
    "denoise|--algorithm denoise"
    "denoise_flips|--algorithm denoise --flips --max-normal-step 0.1"
    "laplacian|--algorithm laplacian --iterations 5"
    "filtered|--algorithm filtered"
    "repair|--flips --repair"
    "feature_repair|--algorithm feature --flips --repair"
    "slide|--slide-boundary"
  )
  local m name cfg opts out
  for m in "${meshes[@]}"; do
    name="$(basename "$m")"
    for cfg in "${configs[@]}"; do
      opts="${cfg#*|}"
      out="$work/out.ply"
      # shellcheck disable=SC2086
      "$bin" smooth "$m" "$out" $opts --report "$work/r.json" \
        --classes-out "$work/c.ply" --quiet
      echo "$name ${cfg%%|*} out $(sha256sum < "$out" | cut -c1-64)"
      echo "$name ${cfg%%|*} classes $(sha256sum < "$work/c.ply" | cut -c1-64)"
      echo "$name ${cfg%%|*} report $(digest_report "$work/r.json")"
    done
    "$bin" classify "$m" "$work/k.ply" --json "$work/k.json" > "$work/k.txt"
    echo "$name classify out $(sha256sum < "$work/k.ply" | cut -c1-64)"
    echo "$name classify stdout $(sed "s|$work|WORK|g" "$work/k.txt" | sha256sum | cut -c1-64)"
    echo "$name classify json $(digest_report "$work/k.json")"
    "$bin" stats "$m" > "$work/s.json"
    echo "$name stats json $(digest_report "$work/s.json")"
  done
  # The numerical ODT is slow: the small bundled meshes only.
  for m in "${small[@]}"; do
    "$bin" smooth "$m" "$work/o.ply" --algorithm odt --iterations 3 --report "$work/r.json" --quiet
    echo "$(basename "$m") odt out $(sha256sum < "$work/o.ply" | cut -c1-64)"
    echo "$(basename "$m") odt report $(digest_report "$work/r.json")"
  done
}

compare() {  # $1 = base binary, $2 = what to call it
  digests "$1" > "$tmp/base.txt"
  digests "$sodt" > "$tmp/new.txt"
  if diff "$tmp/base.txt" "$tmp/new.txt" > "$tmp/diff.txt"; then
    echo "check-identical: $(wc -l < "$tmp/new.txt") digests, all identical to $2"
  else
    echo "check-identical: outputs differ from $2:" >&2
    cat "$tmp/diff.txt" >&2
    exit 1
  fi
}

if [ -n "$base_sodt" ]; then
  tmp="$(mktemp -d)"
  trap 'rm -rf "$tmp"' EXIT
  compare "$base_sodt" "$base_sodt"
  exit 0
fi
if [ -z "$base" ]; then
  digests "$sodt"
  exit 0
fi

tmp="$(mktemp -d)"
trap 'git -C "$root" worktree remove --force "$tmp/src" >/dev/null 2>&1 || true; rm -rf "$tmp"' EXIT
git -C "$root" worktree add --detach "$tmp/src" "$base" >/dev/null
echo "check-identical: building $base's sodt" >&2
# The worktree has no .deps/: vcglib comes from this checkout's MeshLab tree.
cmake -S "$tmp/src" -B "$tmp/build" -DCMAKE_BUILD_TYPE=Release -DSODT_BUILD_TESTS=OFF \
  -DSODT_BUILD_PLUGIN=OFF -DSODT_BUILD_BENCH=OFF -DSODT_BUILD_TOOLS=OFF \
  -DMESHLAB_SOURCE_DIR="$root/.deps/meshlab-src" -DSODT_MESHLAB2025_DIR= > "$tmp/cmake.log"
cmake --build "$tmp/build" --target sodt -j "$(nproc)" > "$tmp/build.log"
compare "$tmp/build/cli/sodt" "$base"

#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Fetches the real-world mesh corpus listed in bench/corpus/corpus.tsv from
# Debian 12's archive into a cache folder outside the checkout. See --help.
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
LIST="$HERE/corpus.tsv"
PY=/usr/bin/python3
DIR="${SODT_CORPUS_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/sodt/corpus-r1}"
ONLY=""
QUICK=0
PRINT_SUMS=0
MANIFEST=0

usage() {
  cat <<EOF
usage: bench/corpus/fetch.sh [--dir DIR] [--quick] [--only NAME[,NAME...]]
                             [--print-sums] [--manifest]

Downloads the Debian 12 packages that hold the meshes of bench/corpus/corpus.tsv
(apt-get download: no root needed, nothing installed), extracts only the mesh
files, gunzips the .gz ones and renders the OpenSCAD examples to STL (facets
sorted, so that every render has the same checksum), then checks each file's
SHA-256 against the list and that it loads (at least 100 triangles, a non-zero
bounding box). Safe to run again: what is already there and correct is kept.

  --dir DIR       cache folder (default: \$SODT_CORPUS_DIR, else
                  \${XDG_CACHE_HOME:-\$HOME/.cache}/sodt/corpus-r1; now $DIR)
  --quick         only the meshes marked quick in corpus.tsv
  --only LIST     only these meshes (comma-separated names)
  --print-sums    print each mesh's SHA-256 instead of failing on a mismatch
                  (for whoever edits corpus.tsv)
  --manifest      also rewrite bench/corpus/MANIFEST.md from the list and the
                  fetched files (provenance, versions, counts)
  -h, --help      this help

Writes DIR/debs/*.deb, DIR/meshes/NAME.{stl,off,obj,ply}, DIR/stats/NAME.json
and DIR/index.tsv (name, kind, file, package, version, member), which
bench/corpus/run.py reads. Needs apt-get, dpkg-deb, tar, gzip, sha256sum,
python3-numpy, and openscad for the OpenSCAD examples (scripts/install-deps.sh
installs them). Exit status: 0 all meshes ready; 1 something is missing or
wrong (every problem is listed); 2 bad command line.
EOF
}

die() { echo "fetch.sh: error: $*" >&2; exit 1; }
log() { printf '[fetch] %s\n' "$*"; }

while [ $# -gt 0 ]; do
  case "$1" in
    --dir) [ $# -ge 2 ] || { echo "fetch.sh: --dir needs a value" >&2; exit 2; }; DIR="$2"; shift 2 ;;
    --dir=*) DIR="${1#--dir=}"; shift ;;
    --only) [ $# -ge 2 ] || { echo "fetch.sh: --only needs a value" >&2; exit 2; }; ONLY="$2"; shift 2 ;;
    --only=*) ONLY="${1#--only=}"; shift ;;
    --quick) QUICK=1; shift ;;
    --print-sums) PRINT_SUMS=1; shift ;;
    --manifest) MANIFEST=1; shift ;;
    -h|--help) usage; exit 0 ;;
    *) echo "fetch.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done

[ -f "$LIST" ] || die "the corpus list $LIST is missing"

# The entries to fetch: name kind package member transform sha256 license quick note
mapfile -t ROWS < <(grep -v '^#' "$LIST" | tail -n +2 | awk -F'\t' -v only=",$ONLY," -v quick="$QUICK" '
  NF < 9 { printf "fetch.sh: corpus.tsv line with %d fields (9 expected): %s\n", NF, $0 > "/dev/stderr"; bad = 1; next }
  (only == ",," || index(only, "," $1 ",")) && (quick == 0 || $8 == 1) { print }
  END { exit bad }') || die "corpus.tsv is malformed"
[ "${#ROWS[@]}" -gt 0 ] || die "no mesh of corpus.tsv matches the selection (--only '$ONLY', --quick $QUICK)"
if [ -n "$ONLY" ]; then
  IFS=, read -r -a wanted <<<"$ONLY"
  for w in "${wanted[@]}"; do
    printf '%s\n' "${ROWS[@]}" | cut -f1 | grep -qxF "$w" || die "--only: no mesh named '$w' in corpus.tsv"
  done
fi

# Tools, checked before anything is downloaded.
missing=()
for t in apt-get dpkg-deb tar gzip sha256sum awk; do command -v "$t" >/dev/null 2>&1 || missing+=("$t"); done
"$PY" -c 'import numpy' 2>/dev/null || missing+=("python3-numpy (for $PY)")
if printf '%s\n' "${ROWS[@]}" | cut -f5 | grep -qx scad; then
  command -v openscad >/dev/null 2>&1 || missing+=("openscad")
fi
[ "${#missing[@]}" -eq 0 ] || die "missing: ${missing[*]}; run scripts/install-deps.sh (or apt-get install them)"

mkdir -p "$DIR/debs" "$DIR/meshes" "$DIR/stats" "$DIR/src" || die "cannot create $DIR"
DIR="$(cd "$DIR" && pwd)"
log "cache: $DIR (${#ROWS[@]} meshes)"

# 1. the packages (one download per package; a .deb already in the cache is reused)
declare -A DEB VERSION
for row in "${ROWS[@]}"; do
  IFS=$'\t' read -r _ _ pkg _ <<<"$row"
  [ -n "${DEB[$pkg]:-}" ] && continue
  deb="$(ls "$DIR/debs/${pkg}"_*.deb 2>/dev/null | sort | tail -n1 || true)"
  if [ -z "$deb" ]; then
    log "downloading $pkg"
    # As root, apt warns that _apt cannot write the folder; harmless.
    if ! out="$(cd "$DIR/debs" && apt-get download -q "$pkg" 2>&1)"; then
      printf '%s\n' "$out" >&2
      die "apt-get download $pkg failed (is Debian 12's archive configured and 'apt-get update' done?)"
    fi
    deb="$(ls "$DIR/debs/${pkg}"_*.deb 2>/dev/null | sort | tail -n1 || true)"
    [ -n "$deb" ] || die "apt-get download $pkg left no ${pkg}_*.deb in $DIR/debs"
  fi
  DEB[$pkg]="$deb"
  VERSION[$pkg]="$(dpkg-deb -f "$deb" Version)" || die "$deb is not a readable .deb (delete it and run again)"
done

# Reads one file out of a .deb to stdout.
deb_cat() { dpkg-deb --fsys-tarfile "$1" | tar -xO ".$2"; }

# 2. the meshes
problems=()
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
: > "$TMP/index.tsv"
for row in "${ROWS[@]}"; do
  IFS=$'\t' read -r name kind pkg member transform sha license quick note <<<"$row"
  deb="${DEB[$pkg]}"
  case "$transform" in
    scad) ext=stl ;;
    file|gunzip) base="${member##*/}"; base="${base%.gz}"; ext="${base##*.}"; ext="${ext,,}" ;;
    *) problems+=("$name: unknown transform '$transform'"); continue ;;
  esac
  out="$DIR/meshes/$name.$ext"
  if [ -f "$out" ] && [ "$sha" != "-" ] && [ "$(sha256sum "$out" | cut -d' ' -f1)" = "$sha" ]; then
    action="cached"
  else
    tmp="$TMP/$name.$ext"
    case "$transform" in
      file|gunzip)
        outer="${member%%!*}"
        if [ "$outer" != "$member" ]; then
          # a member of a tarball inside the package: keep the tarball in src/
          inner="${member#*!}"
          tarball="$DIR/src/$pkg/${outer##*/}"
          if [ ! -f "$tarball" ]; then
            mkdir -p "$DIR/src/$pkg"
            deb_cat "$deb" "$outer" > "$tarball.part" || { rm -f "$tarball.part"; problems+=("$name: $outer not in $deb"); continue; }
            mv "$tarball.part" "$tarball"
          fi
          tar -xzOf "$tarball" "$inner" > "$tmp" 2>/dev/null || { problems+=("$name: $inner not in $tarball"); continue; }
        elif [ "$transform" = gunzip ]; then
          deb_cat "$deb" "$member" | gzip -dc > "$tmp" 2>/dev/null || { problems+=("$name: $member not in $deb or not gzip"); continue; }
        else
          deb_cat "$deb" "$member" > "$tmp" 2>/dev/null || { problems+=("$name: $member not in $deb"); continue; }
        fi
        action="extracted"
        ;;
      scad)
        # the example's folder (it may import a .dxf, .dat or .stl beside it)
        srcdir="$DIR/src/$pkg"
        mkdir -p "$srcdir"
        dpkg-deb --fsys-tarfile "$deb" | tar -x -C "$srcdir" ".${member%/*}" 2>/dev/null \
          || { problems+=("$name: ${member%/*} not in $deb"); continue; }
        scad="$srcdir$member"
        [ -f "$scad" ] || { problems+=("$name: $member not in $deb"); continue; }
        t0=$SECONDS
        if ! (cd "${scad%/*}" && timeout 300 openscad -o "$TMP/$name.raw.stl" "$scad" > "$TMP/$name.log" 2>&1); then
          problems+=("$name: openscad failed on $member: $(tail -n 3 "$TMP/$name.log" | tr '\n' ' ')")
          continue
        fi
        "$PY" "$HERE/meshtool.py" canon-stl "$TMP/$name.raw.stl" "$tmp" --name "$name" >/dev/null \
          || { problems+=("$name: the render of $member is not an ASCII STL"); continue; }
        action="rendered with openscad in $((SECONDS - t0)) s"
        ;;
    esac
    got="$(sha256sum "$tmp" | cut -d' ' -f1)"
    if [ "$PRINT_SUMS" = 1 ]; then
      printf '%s\t%s\n' "$name" "$got"
    elif [ "$sha" != "$got" ]; then
      problems+=("$name: SHA-256 $got, corpus.tsv expects $sha (${pkg} ${VERSION[$pkg]} changed the file?)")
      continue
    fi
    mv "$tmp" "$out"
  fi
  # 3. measures (cached per checksum); a mesh that does not load is a problem
  sum="$(sha256sum "$out" | cut -d' ' -f1)"
  st="$DIR/stats/$name.json"
  if [ ! -f "$st" ] || ! grep -q "\"sha256\": \"$sum\"" "$st"; then
    if ! js="$("$PY" "$HERE/meshtool.py" stats "$out" --json 2>&1)"; then
      problems+=("$name: does not load: $js"); continue
    fi
    printf '%s\n' "$js" | "$PY" -c 'import json,sys; d=json.load(sys.stdin); d["sha256"]=sys.argv[1]; print(json.dumps(d))' "$sum" > "$st"
  fi
  read -r nv nf diag < <("$PY" -c 'import json,sys; d=json.load(open(sys.argv[1])); print(d["vertices"], d["faces"], d["bbox_diag"])' "$st")
  if [ "$nf" -lt 100 ] || [ "$("$PY" -c "print(1 if $diag > 0 else 0)")" != 1 ]; then
    problems+=("$name: not a usable mesh ($nf triangles, bbox diagonal $diag)"); continue
  fi
  printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$kind" "meshes/$name.$ext" "$pkg" "${VERSION[$pkg]}" "$member" >> "$TMP/index.tsv"
  log "$(printf '%-22s %-10s %7d V %7d F  %s' "$name" "$kind" "$nv" "$nf" "$action")"
done

if [ "${#problems[@]}" -gt 0 ]; then
  printf 'fetch.sh: error: %s\n' "${problems[@]}" >&2
  echo "fetch.sh: ${#problems[@]} of ${#ROWS[@]} meshes are not ready" >&2
  exit 1
fi
[ "$PRINT_SUMS" = 1 ] && exit 0
# The index lists what this run checked; a subset run keeps the other lines.
if [ -n "$ONLY" ] || [ "$QUICK" = 1 ]; then
  [ -f "$DIR/index.tsv" ] && awk -F'\t' 'NR==FNR { have[$1]=1; next } !($1 in have)' "$TMP/index.tsv" "$DIR/index.tsv" >> "$TMP/index.tsv"
fi
sort -o "$DIR/index.tsv" "$TMP/index.tsv"
log "ready: ${#ROWS[@]} meshes checked; $DIR/index.tsv lists $(wc -l < "$DIR/index.tsv")"
if [ "$MANIFEST" = 1 ]; then
  "$PY" "$HERE/corpus.py" manifest --dir "$DIR" --out "$HERE/MANIFEST.md"
  log "wrote $HERE/MANIFEST.md"
fi

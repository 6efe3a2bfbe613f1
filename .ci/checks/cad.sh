#!/usr/bin/env bash
# The CAD check: nendo's STEP and IGES exports of six sculpted primitives (sphere, torus,
# cylinder, hemisphere, plane, tube) read with OpenCASCADE and checked against the models by
# scripts/cad_check.py (validity, one face per patch, the control points, closed solids and
# their exact volumes, open shells and their borders, shared edges, G1, outward faces, pole
# faces of three edges, IGES in one group).
#
# Then the one-surface exports (`--one-surface`) of the sphere, torus, plane and tube (its
# unequal knots) by scripts/cad_one_surface.py: one face each, valid, the spline on the knots of
# the saved spacing ratios and within 1e-9 of every patch, the sphere and torus closed solids
# with the exact volume; and the sphere in inches at scale 2 (50.8 mm per model unit).
#
# FreeCAD: when `freecadcmd` is installed (Debian's freecad-python3; not installed by this
# check) and starts within a minute, its headless importer (Import.insert, Part.read) opens
# every IGES file written here with the expected faces (scripts/freecad_iges.py). Without it,
# OpenCASCADE's IGES reader checks the group above (one top-level entity) and the check says
# FreeCAD was not run.
#
# OpenCASCADE comes from PyPI's cadquery-ocp-novtk (no display needed), pinned, installed once
# into a cached virtual environment (~1 min the first time; reused after). A failed install
# fails the check: it never passes without OpenCASCADE. Takes ~1-2 min once installed.
set -euo pipefail
cd "$(dirname "$0")/../.."

OCP_VERSION="8.0.1.1.0"
VENV="${XDG_CACHE_HOME:-$HOME/.cache}/nendo-ci/venv-ocp-$OCP_VERSION"
fail() { echo "cad check FAILED: $*"; exit 1; }

if ! "$VENV/bin/python" -c "import OCP.STEPControl, numpy" 2>/dev/null; then
  echo "cad check: installing cadquery-ocp-novtk==$OCP_VERSION into $VENV"
  rm -rf "$VENV"
  mkdir -p "$(dirname "$VENV")"
  python3 -m venv "$VENV" || fail "python3 -m venv failed (apt-get install python3-venv)"
  "$VENV/bin/pip" install -q --disable-pip-version-check "cadquery-ocp-novtk==$OCP_VERSION" numpy \
    || fail "pip could not install cadquery-ocp-novtk==$OCP_VERSION (OpenCASCADE for Python)"
  "$VENV/bin/python" -c "import OCP.STEPControl, numpy" \
    || fail "cadquery-ocp-novtk==$OCP_VERSION installed but OCP does not import"
fi

# shellcheck source=lib/binary.sh
. .ci/checks/lib/binary.sh

WORK="$(mktemp -d /tmp/nendo-cad-check.XXXXXX)"
trap 'rm -rf "$WORK"' EXIT

# name, sculpt arguments, pushes (a dent and a bump each; the tube and hemisphere also near
# their poles, the sphere at both).
sculpt() {
  local name="$1"; shift
  local ops="$1"; shift
  printf '%s\n' "$ops" >"$WORK/$name.ops"
  "$BIN" sculpt "$@" --ops "$WORK/$name.ops" --out "$WORK/$name.json" >"$WORK/$name.log" 2>&1 \
    || { cat "$WORK/$name.log"; fail "nendo sculpt $name"; }
}
sculpt sphere '{"op":"push","at":[0,0,3],"dir":[0,0,-1],"depth":0.5,"radius":1.5}
{"op":"push","at":[3,0,0],"dir":[-1,0,0],"depth":-0.4,"radius":1.2}
{"op":"push","at":[0,0,-3],"dir":[0,0,1],"depth":-0.3,"radius":1.0}' --primitive sphere
sculpt torus '{"op":"push","at":[4,0,1],"dir":[0,0,-1],"depth":0.3,"radius":1.0}
{"op":"push","at":[0,-5,0],"dir":[0,1,0],"depth":-0.4,"radius":1.2}' --primitive torus
sculpt cylinder '{"op":"push","at":[2,0,2],"dir":[-1,0,0],"depth":0.4,"radius":1.2}
{"op":"push","at":[0,2,1],"dir":[0,-1,0],"depth":-0.3,"radius":1.0}' --primitive cylinder
sculpt hemisphere '{"op":"push","at":[0,0,3],"dir":[0,0,-1],"depth":0.4,"radius":1.2}
{"op":"push","at":[2,0,2],"dir":[-1,0,-1],"depth":-0.3,"radius":1.0}' --primitive hemisphere
sculpt plane '{"op":"push","at":[0.5,0.5,0],"dir":[0,0,-1],"depth":0.6,"radius":1.25}
{"op":"push","at":[-1,-1,0],"dir":[0,0,1],"depth":0.3,"radius":1.0}' --primitive plane
sculpt tube '{"op":"push","at":[0,0,0],"dir":[0,0,1],"depth":0.3,"radius":1.0}
{"op":"push","at":[1,0,3],"dir":[-1,0,0],"depth":0.2,"radius":1.0}' --primitive tube

# Curves go out too: a space Bezier curve and a planar B-spline on the sphere and the plane.
for name in sphere plane; do
  "$VENV/bin/python" - "$WORK/$name.json" <<'PY' || fail "cannot add curves to $name"
import json, sys
doc = json.load(open(sys.argv[1]))
doc["curves"] = [
    {"bezier": [[0, 0, 4], [1, 2, 5], [2, 0, 4.5], [3, 1, 4]]},
    {"bspline": {"degree": 3, "knots": [0, 0, 0, 0, 0.5, 1, 1, 1, 1],
                 "points": [[0, 0], [1, 1], [2, 0], [3, 1], [4, 0]]}},
]
json.dump(doc, open(sys.argv[1], "w"))
PY
done

for name in sphere torus cylinder hemisphere plane tube; do
  "$BIN" export "$WORK/$name.json" "$WORK/$name.step" >/dev/null || fail "nendo export $name.step"
  "$BIN" export "$WORK/$name.json" "$WORK/$name.igs" >/dev/null || fail "nendo export $name.igs"
  "$VENV/bin/python" scripts/cad_check.py "$WORK/$name.json" "$WORK/$name.step" "$WORK/$name.igs" \
    2>&1 | grep -av -e "Total number of loaded entities" -e $'^\e\\[0m$' -e '^$' || true
  [ "${PIPESTATUS[0]}" = 0 ] || fail "$name (see above)"
done

iges_faces=""
for name in sphere torus cylinder hemisphere plane tube; do
  patches=$("$VENV/bin/python" -c 'import json,sys; s=json.load(open(sys.argv[1]))["surface"]; print(s["patches_u"]*s["patches_v"])' "$WORK/$name.json")
  iges_faces+="$WORK/$name.igs=$patches;"
done

# One surface per model.
for name in sphere torus plane tube; do
  "$BIN" export "$WORK/$name.json" "$WORK/$name-one.step" --one-surface >/dev/null \
    || fail "nendo export --one-surface $name.step"
  "$BIN" export "$WORK/$name.json" "$WORK/$name-one.igs" --one-surface >/dev/null \
    || fail "nendo export --one-surface $name.igs"
  "$VENV/bin/python" scripts/cad_one_surface.py "$WORK/$name.json" "$WORK/$name-one.step" \
    "$WORK/$name-one.igs" 2>&1 | grep -av -e "Total number of loaded entities" -e $'^\e\\[0m$' -e '^$' || true
  [ "${PIPESTATUS[0]}" = 0 ] || fail "one-surface $name (see above)"
  iges_faces+="$WORK/$name-one.igs=1;"
done
"$BIN" export "$WORK/sphere.json" "$WORK/sphere-in.step" --one-surface --units in --scale 2 >/dev/null \
  || fail "nendo export --units in"
"$BIN" export "$WORK/sphere.json" "$WORK/sphere-in.igs" --one-surface --units in --scale 2 >/dev/null \
  || fail "nendo export --units in"
"$VENV/bin/python" scripts/cad_one_surface.py "$WORK/sphere.json" "$WORK/sphere-in.step" \
  "$WORK/sphere-in.igs" 50.8 2>&1 | grep -av -e "Total number of loaded entities" -e $'^\e\\[0m$' -e '^$' || true
[ "${PIPESTATUS[0]}" = 0 ] || fail "one-surface sphere in inches (see above)"

freecad="FreeCAD not installed (apt-get install freecad-python3 to check its importer too)"
if command -v freecadcmd >/dev/null 2>&1 && timeout 60 freecadcmd -c 'print(1)' >/dev/null 2>&1; then
  out=$(NENDO_IGES="$iges_faces" timeout 120 freecadcmd scripts/freecad_iges.py 2>&1 || true)
  printf '%s\n' "$out" | grep -ao 'freecad_iges: .*' | sed 's/^freecad_iges: //'
  printf '%s\n' "$out" | grep -aq '^FREECAD_IGES_OK' \
    || { printf '%s\n' "$out" | tail -5; fail "FreeCAD's headless importer on the IGES files"; }
  freecad="FreeCAD's headless importer opened every IGES file"
fi
echo "cad check passed: STEP and IGES of six sculpted primitives, one-surface exports of four, read by OpenCASCADE $OCP_VERSION; $freecad."

#!/usr/bin/env bash
# The CAD check: nendo's STEP and IGES exports of six sculpted primitives (sphere, torus,
# cylinder, hemisphere, plane, tube) read with OpenCASCADE and checked against the models by
# scripts/cad_check.py (validity, one face per patch, the control points, closed solids and
# their exact volumes, open shells and their borders, shared edges, G1, outward faces).
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
echo "cad check passed: STEP and IGES of six sculpted primitives read by OpenCASCADE $OCP_VERSION."

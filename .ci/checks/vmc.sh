#!/usr/bin/env bash
# The VMC check: nendo's VMC receiver against an independent sender, PyPI's python-osc
# (tests/vmc/independent_sender.py): bundles of a known skeleton recorded by
# `nendo record --profile vmc --vmc-listen ...` for both hands, the recorded joints against
# the poses composed by the script, bad packets and a flood counted, and `nendo replay` of
# the trace leaving the 0.30-deep dent under the index tip.
#
# python-osc is pinned and installed once into a cached virtual environment (as the CAD check
# does for OpenCASCADE). A failed install fails the check, naming the package: it never
# passes without python-osc.
set -euo pipefail
cd "$(dirname "$0")/../.."

OSC_VERSION="1.10.2"
VENV="${XDG_CACHE_HOME:-$HOME/.cache}/nendo-ci/venv-osc-$OSC_VERSION"
fail() { echo "vmc check FAILED: $*"; exit 1; }

if ! "$VENV/bin/python" -c "import pythonosc" 2>/dev/null; then
  echo "vmc check: installing python-osc==$OSC_VERSION into $VENV"
  rm -rf "$VENV"
  mkdir -p "$(dirname "$VENV")"
  python3 -m venv "$VENV" || fail "python3 -m venv failed (apt-get install python3-venv)"
  "$VENV/bin/pip" install -q --disable-pip-version-check "python-osc==$OSC_VERSION" \
    || fail "pip could not install python-osc==$OSC_VERSION (the PyPI package python-osc)"
  "$VENV/bin/python" -c "import pythonosc" \
    || fail "python-osc==$OSC_VERSION installed but pythonosc does not import"
fi

# shellcheck source=lib/binary.sh
. .ci/checks/lib/binary.sh

WORK="$(mktemp -d /tmp/nendo-vmc-check.XXXXXX)"
trap 'rm -rf "$WORK"' EXIT

timeout 600 "$VENV/bin/python" tests/vmc/independent_sender.py "$BIN" "$PWD" "$WORK" "$@" \
  || fail "tests/vmc/independent_sender.py (see above)"

#!/usr/bin/env bash
# The layers the compiler enforces: the geometry crate (nendo-geom) depends on nothing of files,
# devices, GPU or UI, and the device crate (nendo-devices) on nothing of geometry or GPU.
set -euo pipefail
cd "$(dirname "$0")/../.."

fail=""
check_absent() {
  local package="$1"; shift
  local tree
  tree="$(cargo tree -p "$package" -e normal --prefix none --format '{p}' | awk '{print $1}' | sort -u)"
  for banned in "$@"; do
    if grep -qx "$banned" <<<"$tree"; then
      echo "layers: $package depends on $banned"
      fail=1
    fi
  done
}
check_absent nendo-geom wgpu winit egui egui-wgpu egui-winit serde_json hidapi serialport png clap \
  nendo-devices nendo tempfile roxmltree svgtypes
check_absent nendo-devices nendo-geom nendo wgpu winit egui png
[ -z "$fail" ] || exit 1
echo "layers check passed: nendo-geom and nendo-devices depend on none of the crates above them"

#!/usr/bin/env bash
# The layers the compiler enforces: the geometry crate (nendo-geom) depends on nothing of files,
# devices, GPU or UI, and the device crate (nendo-devices) on nothing of geometry or GPU.
# Inside nendo: the headless editor (src/editor/) builds and runs its tests without the `gui`
# feature; only the window's shell (src/app/) and its one entry (src/cli/window.rs) use winit
# or egui, only the renderer and the shell use wgpu, and nothing outside the shell names it.
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

# The window's libraries, used as paths (`egui::`, `winit::`, `wgpu::`) or imported.
uses_of() {
  grep -rlE "(^|[^[:alnum:]_])($1)(::|;| as )" src benches tests --include='*.rs' || true
}
while IFS= read -r file; do
  [ -n "$file" ] || continue
  case "$file" in
    src/app/*|src/cli/window.rs) ;;
    *) echo "layers: $file uses winit or egui (only src/app/ and src/cli/window.rs may)"; fail=1 ;;
  esac
done <<<"$(uses_of 'winit|egui|egui_winit|egui_wgpu')"
while IFS= read -r file; do
  [ -n "$file" ] || continue
  case "$file" in
    src/app/*|src/render/*|benches/render.rs|tests/it/render_headless.rs|tests/it/shader_validation.rs) ;;
    *) echo "layers: $file uses wgpu (only src/render/, src/app/ and the render benches and tests may)"; fail=1 ;;
  esac
done <<<"$(uses_of 'wgpu')"
# Nothing names the shell but the shell and the entry that opens the window.
while IFS= read -r file; do
  [ -n "$file" ] || continue
  case "$file" in
    src/app/*|src/cli/window.rs) ;;
    *) echo "layers: $file names the window's shell (crate::app / nendo::app); use nendo::editor"; fail=1 ;;
  esac
done <<<"$(grep -rlE '(crate|nendo)::app([^[:alnum:]_]|$)' src benches tests --include='*.rs' || true)"
# nendo-geom's surface/ folders are layers (base → net → constraint → operation → engine): a file
# names only the modules of its own layer and those below (comment lines aside).
surface=geom/src/surface
net="grid|group|primitive"
constraint="regulate|verify|continuity|mirror"
operation="shape_fn|nearest|grab|smooth|inverse|refine|deviation"
engine="engine"
check_layer() {
  local folder="$1" above="$2" hits
  hits="$(grep -rnE "surface::($above)\b" "$surface/$folder" --include=*.rs | grep -vE '^[^:]+:[0-9]+:\s*//' || true)"
  if [ -n "$hits" ]; then
    echo "layers: $surface/$folder uses a layer above it:"
    echo "$hits"
    fail=1
  fi
}
check_layer base "$net|$constraint|$operation|$engine"
check_layer net "$constraint|$operation|$engine"
check_layer constraint "$operation|$engine"
check_layer operation "$engine"
[ -z "$fail" ] || exit 1

# The headless editor builds, and its unit tests run, without the window (`gui` off: one
# build of its own, with its own feature resolution).
# `--lib`: the library alone, so that the window's binary in target/release stays the gui one
# the window checks run.
if ! cargo build -p nendo --no-default-features --release --lib; then
  echo "layers: nendo does not build without the gui feature (the headless editor must)"
  exit 1
fi
if ! cargo test -p nendo --no-default-features --release --lib editor; then
  echo "layers: the editor's unit tests fail without the gui feature"
  exit 1
fi
echo "layers check passed: nendo-geom and nendo-devices depend on none of the crates above them;"
echo "  the surface's layers use only those below them;"
echo "  winit / egui only in the window's shell, wgpu only in the renderer and the shell;"
echo "  the headless editor builds and passes its tests without gui"

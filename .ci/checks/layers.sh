#!/usr/bin/env bash
# The layers the compiler enforces: the geometry crate (nendo-geom) depends on nothing of files,
# devices, GPU or UI, and the device crate (nendo-devices) on nothing of geometry or GPU; the
# library (nendo-modeller, lib `nendo`) depends on neither the measurement suites (nendo-bench)
# nor the binary's package (nendo), and nothing but the binary's package depends on the suites.
# Inside the library: the headless editor (modeller/src/editor/) builds and runs its tests
# without the `gui` feature; only the window's shell (modeller/src/app/) and its one entry
# (modeller/src/cli/window.rs) use winit or egui, only the renderer and the shell use wgpu, and
# nothing outside the shell names it.
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
  nendo-devices nendo-modeller nendo-bench nendo tempfile roxmltree svgtypes
check_absent nendo-devices nendo-geom nendo-modeller nendo-bench nendo wgpu winit egui png
check_absent nendo-modeller nendo-bench nendo
# The suites' dependents, tests and benches included: the binary's package alone.
while IFS= read -r package; do
  case "$package" in
    nendo-bench|nendo|"") ;;
    *) echo "layers: $package depends on nendo-bench (only the nendo binary, its tests and benches may)"; fail=1 ;;
  esac
done <<<"$(cargo tree -i nendo-bench --workspace -e normal,build,dev --prefix none --format '{p}' | awk '{print $1}' | sort -u)"

# The window's libraries, used as paths (`egui::`, `winit::`, `wgpu::`) or imported.
uses_of() {
  grep -rlE "(^|[^[:alnum:]_])($1)(::|;| as )" src modeller/src bench/src benches tests --include='*.rs' || true
}
while IFS= read -r file; do
  [ -n "$file" ] || continue
  case "$file" in
    modeller/src/app/*|modeller/src/cli/window.rs) ;;
    *) echo "layers: $file uses winit or egui (only modeller/src/app/ and modeller/src/cli/window.rs may)"; fail=1 ;;
  esac
done <<<"$(uses_of 'winit|egui|egui_winit|egui_wgpu')"
while IFS= read -r file; do
  [ -n "$file" ] || continue
  case "$file" in
    modeller/src/app/*|modeller/src/render/*|benches/render.rs|tests/it/render_headless.rs|tests/it/shader_validation.rs) ;;
    *) echo "layers: $file uses wgpu (only modeller/src/render/, modeller/src/app/ and the render benches and tests may)"; fail=1 ;;
  esac
done <<<"$(uses_of 'wgpu')"
# Nothing names the shell but the shell and the entry that opens the window.
while IFS= read -r file; do
  [ -n "$file" ] || continue
  case "$file" in
    modeller/src/app/*|modeller/src/cli/window.rs) ;;
    *) echo "layers: $file names the window's shell (crate::app / nendo::app); use nendo::editor"; fail=1 ;;
  esac
done <<<"$(grep -rlE '(crate|nendo)::app([^[:alnum:]_]|$)' src modeller/src bench/src benches tests --include='*.rs' || true)"
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
# The library's package alone (`nendo-modeller --lib`), so that the window's binary in
# target/release stays the gui one the window checks run.
if ! cargo build -p nendo-modeller --no-default-features --release --lib; then
  echo "layers: nendo-modeller does not build without the gui feature (the headless editor must)"
  exit 1
fi
if ! cargo test -p nendo-modeller --no-default-features --release --lib editor; then
  echo "layers: the editor's unit tests fail without the gui feature"
  exit 1
fi
echo "layers check passed: nendo-geom, nendo-devices and nendo-modeller depend on none of the crates"
echo "  above them, and only the binary's package on nendo-bench;"
echo "  the surface's layers use only those below them;"
echo "  winit / egui only in the window's shell, wgpu only in the renderer and the shell;"
echo "  the headless editor builds and passes its tests without gui"

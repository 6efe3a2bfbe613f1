# Sourced by the checks that run the release binary (not run on its own: .ci/run runs only
# .ci/checks/*.sh). Sets BIN to the absolute path of the `nendo` binary: $NENDO_BIN, or the
# release build in the target directory, built first when it is not there.
BIN="${NENDO_BIN:-${CARGO_TARGET_DIR:-target}/release/nendo}"
if [ ! -x "$BIN" ]; then
  cargo build --release --bin nendo
fi
BIN="$(cd "$(dirname "$BIN")" && pwd)/$(basename "$BIN")"

#!/usr/bin/env bash
# The recording check: `nendo record` survives whatever ends it.
#
# 1. SIGKILL at random moments: 20 recordings of two `nendo emulate` processes (CyberGlove and
#    Fastrak, motion press, over the default plane) killed with `kill -9` between 0 and 2 s after
#    their trace appeared. Each must leave its trace under --out and nothing else, and
#    `nendo replay` must read it, saying how many frames it recovered; the table of recovered
#    frames is printed.
# 2. A full disk: a 64 KiB tmpfs (mounted here, so the check runs as root, as CI does). The
#    recording must stop at once with an error naming the file, the disk and the frames kept
#    (exit status 1), the file must end with a complete frame line and replay exactly those
#    frames, and nothing else may be left on the tmpfs.
# 3. A disk too full for the header: no trace appears (nothing is left on the tmpfs), and the
#    error says why.
#
# Needs: root (mount), jq. Takes ~40 s.
set -euo pipefail
cd "$(dirname "$0")/../.."

# shellcheck source=lib/binary.sh
. .ci/checks/lib/binary.sh
command -v jq >/dev/null || { echo "record-survives check: jq is missing (apt-get install jq)"; exit 1; }
[ "$(id -u)" = 0 ] || { echo "record-survives check FAILED: it mounts a small tmpfs and needs root (CI runs as root)"; exit 1; }

WORK="$(mktemp -d /tmp/nendo-record-survives.XXXXXX)"
GLOVE_PID=""
TRACKER_PID=""
REC_PID=""
cleanup() {
  for pid in "$REC_PID" "$GLOVE_PID" "$TRACKER_PID"; do
    [ -n "$pid" ] && kill "$pid" 2>/dev/null || true
  done
  wait 2>/dev/null || true
  mountpoint -q "$WORK/small" && umount "$WORK/small"
  rm -rf "$WORK"
}
trap cleanup EXIT
fail() { echo "record-survives check FAILED: $*"; exit 1; }

# The shipped glove + tracker profile placed so the press gesture reaches the default plane.
jq '.name = "record-check" | .world_from_tracker.translation = [0, 0, 0]
    | .world_from_tracker.scale = 21.5' \
  devices/profiles/cyberglove2-18-fastrak.json >"$WORK/profile.json"
start_emulator() { # device → prints its port
  "$BIN" emulate "$1" --motion press --seconds 600 --profile "$WORK/profile.json" \
    >"$WORK/$1.out" 2>"$WORK/$1.log" &
  local pid=$!
  # Known to the cleanup before anything can fail, so a failure never leaves it running
  # (the cleanup's `wait` would wait for it). Up to 30 s: a loaded machine is slow to start it.
  if [ "$1" = fastrak ]; then TRACKER_PID=$pid; else GLOVE_PID=$pid; fi
  for _ in $(seq 300); do [ -s "$WORK/$1.out" ] && break; sleep 0.1; done
  [ -s "$WORK/$1.out" ] || fail "the $1 emulator did not print its port"
}
start_emulator cyberglove
start_emulator fastrak
GLOVE_PORT="$(head -n1 "$WORK/cyberglove.out")"
TRACKER_PORT="$(head -n1 "$WORK/fastrak.out")"
# `nendo record` of both emulators on the plane: "${RECORD[@]}" --out T [options…] (the binary
# itself, not a shell function, so that `&` gives its own pid for kill -9).
RECORD=("$BIN" record --profile "$WORK/profile.json" --glove-port "$GLOVE_PORT"
  --tracker-port "$TRACKER_PORT" --primitive plane)

START=$SECONDS
# --- 1: kill -9 at random moments.
RANDOM=25
total=0
for k in $(seq -w 1 20); do
  dir="$WORK/kill-$k"
  mkdir -p "$dir"
  "${RECORD[@]}" --out "$dir/session.trace" --seconds 60 >"$dir/record.out" 2>"$dir/record.err" &
  REC_PID=$!
  for _ in $(seq 3000); do [ -e "$dir/session.trace" ] && break; sleep 0.01; done
  [ -e "$dir/session.trace" ] || fail "try $k: no trace appeared ($(cat "$dir/record.err"))"
  delay_ms=$(( RANDOM % 2000 ))
  sleep "$(printf '%d.%03d' $(( delay_ms / 1000 )) $(( delay_ms % 1000 )))"
  kill -9 "$REC_PID"
  wait "$REC_PID" 2>/dev/null && fail "try $k: nendo record was not killed"
  REC_PID=""
  left="$(ls -A "$dir" | grep -v -e '^record\.' | tr '\n' ' ')"
  [ "$left" = "session.trace " ] || fail "try $k: left $left"
  "$BIN" replay "$dir/session.trace" --out "$dir/replayed.json" >/dev/null 2>"$dir/replay.err" \
    || fail "try $k: replay failed: $(cat "$dir/replay.err")"
  frames="$(sed -n 's/.*recovered its \([0-9]*\) complete frame.*/\1/p' "$dir/replay.err" | head -n1)"
  [ -n "$frames" ] || fail "try $k: replay did not say what it recovered: $(cat "$dir/replay.err")"
  contacts="$(sed -n 's/.*): \([0-9]*\) contacts.*/\1/p' "$dir/replay.err" | head -n1)"
  torn=""
  grep -q "cut short" "$dir/replay.err" && torn=", a torn last line dropped"
  printf 'try %s: killed %4d ms after the trace appeared: %4d frames recovered, %s contacts replayed%s\n' \
    "$k" "$delay_ms" "$frames" "${contacts:-?}" "$torn"
  total=$(( total + frames ))
done
echo "20 kills: $total frames recovered in all"

# --- 2: a full disk.
mkdir -p "$WORK/small"
mount -t tmpfs -o size=64k tmpfs "$WORK/small" || fail "cannot mount a tmpfs"
set +e
"${RECORD[@]}" --out "$WORK/small/full.trace" --seconds 60 >"$WORK/full.out" 2>"$WORK/full.err"
status=$?
set -e
err="$(cat "$WORK/full.err")"
[ "$status" = 1 ] || fail "a full disk: exit status $status ($err)"
case "$err" in
  *"full.trace: No space left on device"*"the recording stopped; the file keeps the "*) ;;
  *) fail "a full disk: unclear error: $err" ;;
esac
kept="$(sed -n 's/.*the file keeps the \([0-9]*\) frames.*/\1/p' "$WORK/full.err")"
[ "$(tail -c1 "$WORK/small/full.trace" | od -An -c | tr -d ' ')" = '\n' ] \
  || fail "a full disk: the trace does not end with a complete line"
"$BIN" replay "$WORK/small/full.trace" --out "$WORK/full.json" >/dev/null 2>"$WORK/full-replay.err" \
  || fail "a full disk: replay failed: $(cat "$WORK/full-replay.err")"
grep -q "recovered its $kept complete frames" "$WORK/full-replay.err" \
  || fail "a full disk: replay recovered other than the $kept frames kept: $(cat "$WORK/full-replay.err")"
[ "$(ls -A "$WORK/small")" = "full.trace" ] || fail "a full disk: left $(ls -A "$WORK/small")"
echo "full disk: $err"
echo "full disk: $(stat -c %s "$WORK/small/full.trace") bytes on the 64 KiB tmpfs; replay: $(head -n1 "$WORK/full-replay.err")"

# --- 3: a disk too full for the header.
rm "$WORK/small/full.trace"
head -c $(( 64 * 1024 - 4096 )) /dev/zero >"$WORK/small/filler" 2>/dev/null || true
head -c 4096 /dev/zero >>"$WORK/small/filler" 2>/dev/null || true
set +e
"${RECORD[@]}" --out "$WORK/small/none.trace" --seconds 5 >"$WORK/none.out" 2>"$WORK/none.err"
status=$?
set -e
[ "$status" = 1 ] || fail "no room for the header: exit status $status ($(cat "$WORK/none.err"))"
grep -q "none.trace: No space left on device" "$WORK/none.err" \
  || fail "no room for the header: unclear error: $(cat "$WORK/none.err")"
grep -q "nendo-tmp" "$WORK/none.err" && fail "no room for the header: the error names the temporary: $(cat "$WORK/none.err")"
[ "$(ls -A "$WORK/small")" = "filler" ] || fail "no room for the header: left $(ls -A "$WORK/small")"
echo "no room for the header: $(cat "$WORK/none.err")"
echo "record-survives check passed in $(( SECONDS - START )) s"

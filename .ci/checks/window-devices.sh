#!/usr/bin/env bash
# The glove-user check: the modeller window connected with `--profile` to two emulated devices
# (`nendo emulate fastrak` and `nendo emulate cyberglove`, motion press, each on a pseudo-terminal
# behind a fixed `--link` path), under Xvfb with software rendering.
#
# 1. The window starts with both devices off: Connect still starts, both read Disconnected.
# 2. The emulators start: both devices reach Ok (the window retries them), the hand is drawn,
#    and the press gesture deforms the clay (a contact counted, the 3D view changed, the
#    autosaved model apart from the plane); the status carries the hand's latency figure.
# 3. The glove emulator is stopped: the glove reads Disconnected with an error.
# 4. It is started again on the same path: the glove is Ok again and its error is gone.
# In 2, the desk: Space held (the clutch) keeps the hand off the clay for two press gestures;
# let go, the press's contact feedback is shown.
#
# The window reports its device status in a file (NENDO_STATUS_FILE, a test aid: one JSON
# object, rewritten four times a second); screenshots judge the view.
#
# Needs: xvfb, xdotool, imagemagick, jq, mesa-vulkan-drivers (or Mesa GL). Takes ~40 s.
set -euo pipefail
cd "$(dirname "$0")/../.."

# shellcheck source=lib/binary.sh
. .ci/checks/lib/binary.sh
for tool in Xvfb xdotool import compare convert jq; do
  command -v "$tool" >/dev/null || { echo "window-devices check: $tool is missing (apt-get install xvfb xdotool imagemagick jq)"; exit 1; }
done
CONVERT=/usr/bin/convert
[ -x "$CONVERT" ] || CONVERT=convert

WORK="$(mktemp -d /tmp/nendo-window-devices.XXXXXX)"
XVFB_PID=""
APP_PID=""
TRACKER_PID=""
GLOVE_PID=""
cleanup() {
  for pid in "$APP_PID" "$TRACKER_PID" "$GLOVE_PID"; do
    [ -n "$pid" ] && kill "$pid" 2>/dev/null || true
  done
  [ -n "$XVFB_PID" ] && kill "$XVFB_PID" 2>/dev/null || true
  wait 2>/dev/null || true
  [ -n "${KEEP_SHOTS:-}" ] && cp "$WORK"/*.png "$KEEP_SHOTS"/ 2>/dev/null || true
  rm -rf "$WORK"
}
trap cleanup EXIT
fail() {
  echo "window-devices check FAILED: $*"
  echo "--- status"; cat "$WORK/status.json" 2>/dev/null || true
  echo "--- app log"; cat "$WORK/app.log" 2>/dev/null || true
  for e in tracker glove; do echo "--- $e emulator"; cat "$WORK/$e.log" 2>/dev/null || true; done
  exit 1
}

# shellcheck source=lib/xvfb.sh
. .ci/checks/lib/xvfb.sh
start_xvfb
# Private settings and profile folder: the check never reads or writes the user's.
export XDG_CONFIG_HOME="$WORK/config"
export NENDO_STATUS_FILE="$WORK/status.json"

# The shipped glove + tracker profile on the emulators' fixed paths, its scale fitted to the
# default plane (the hand 4 sides long; the finger radius follows it: 1 side).
jq --arg g "$WORK/glove.tty" --arg t "$WORK/tracker.tty" '
    .name = "check" | .input.devices.glove.port = $g | .input.devices.tracker.port = $t
    | .world_from_tracker.translation = [0, 0, 0] | .world_from_tracker.scale = 21.5' \
  devices/profiles/cyberglove2-18-fastrak.json >"$WORK/profile.json"

start_emulator() { # role device
  "$BIN" emulate "$2" --motion press --profile "$WORK/profile.json" --link "$WORK/$1.tty" \
    >"$WORK/$1.out" 2>"$WORK/$1.log" &
  local pid=$!
  # Known to the cleanup before anything can fail, so a failure never leaves it running
  # (the cleanup's `wait` would wait for it). Up to 30 s: a loaded machine is slow to start it.
  if [ "$1" = tracker ]; then TRACKER_PID=$pid; else GLOVE_PID=$pid; fi
  for _ in $(seq 300); do [ -s "$WORK/$1.out" ] && break; sleep 0.1; done
  [ "$(head -n1 "$WORK/$1.out" 2>/dev/null)" = "$WORK/$1.tty" ] || fail "the $1 emulator did not print its port"
}
# status JQ-FILTER: the filter's value on the window's status (false when there is none yet).
status() { jq -e "$1" "$WORK/status.json" >/dev/null 2>&1; }
wait_status() { # seconds description jq-filter
  for _ in $(seq $(( $1 * 4 ))); do status "$3" && return 0; sleep 0.25; done
  fail "$2 (waited $1 s)"
}
state() { jq -r --arg r "$1" '.devices[] | select(.role == $r) | .state' "$WORK/status.json"; }
# The 3D view: right of the 290-point tool panel, left of the 330-point Devices panel.
view_shot() { # name
  import -window "$WID" "$WORK/$1-full.png"
  "$CONVERT" "$WORK/$1-full.png" -crop "$(( WIDTH - 650 ))x$(( HEIGHT - 100 ))+300+40" +repage "$WORK/$1.png"
}
differ() { # a b → pixels that differ by more than 5 %
  local d
  d="$(compare -metric AE -fuzz 5% "$WORK/$1.png" "$WORK/$2.png" null: 2>&1 || true)"
  echo "${d%% *}"
}

START=$SECONDS
# --- 1: the window connects with both devices off.
"$BIN" --profile "$WORK/profile.json" --autosave "$WORK/autosave.nendo.json" --no-recover \
  >"$WORK/app.log" 2>&1 &
APP_PID=$!
WID="$(timeout 60 xdotool search --sync --name '^nendo' | head -n1)" || fail "no window appeared within 60 s"
eval "$(xdotool getwindowgeometry --shell "$WID")"   # WIDTH, HEIGHT
wait_status 30 "the window did not connect with both devices off" \
  '.session == "devices" and ([.devices[] | select(.state == "disconnected" and (.last_error | type) == "string")] | length) == 2'
echo "both devices off: Connect started, glove $(state glove), tracker $(state tracker)"
sleep 1
view_shot before

# --- 2: the devices come with Space held (the clutch): both Ok, the hand drawn, and no
# contact through two whole press gestures (3 s each). Space let go: the next press is shown
# (the clay's displacement under it, the contact feedback) and deforms the clay.
xdotool windowfocus --sync "$WID"
xdotool keydown space
start_emulator tracker fastrak
start_emulator glove cyberglove
wait_status 30 "the devices did not both reach Ok" \
  '([.devices[] | select(.state == "ok" and .last_error == null)] | length) == 2'
echo "emulators started: glove $(state glove), tracker $(state tracker), no error"
wait_status 15 "the hand was not drawn" '.hand_drawn == true'
wait_status 5 "Space held did not clutch the hand" '.clutched == true'
sleep 6.5
status '.clutched == true and .contacts == 0' || { xdotool keyup space; fail "the hand touched the clay while Space was held"; }
xdotool keyup space
echo "clutch: 6.5 s of press gestures with Space held, no contact"
wait_status 5 "Space let go did not release the clutch" '.clutched == false'
wait_status 20 "no contact feedback while pressing" '.clay_moved != null and .clay_moved > 0.05'
echo "contact feedback: the clay moved $(jq .clay_moved "$WORK/status.json") sides under the press"
wait_status 20 "the press gesture made no contact" '.contacts >= 1'
wait_status 10 "the window shows no hand latency figure" \
  '.latency.samples > 0 and .latency.cpu_median_ms >= 0 and .latency.cpu_p95_ms >= .latency.cpu_median_ms'
echo "hand latency (median / p95 of $(jq -r .latency.samples "$WORK/status.json") samples):" \
  "CPU $(jq -r '"\(.latency.cpu_median_ms) / \(.latency.cpu_p95_ms)"' "$WORK/status.json") ms," \
  "shown $(jq -r '"\(.latency.presented_median_ms) / \(.latency.presented_p95_ms)"' "$WORK/status.json") ms;" \
  "each frame's newest sample: CPU $(jq -r '"\(.latency.newest_cpu_median_ms) / \(.latency.newest_cpu_p95_ms)"' "$WORK/status.json") ms," \
  "shown $(jq -r '"\(.latency.newest_presented_median_ms) / \(.latency.newest_presented_p95_ms)"' "$WORK/status.json") ms"
sleep 1.5
view_shot pressed
pressed="$(differ before pressed)"
awk -v d="$pressed" 'BEGIN { exit !(d + 0 > 2000) }' || fail "the hand and the dent did not change the view ($pressed pixels)"
# The clay itself (the hand hides the dent from this view): the autosave against the plane.
"$BIN" sculpt --primitive plane --out "$WORK/plane.json" 2>/dev/null
deviation=0
for _ in $(seq 40); do
  if [ -s "$WORK/autosave.nendo.json" ]; then
    deviation="$("$BIN" check "$WORK/autosave.nendo.json" --against "$WORK/plane.json" 2>/dev/null | jq '.deviation.max' || echo 0)"
    awk -v d="$deviation" 'BEGIN { exit !(d + 0 > 0.01) }' && break
  fi
  sleep 0.25
done
awk -v d="$deviation" 'BEGIN { exit !(d + 0 > 0.01) }' || fail "the autosaved clay is still the plane (deviation $deviation)"
echo "hand drawn, clay pressed: $(jq .contacts "$WORK/status.json") contact(s), $pressed pixels of the view changed, the autosave $deviation sides from the plane"

# --- 3: the glove goes away.
kill "$GLOVE_PID"
wait "$GLOVE_PID" 2>/dev/null || true
GLOVE_PID=""
wait_status 15 "the glove did not read Disconnected" \
  '.devices[] | select(.role == "glove") | .state == "disconnected" and (.last_error | type) == "string"'
echo "glove emulator stopped: glove $(state glove) ($(jq -r '.devices[] | select(.role == "glove") | .last_error' "$WORK/status.json")), tracker $(state tracker)"

# --- 4: and comes back on the same path.
start_emulator glove cyberglove
wait_status 20 "the glove did not come back Ok without its error" \
  '.devices[] | select(.role == "glove") | .state == "ok" and .last_error == null'
status '.devices[] | select(.role == "tracker") | .state == "ok"' || fail "the tracker is not Ok any more"
view_shot back
echo "glove emulator restarted: glove $(state glove), no stale error; tracker $(state tracker)"
echo "window-devices check passed in $(( SECONDS - START )) s"

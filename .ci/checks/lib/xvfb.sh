# Sourced by the window checks (not run on its own: .ci/run runs only .ci/checks/*.sh).
# start_xvfb: a private XDG runtime/state directory under $WORK and a virtual X display
# (Xvfb picks a free display and writes its number to fd 3); exports DISPLAY and sets
# XVFB_PID. Needs $WORK and a fail() function.
start_xvfb() {
  export XDG_RUNTIME_DIR="$WORK/xdg"
  mkdir -p "$XDG_RUNTIME_DIR" && chmod 700 "$XDG_RUNTIME_DIR"
  export XDG_STATE_HOME="$WORK/state"
  Xvfb -displayfd 3 -screen 0 1600x1000x24 -nolisten tcp 3>"$WORK/display" 2>"$WORK/xvfb.log" &
  XVFB_PID=$!
  for _ in $(seq 100); do [ -s "$WORK/display" ] && break; sleep 0.1; done
  [ -s "$WORK/display" ] || fail "Xvfb did not start"
  DISPLAY=":$(head -n1 "$WORK/display")"
  export DISPLAY
}

"""The window class of the crash hunt (`scripts/crash-hunt.py --only window`).

Each case starts the real window under one private Xvfb display with mutated files — the model
it opens, `settings.json`, the autosave slots a killed window left, a trace played by a replay
profile (`--profile`) — drives it with xdotool for a few seconds (random moves, clicks, drags,
wheel turns and keys over the 3D view and the panels) and kills it with SIGKILL at a random
moment. Oracles, checked after the kill:

- no panic, abort or allocation failure in its standard error;
- the window either ran until the kill or ended by itself with status 0, or 1 / 2 with a
  message (never 101 or a signal of its own);
- every autosave slot left is a readable model (`nendo check` exits 0; a slot the case planted
  and the window did not touch may stay as it was);
- `settings.json` is parseable JSON, or the bytes the case gave it (a corrupt file the window
  kept aside or left alone).

A wrong outcome is reported and saved (the case's files, stderr, the actions taken) under
`--out` as `window-NNN/`. Needs Xvfb and xdotool (Debian: `apt-get install xvfb xdotool`) and a
Vulkan or GL driver for the window (Mesa's lavapipe / llvmpipe).
"""

import json
import os
import random
import shutil
import signal
import subprocess
import tempfile
import time

KEYS = [
    "z", "ctrl+z", "ctrl+y", "ctrl+shift+z", "Home", "F1", "question", "Escape", "Return", "Tab",
    "x", "shift+x", "e", "g", "1", "2", "3", "4", "5", "6", "7", "8", "9", "f", "shift+f",
    "space", "Delete", "BackSpace", "a", "ctrl+s", "ctrl+o", "Left", "Right", "Up", "Down",
]

SETTINGS_SEEDS = [
    {"format": "nendo-settings", "version": 1, "brush": {"falloff": "soft", "strength": 0.5, "radius": 1.5}},
    {"format": "nendo-settings", "version": 1},
    {"format": "nendo-settings", "version": 1, "brush": {"falloff": "flat", "strength": 1.0, "radius": 0.3}, "orbit": "middle"},
]


def _start_xvfb(work):
    """A private X display; returns (process, DISPLAY)."""
    # Xvfb picks a free display and writes its number to the descriptor given.
    r, w = os.pipe()
    p = subprocess.Popen(
        ["Xvfb", "-displayfd", str(w), "-screen", "0", "1600x1000x24", "-nolisten", "tcp"],
        stdout=subprocess.DEVNULL, stderr=open(os.path.join(work, "xvfb.log"), "wb"), pass_fds=(w,),
    )
    os.close(w)
    num = b""
    deadline = time.monotonic() + 15
    os.set_blocking(r, False)
    while time.monotonic() < deadline and not num.endswith(b"\n"):
        try:
            chunk = os.read(r, 64)
            if not chunk:
                break
            num += chunk
        except BlockingIOError:
            time.sleep(0.05)
    os.close(r)
    if not num.strip():
        p.kill()
        raise RuntimeError("Xvfb did not start (see xvfb.log)")
    return p, ":" + num.decode().strip()


def _xdo(env, *args, timeout=5):
    try:
        return subprocess.run(["xdotool", *args], env=env, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None


def _mutate_settings(rng, mutate_json_text):
    seed = rng.choice(SETTINGS_SEEDS)
    r = rng.random()
    if r < 0.25:
        return json.dumps(seed).encode()
    if r < 0.3:
        return b"\x00" * rng.choice([0, 1, 100])
    return mutate_json_text(rng, seed)


def gen_window(rng, seeds, mutate_json_text, mutate_lines, mutate_line_json_or_tokens):
    """One window case: files (relative names -> bytes), argv extras, actions, kill time."""
    files = {}
    argv = []
    notes = []
    # the model opened
    if rng.random() < 0.6:
        data = rng.choice(seeds.models)
        if rng.random() < 0.6:
            data = mutate_json_text(rng, data)
            notes.append("mutated model")
        files["model.json"] = data
        argv.append("{d}/model.json")
    # settings.json
    if rng.random() < 0.8:
        files["config/nendo/settings.json"] = _mutate_settings(rng, mutate_json_text)
    # autosave slots a killed window left (recovery is offered at the start)
    autosave_mode = rng.choice(["default", "default", "given", "none"])
    if autosave_mode == "given":
        argv += ["--autosave", "{d}/auto.nendo.json"]
        base = "auto.nendo.json"
    elif autosave_mode == "default":
        base = "state/nendo/autosave.nendo.json"
    else:
        argv.append("--no-autosave")
        base = None
    if base and rng.random() < 0.5:
        for k in rng.sample([1, 2, 3], rng.choice([1, 1, 2])):
            name = base if k == 1 else base.replace("autosave.nendo.json", f"autosave-{k}.nendo.json").replace("auto.nendo.json", f"auto-{k}.nendo.json")
            data = rng.choice(seeds.models)
            if rng.random() < 0.6:
                data = mutate_json_text(rng, data)
            files[name] = data
    if rng.random() < 0.3:
        argv.append("--no-recover")
    # a trace played through a replay profile
    if rng.random() < 0.3:
        trace = rng.choice(sorted(seeds.traces.values()))
        if rng.random() < 0.7:
            trace = mutate_lines(rng, trace, mutate_line_json_or_tokens)
        files["t.trace"] = trace
        profile = {"format": "nendo-device-profile", "version": 1, "name": "hunt-replay",
                   "input": {"replay": {"trace": "{d}/t.trace", "speed": rng.choice([1.0, 4.0, 40.0])}}}
        pdata = json.dumps(profile).encode()
        if rng.random() < 0.2:
            pdata = mutate_json_text(rng, pdata)
        files["replay.json"] = pdata
        argv += ["--profile", "{d}/replay.json"]
    seconds = rng.uniform(1.5, 5.0)
    actions = []
    t = 0.0
    while t < seconds:
        kind = rng.choice(["move", "click", "click", "drag", "drag", "wheel", "key", "key", "key"])
        x, y = rng.randrange(0, 1600), rng.randrange(0, 1000)
        if kind == "move":
            actions.append(("move", x, y))
        elif kind == "click":
            actions.append(("click", x, y, rng.choice([1, 1, 1, 2, 3])))
        elif kind == "drag":
            path = [(x + rng.randrange(-200, 200), y + rng.randrange(-200, 200)) for _ in range(rng.randrange(2, 6))]
            mods = rng.choice([None, None, "ctrl", "shift"])
            actions.append(("drag", x, y, rng.choice([1, 1, 2, 3]), path, mods))
        elif kind == "wheel":
            actions.append(("wheel", x, y, rng.choice([4, 5]), rng.randrange(1, 5)))
        else:
            actions.append(("key", rng.choice(KEYS)))
        t += rng.uniform(0.05, 0.4)
    kill_at = rng.uniform(0.3, seconds)
    return {"files": files, "argv": argv, "actions": actions, "kill_at": kill_at, "autosave": base, "notes": notes}


def _act(env, a):
    k = a[0]
    if k == "move":
        _xdo(env, "mousemove", str(a[1]), str(a[2]))
    elif k == "click":
        _xdo(env, "mousemove", str(a[1]), str(a[2]))
        _xdo(env, "click", str(a[3]))
    elif k == "drag":
        _, x, y, button, path, mods = a
        _xdo(env, "mousemove", str(x), str(y))
        if mods:
            _xdo(env, "keydown", mods)
        _xdo(env, "mousedown", str(button))
        for px, py in path:
            _xdo(env, "mousemove", str(max(0, px)), str(max(0, py)))
            time.sleep(0.03)
        _xdo(env, "mouseup", str(button))
        if mods:
            _xdo(env, "keyup", mods)
    elif k == "wheel":
        _xdo(env, "mousemove", str(a[1]), str(a[2]))
        _xdo(env, "click", "--repeat", str(a[4]), str(a[3]))
    elif k == "key":
        _xdo(env, "key", a[1])


def _check_model(binary, path, env):
    r = subprocess.run([binary, "check", path], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, timeout=60)
    return r.returncode, r.stderr.decode(errors="replace")


def run_window_case(cfg, case, display):
    """Runs one window case; returns (violations list, stderr bytes, outcome text)."""
    d = tempfile.mkdtemp(prefix="w", dir=cfg.work)
    for name, data in case["files"].items():
        p = os.path.join(d, name)
        os.makedirs(os.path.dirname(p), exist_ok=True)
        data = data.replace(b"{d}", d.encode()) if name == "replay.json" else data
        with open(p, "wb") as f:
            f.write(data)
    os.makedirs(os.path.join(d, "xdg"), mode=0o700, exist_ok=True)
    env = dict(cfg.env)
    env.update({
        "DISPLAY": display,
        "XDG_RUNTIME_DIR": os.path.join(d, "xdg"),
        "XDG_STATE_HOME": os.path.join(d, "state"),
        "XDG_CONFIG_HOME": os.path.join(d, "config"),
        "HOME": d,
        "RUST_BACKTRACE": "1",
    })
    argv = [cfg.binary] + [a.replace("{d}", d) for a in case["argv"]]
    err_path = os.path.join(d, "stderr.txt")
    planted = {n: v for n, v in case["files"].items()}
    with open(err_path, "wb") as err:
        p = subprocess.Popen(argv, env=env, stdout=subprocess.DEVNULL, stderr=err, cwd=d, start_new_session=True)
    t0 = time.monotonic()
    # wait for the window (or the process's end)
    wid = None
    while time.monotonic() - t0 < 30 and p.poll() is None:
        r = _xdo(env, "search", "--pid", str(p.pid), timeout=3)
        if r is not None and r.stdout.strip():
            wid = r.stdout.split()[0].decode()
            break
        time.sleep(0.2)
    killed = False
    if wid is not None:
        _xdo(env, "windowactivate", wid)
        time.sleep(0.3)
        start = time.monotonic()
        for a in case["actions"]:
            if time.monotonic() - start >= case["kill_at"] or p.poll() is not None:
                break
            _act(env, a)
        while time.monotonic() - start < case["kill_at"] and p.poll() is None:
            time.sleep(0.05)
    if p.poll() is None:
        os.killpg(p.pid, signal.SIGKILL)
        killed = True
    rc = p.wait()
    # release any key or button xdotool may have left down
    for m in ("ctrl", "shift"):
        _xdo(env, "keyup", m)
    for b in ("1", "2", "3"):
        _xdo(env, "mouseup", b)
    with open(err_path, "rb") as f:
        err = f.read()
    violations = []
    for needle in (b"panicked", b"memory allocation of", b"stack backtrace", b"RUST_BACKTRACE", b"Aborted"):
        if needle in err:
            violations.append(f"stderr holds {needle.decode()!r}")
    if not killed:
        if rc < 0:
            violations.append(f"the window died by signal {-rc}")
        elif rc not in (0, 1, 2):
            violations.append(f"the window exited with status {rc}")
        elif rc != 0 and not err.strip():
            violations.append(f"the window exited with status {rc} and no message")
        elif wid is None and rc == 0:
            violations.append("the window exited with status 0 before showing itself")
    elif wid is None:
        violations.append("no window within 30 s (killed)")
    # autosave slots: each a readable model, or the planted bytes untouched
    base = case["autosave"]
    checked = 0
    if base:
        folder = os.path.join(d, os.path.dirname(base))
        if os.path.isdir(folder):
            for n in sorted(os.listdir(folder)):
                if not n.endswith(".nendo.json"):
                    continue
                rel = os.path.join(os.path.dirname(base), n)
                path = os.path.join(folder, n)
                with open(path, "rb") as f:
                    now = f.read()
                if planted.get(rel) == now:
                    continue
                code, msg = _check_model(cfg.binary, path, env)
                checked += 1
                if code != 0:
                    violations.append(f"autosave {rel} is not a readable model after the kill: {msg.strip()[-300:]}")
    settings = os.path.join(d, "config", "nendo", "settings.json")
    if os.path.exists(settings):
        with open(settings, "rb") as f:
            now = f.read()
        if now != planted.get("config/nendo/settings.json"):
            try:
                json.loads(now)
            except ValueError as e:
                violations.append(f"settings.json is not JSON after the run: {e}")
    outcome = f"{'killed' if killed else f'exit {rc}'}{'' if wid else ', no window'}, {time.monotonic() - t0:.1f} s"
    if checked:
        outcome += f", {checked} autosave{'s' if checked > 1 else ''} written and checked"
    if not killed and err.strip():
        outcome += ": " + err.decode(errors="replace").strip().splitlines()[-1][:160]
    return violations, err, outcome, d


def save_window_repro(cfg, idx, case, violations, err, d):
    out = os.path.join(cfg.out, f"window-{idx:03d}")
    if os.path.exists(out):
        shutil.rmtree(out)
    shutil.copytree(d, out, symlinks=True, ignore=shutil.ignore_patterns("xdg"))
    with open(os.path.join(out, "case.json"), "w") as f:
        json.dump({"argv": case["argv"], "actions": case["actions"], "kill_at": case["kill_at"],
                   "violations": violations, "id": case.get("id")}, f, indent=1)
    return out


def run_window_hunt(cfg, seeds, count, mutators, stop_flag=None):
    """Runs `count` window cases one after another on one Xvfb; returns (ran, found) where
    found is a list of (case id, violations, reproducer directory)."""
    mutate_json_text, mutate_lines, mutate_line_json_or_tokens = mutators
    for tool in ("Xvfb", "xdotool"):
        if shutil.which(tool) is None:
            raise RuntimeError(f"the window class needs {tool} (apt-get install xvfb xdotool)")
    xvfb, display = _start_xvfb(cfg.work)
    found = []
    ran = 0
    outcomes = {}
    try:
        for i in range(count):
            if stop_flag is not None and stop_flag.is_set():
                break
            rng = random.Random(f"{cfg.seed}:window:{i}")
            case = gen_window(rng, seeds, mutate_json_text, mutate_lines, mutate_line_json_or_tokens)
            case["id"] = f"window:{i}"
            violations, err, outcome, d = run_window_case(cfg, case, display)
            ran += 1
            kind = outcome.split(",")[0].split(":")[0]
            outcomes[kind] = outcomes.get(kind, 0) + 1
            if "written and checked" in outcome:
                outcomes["with an autosave checked"] = outcomes.get("with an autosave checked", 0) + 1
            print(f"  window:{i}: {outcome}" + (f"  VIOLATION: {'; '.join(violations)}" if violations else ""), flush=True)
            if violations:
                repro = save_window_repro(cfg, len(found) + 1, case, violations, err, d)
                found.append((case["id"], violations, repro))
            shutil.rmtree(d, ignore_errors=True)
    finally:
        xvfb.kill()
        xvfb.wait()
    return ran, found, outcomes

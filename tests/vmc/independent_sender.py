#!/usr/bin/env python3
"""nendo's VMC receiver against an independent sender: PyPI's python-osc.

For each hand (the shipped `vmc` profile for the right hand, a copy with `"side": "left"`
for the left), `nendo record --vmc-listen` records while this script sends VMC bundles of a
known skeleton — a humanoid with straight arms and identity rotations, the hand turned so
its index points down — lowered until the index tip is 0.3 side into the default plane and
raised again, at 60 bundles a second. Then:

- at least 90 % of the gesture's bundles are in the trace, each joint the bundle gives (the
  wrist and the fingers' proximal, intermediate and distal joints) within 1e-5 m of the pose
  composed here (this script's own composition and Unity -> nendo conversion, from the float32
  numbers sent), the made index tip too (distal joint + the hand's distal length along the
  intermediate -> distal direction);
- a bundle missing a bone (sent first, before the bone ever came), one with a NaN, a truncated bundle, garbage and a flood of 10x the
  rate (600 bundles a second for a second) are counted in record's summary, and the recording
  goes on (a marker bundle sent after them is in the trace);
- `nendo replay` of the trace leaves a dent 0.30 +- 0.03 deep whose deepest point is within
  0.1 side of the expected tip position.

Usage: independent_sender.py NENDO_BINARY REPO_ROOT WORK_DIR [--throughput]
(--throughput: also send as fast as possible for 3 s and print packets/s and record's CPU.)
Exit status 0 when every check holds; a failed check names itself.
"""

import json
import math
import os
import signal
import socket
import struct
import subprocess
import sys
import time

try:
    from pythonosc.osc_bundle_builder import IMMEDIATELY, OscBundleBuilder
    from pythonosc.osc_message_builder import OscMessageBuilder
except ImportError:
    sys.exit("vmc check FAILED: the PyPI package python-osc is not installed "
             "(pip install python-osc; .ci/checks/vmc.sh installs it in its cached venv)")

RATE_HZ = 60.0
TOLERANCE_M = 1e-5


def fail(message):
    sys.exit(f"vmc check FAILED: {message}")


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


# Quaternions as (x, y, z, w).
def qmul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz)


def qrot(q, v):
    x, y, z, w = q
    vx, vy, vz = v
    # v + 2w (u x v) + 2 u x (u x v), u the vector part
    cx, cy, cz = y * vz - z * vy, z * vx - x * vz, x * vy - y * vx
    ccx, ccy, ccz = y * cz - z * cy, z * cx - x * cz, x * cy - y * cx
    return (vx + 2 * (w * cx + ccx), vy + 2 * (w * cy + ccy), vz + 2 * (w * cz + ccz))


def add(a, b):
    return tuple(p + q for p, q in zip(a, b))


def sub(a, b):
    return tuple(p - q for p, q in zip(a, b))


def scale(a, s):
    return tuple(p * s for p in a)


def norm(a):
    return math.sqrt(sum(p * p for p in a))


def unity_to_nendo(p):
    return (p[0], p[2], p[1])


ID = (0.0, 0.0, 0.0, 1.0)
FINGERS = {  # Unity offsets: proximal from the hand, then intermediate, distal (metres)
    "Index": (0.025, (0.095, 0.040, 0.023)),
    "Middle": (0.0, (0.095, 0.045, 0.027)),
    "Ring": (-0.02, (0.09, 0.042, 0.026)),
    "Little": (-0.04, (0.085, 0.033, 0.019)),
}
# nendo's default hand (devices/src/profile/hand.rs): the index's distal length.
INDEX_DISTAL_M = 0.018


def skeleton(side):
    """The known skeleton: (name, parent, local position, local rotation), Unity frame."""
    s = 1.0 if side == "right" else -1.0
    half = math.sqrt(0.5)
    # The hand turned about Unity's Z so the fingers point down (-Y).
    down = (0.0, 0.0, -half, half) if side == "right" else (0.0, 0.0, half, half)
    bones = [("Hips", None, (0.0, 1.0, 0.0), ID), ("Spine", "Hips", (0.0, 0.1, 0.0), ID),
             ("Chest", "Spine", (0.0, 0.1, 0.0), ID),
             ("UpperChest", "Chest", (0.0, 0.1, 0.0), ID)]
    for name, sign in (("Right", 1.0), ("Left", -1.0)):
        ours = (name == "Right") == (side == "right")

        def b(bone, parent, x, y, z, q=ID):
            # Every parent is on the same side, but the shoulder's (the upper chest).
            parent = parent if parent == "UpperChest" else name + parent
            bones.append((name + bone, parent, (sign * x, y, z), q))
        b("Shoulder", "UpperChest", 0.05, 0.12, 0.0)
        b("UpperArm", "Shoulder", 0.10, 0.0, 0.0)
        b("LowerArm", "UpperArm", 0.28, 0.0, 0.0)
        b("Hand", "LowerArm", 0.25, 0.0, 0.0, down if ours else ID)
        b("ThumbProximal", "Hand", 0.02, -0.01, 0.025)
        b("ThumbIntermediate", "ThumbProximal", 0.03, 0.0, 0.02)
        b("ThumbDistal", "ThumbIntermediate", 0.03, 0.0, 0.0)
        for finger, (z, (l1, l2, l3)) in FINGERS.items():
            b(finger + "Proximal", "Hand", l1, 0.0, z)
            b(finger + "Intermediate", finger + "Proximal", l2, 0.0, 0.0)
            b(finger + "Distal", finger + "Intermediate", l3, 0.0, 0.0)
    # Every number as it goes on the wire (float32).
    return [(n, p, tuple(map(f32, pos)), tuple(map(f32, q))) for n, p, pos, q in bones]


def compose(bones, root):
    """World poses (Unity frame) of every bone: p = p_parent + R_parent p_local."""
    table = {n: (p, pos, q) for n, p, pos, q in bones}
    world = {}

    def get(n):
        if n in world:
            return world[n]
        parent, pos, q = table[n]
        pp, pq = root if parent is None else get(parent)
        world[n] = (add(pp, qrot(pq, pos)), qmul(pq, q))
        return world[n]
    for n in table:
        get(n)
    return world


# Unity bone (without the side) -> the trace's joint index (OpenXR order).
JOINTS = {"Hand": 1, "ThumbProximal": 2, "ThumbIntermediate": 3, "ThumbDistal": 4,
          "IndexProximal": 7, "IndexIntermediate": 8, "IndexDistal": 9,
          "MiddleProximal": 12, "MiddleIntermediate": 13, "MiddleDistal": 14,
          "RingProximal": 17, "RingIntermediate": 18, "RingDistal": 19,
          "LittleProximal": 22, "LittleIntermediate": 23, "LittleDistal": 24}
INDEX_TIP = 10


def expected_joints(bones, root, side):
    """Joint index -> position (metres, nendo's tracker frame), measured ones and the index tip."""
    prefix = "Right" if side == "right" else "Left"
    world = compose(bones, root)
    out = {j: unity_to_nendo(world[prefix + b][0]) for b, j in JOINTS.items()}
    inter, distal = out[8], out[9]
    d = sub(distal, inter)
    out[INDEX_TIP] = add(distal, scale(d, INDEX_DISTAL_M / norm(d)))
    return out


def message(address, *args):
    m = OscMessageBuilder(address=address)
    for a in args:
        if isinstance(a, str):
            m.add_arg(a)
        elif isinstance(a, int):
            m.add_arg(a, "i")
        else:
            m.add_arg(a, "f")
    return m.build()


def bundle(bones, root, drop=None, nan=None):
    b = OscBundleBuilder(IMMEDIATELY)
    b.add_content(message("/VMC/Ext/Root/Pos", "root", *root[0], *root[1]))
    for name, _, pos, q in bones:
        if name == drop:
            continue
        pos = (float("nan"), pos[1], pos[2]) if name == nan else pos
        b.add_content(message("/VMC/Ext/Bone/Pos", name, *pos, *q))
    b.add_content(message("/VMC/Ext/OK", 1))
    b.add_content(message("/VMC/Ext/T", f32(time.monotonic() % 1000.0)))
    return b.build().dgram


def free_port():
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def read_trace(path):
    """(header dict, frames: list of {joint index: (flag, position)} or None)."""
    header, frames = {}, []
    with open(path) as f:
        lines = f.read().splitlines()
    # Version 3 brought skeleton frames; version 4 the gate's marks (a `marks held` header line,
    # a `held=` field after a frame's columns), written by every gated recorder.
    if not lines or lines[0] not in ("nendo-hand-trace 3", "nendo-hand-trace 4"):
        fail(f"{path}: not a version-3 or -4 trace: {lines[:1]}")
    it = iter(lines[1:])
    for line in it:
        if line == "frames":
            break
        key, _, rest = line.partition(" ")
        header[key] = rest
    for line in it:
        if line.startswith("end "):
            break
        words = [w for w in line.split() if "=" not in w]
        s = words.index("S")
        rest = words[s + 1:]
        if rest == ["-"]:
            frames.append(None)
            continue
        joints, k = {}, 0
        for j in range(26):
            if rest[k] == "-":
                k += 1
                continue
            flag = rest[k]
            pos = tuple(float(x) for x in rest[k + 1:k + 4])
            joints[j] = (flag, pos)
            k += 9
        frames.append(joints)
    return header, frames


def bezier_point(patch, u, v):
    bu = [(1 - u) ** 3, 3 * u * (1 - u) ** 2, 3 * u * u * (1 - u), u ** 3]
    bv = [(1 - v) ** 3, 3 * v * (1 - v) ** 2, 3 * v * v * (1 - v), v ** 3]
    p = [0.0, 0.0, 0.0]
    for i in range(4):
        for j in range(4):
            w = bu[i] * bv[j]
            c = patch[4 * i + j]
            p[0] += w * c[0]
            p[1] += w * c[1]
            p[2] += w * c[2]
    return p


def deepest_near(model_path, x, y, radius):
    with open(model_path) as f:
        model = json.load(f)
    best = None
    for patch in model["surface"]["patches"]:
        xs = [c[0] for c in patch]
        ys = [c[1] for c in patch]
        if min(xs) > x + 1.5 or max(xs) < x - 1.5 or min(ys) > y + 1.5 or max(ys) < y - 1.5:
            continue
        n = 40
        for a in range(n + 1):
            for b in range(n + 1):
                p = bezier_point(patch, a / n, b / n)
                if math.hypot(p[0] - x, p[1] - y) <= radius and (best is None or p[2] < best[2]):
                    best = p
    return best


def run_side(nendo, repo, work, side, throughput):
    port = free_port()
    out = os.path.join(work, f"{side}.trace")
    if side == "right":
        profile = "vmc"
        with open(os.path.join(repo, "devices/profiles/vmc.json")) as f:
            wft = json.load(f)["world_from_tracker"]
    else:
        with open(os.path.join(repo, "devices/profiles/vmc.json")) as f:
            p = json.load(f)
        p["name"] = "vmc-left"
        p["hand"] = {"side": "left", "palm_length": 0.095, "palm_width": 0.085,
                     "thumb": {"proximal": 0.046, "middle": 0.032, "distal": 0.027},
                     "index": {"proximal": 0.040, "middle": 0.023, "distal": INDEX_DISTAL_M},
                     "middle": {"proximal": 0.045, "middle": 0.027, "distal": 0.019},
                     "ring": {"proximal": 0.042, "middle": 0.026, "distal": 0.019},
                     "pinky": {"proximal": 0.033, "middle": 0.019, "distal": 0.017}}
        profile = os.path.join(work, "vmc-left.json")
        with open(profile, "w") as f:
            json.dump(p, f)
        wft = p["world_from_tracker"]
    t, c = wft["translation"], wft["scale"]
    if wft["rotation_wxyz"] != [1.0, 0.0, 0.0, 0.0]:
        fail("this check expects the vmc profile's world_from_tracker without rotation")

    bones = skeleton(side)
    tip0 = expected_joints(bones, ((0.0, 0.0, 0.0), ID), side)[INDEX_TIP]
    target_xy = (1.0, 0.5)

    def root_for(depth):
        # world = t + c * tracker; tracker = (x, z, y) of Unity
        want = ((target_xy[0] - t[0]) / c, (target_xy[1] - t[1]) / c, (depth - t[2]) / c)
        d = sub(want, tip0)
        return (tuple(map(f32, (d[0], d[2], d[1]))), ID)

    cmd = [nendo, "record", "--profile", profile, "--vmc-listen", f"127.0.0.1:{port}",
           "--out", out, "--seconds", "120", "--primitive", "plane", "--finger", "index"]
    log = open(os.path.join(work, f"{side}-record.log"), "w+")
    rec = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT)
    try:
        deadline = time.monotonic() + 60
        while not os.path.exists(out):
            if rec.poll() is not None or time.monotonic() > deadline:
                log.seek(0)
                fail(f"{side}: nendo record did not start: {log.read()}")
            time.sleep(0.05)
        tx = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        dest = ("127.0.0.1", port)
        period = 1.0 / RATE_HZ
        clock = [time.monotonic()]

        def send(data, dt=period):
            clock[0] += dt
            pause = clock[0] - time.monotonic()
            if pause > 0:
                time.sleep(pause)
            tx.sendto(data, dest)

        high = root_for(2.0)
        prefix = "Right" if side == "right" else "Left"
        # First a bundle missing a bone of the hand: no hand can be composed (a bone keeps its
        # last pose until a new one comes, as senders may spread bones over datagrams, so the
        # gap shows only before the bone ever came).
        send(bundle(bones, high, drop=prefix + "IndexIntermediate"))
        for _ in range(10):
            send(bundle(bones, high))
        # The gesture: 1 side above the plane down to 0.3 into it, held, and up again.
        depths = [1.0 - 0.05 * k for k in range(27)]
        depths = depths + [depths[-1]] * 10 + depths[::-1]
        gesture = []
        for d in depths:
            root = root_for(d)
            send(bundle(bones, root))
            gesture.append(expected_joints(bones, root, side))
        # What a sender may do wrong.
        whole = bundle(bones, high)
        send(bundle(bones, high, nan=prefix + "Hand"))
        send(whole[: len(whole) // 2])
        send(b"\x00garbage that is no OSC")
        send(whole)
        # A flood: ten times the rate for a second.
        flood_sent = 0
        for _ in range(int(RATE_HZ * 10)):
            send(whole, period / 10)
            flood_sent += 1
        marker_root = root_for(3.0)
        time.sleep(0.2)
        send(bundle(bones, marker_root))
        marker = expected_joints(bones, marker_root, side)
        thr = None
        if throughput:
            rate = float(os.environ.get("VMC_THROUGHPUT_RATE", "0")) or None
            thr = measure_throughput(tx, dest, whole, rec.pid, rate)
        time.sleep(0.5)
        rec.send_signal(signal.SIGINT)
        try:
            rec.wait(timeout=60)
        except subprocess.TimeoutExpired:
            fail(f"{side}: nendo record did not stop on SIGINT")
    finally:
        if rec.poll() is None:
            rec.kill()
            rec.wait()
    log.seek(0)
    summary = log.read()
    if rec.returncode != 0:
        fail(f"{side}: nendo record exited {rec.returncode}: {summary}")

    header, frames = read_trace(out)
    if header.get("skeleton") != side:
        fail(f"{side}: the trace's skeleton line is {header.get('skeleton')!r}")
    hand = json.loads(header["hand"])
    if hand["side"] != side or abs(hand["index"]["distal"] - INDEX_DISTAL_M) > 1e-12:
        fail(f"{side}: the trace's hand is {hand}")
    hands = [f for f in frames if f]

    def matches(joints, want):
        return all(j in joints and max(abs(a - b) for a, b in zip(joints[j][1], p)) <= TOLERANCE_M
                   for j, p in want.items())

    # Each gesture bundle's wrist picks its frame; then every joint must agree.
    found, worst = 0, 0.0
    for want in gesture:
        wrist = want[1]
        hit = [f for f in hands if 1 in f and max(abs(a - b) for a, b in zip(f[1][1], wrist)) <= TOLERANCE_M]
        if not hit:
            continue
        f = hit[0]
        for j, p in want.items():
            if j not in f:
                fail(f"{side}: joint {j} missing from a recorded hand")
            worst = max(worst, max(abs(a - b) for a, b in zip(f[j][1], p)))
        if f[INDEX_TIP][0] != "d" or f[7][0] != "m":
            fail(f"{side}: the index tip must be marked made (d), its knuckle measured (m)")
        found += 1
    if worst > TOLERANCE_M:
        fail(f"{side}: a recorded joint is {worst:.2e} m from the composed pose (allowed {TOLERANCE_M})")
    share = found / len(gesture)
    if share < 0.9:
        fail(f"{side}: {found} of {len(gesture)} gesture bundles recorded ({share:.0%}, need 90 %)")
    if not any(matches(f, marker) for f in hands):
        fail(f"{side}: the bundle sent after the bad packets and the flood is not in the trace")

    # Counters in record's summary: "tracker: N records, R rejected, B bytes skipped, I invalid values, F faults".
    line = next((l for l in summary.splitlines() if l.startswith("tracker:")), None)
    if line is None:
        fail(f"{side}: no tracker line in record's summary: {summary}")
    nums = {}
    for part in line.split(":", 1)[1].split(","):
        words = part.split()
        nums[" ".join(words[1:])] = int(words[0])
    if nums.get("rejected", 0) < 2:
        fail(f"{side}: the truncated bundle and the garbage are not counted as rejected: {line}")
    if nums.get("invalid values", 0) < 1:
        fail(f"{side}: the NaN is not counted as an invalid value: {line}")
    if nums.get("faults", 0) < 2:
        fail(f"{side}: the bundles missing a bone (and the NaN one) are not counted as faults: {line}")

    model = os.path.join(work, f"{side}.json")
    r = subprocess.run([nendo, "replay", out, "--out", model], capture_output=True, text=True,
                       timeout=600)
    if r.returncode != 0:
        fail(f"{side}: nendo replay exited {r.returncode}: {r.stderr}")
    best = deepest_near(model, target_xy[0], target_xy[1], 1.0)
    if best is None:
        fail(f"{side}: no surface under the tip")
    depth = -best[2]
    off = math.hypot(best[0] - target_xy[0], best[1] - target_xy[1])
    if not (0.27 <= depth <= 0.33) or off > 0.1:
        fail(f"{side}: the dent is {depth:.4f} deep at {off:.4f} side from the tip (want 0.30 +- 0.03 within 0.1)")
    print(f"vmc {side}: {found}/{len(gesture)} gesture bundles recorded, joints within "
          f"{worst:.1e} m; flood of {flood_sent} bundles at {10 * RATE_HZ:.0f}/s; counters: {line.strip()}; "
          f"dent {depth:.4f} deep, {off:.4f} side from the tip")
    if thr:
        sent, dt, cpu = thr
        # Every datagram before the measurement decoded but the two refused ones.
        before = 1 + 10 + len(gesture) + 1 + 1 + flood_sent + 1
        got = nums.get("records", 0) - before
        dropped = next((l for l in summary.splitlines() if "dropped on overflow" in l), "")
        print(f"throughput: {sent / dt:.0f} bundles/s sent ({len(whole)} bytes each) for {dt:.1f} s, "
              f"{got / dt:.0f}/s received and decoded ({got} of {sent}); nendo record used "
              f"{cpu:.2f} s CPU ({100 * cpu / dt:.0f} % of a core); {dropped.strip()}")


def cpu_seconds(pid):
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def measure_throughput(tx, dest, data, pid, rate=None):
    """Sends `data` for 3 s, as fast as possible or at `rate` a second; (sent, seconds, the
    receiver's CPU seconds)."""
    cpu0, t0 = cpu_seconds(pid), time.monotonic()
    sent = 0
    while time.monotonic() - t0 < 3.0:
        tx.sendto(data, dest)
        sent += 1
        if rate:
            pause = t0 + sent / rate - time.monotonic()
            if pause > 0:
                time.sleep(pause)
        elif sent % 64 == 0:
            time.sleep(0.0005)
    dt = time.monotonic() - t0
    time.sleep(0.3)
    cpu = cpu_seconds(pid) - cpu0
    return sent, dt, cpu


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    if len(args) != 3:
        sys.exit(__doc__)
    nendo, repo, work = args
    for side in ("right", "left"):
        run_side(nendo, repo, work, side, "--throughput" in sys.argv and side == "right")
    print("vmc check passed: python-osc's bundles recorded, composed and replayed for both hands")


if __name__ == "__main__":
    main()

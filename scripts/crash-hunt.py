#!/usr/bin/env python3
"""Seeded crash hunt over every parser and subcommand of the `nendo` binary.

How to run (from the repository root, after `cargo build --release --bin nendo`):

    python3 scripts/crash-hunt.py                      # the full run: >= 80 000 inputs
    python3 scripts/crash-hunt.py --count 5000         # a quick look (scaled down)
    python3 scripts/crash-hunt.py --only sculpt,check  # some subcommands only
    python3 scripts/crash-hunt.py --replay-case curve:1234   # rerun one input, print it

Options: `--bin PATH` (default target/release/nendo), `--seed S` (default 1; the same seed and
count give the same inputs), `--count N` (total inputs, split over the subcommands in the
proportions of the last hunt; default 84 000), `--jobs J` (parallel workers, default 2),
`--timeout S` (per input, default 20 s), `--mem-gb G` (address-space limit per input, default 4),
`--out DIR` (reproducers, default target/crash-hunt/), `--max-seconds S` (stop starting inputs after S
seconds and report what ran; Ctrl+C does the same), `--no-shrink`. `render` and the PNG of `figure shape` need a
Vulkan driver (on Debian: `apt-get install -y mesa-vulkan-drivers libvulkan1`); XDG_RUNTIME_DIR
is set to a temporary directory.

Inputs: seeds come from the repository (tests/data/**, devices/profiles/*, devices/traces/* and
each of them as version 4 with the gate's `held=` marks, the
README's examples) and from valid inputs the binary generates (primitives, sculpted models);
mutations are byte flips, insertions, deletions, truncation, duplicated chunks, a BOM, UTF-8
garbage, numbers swapped for NaN / 1e308 / -0 / huge integers / strings, duplicated and unknown
members, deep nesting and huge arrays (bounded: one input stays below about 1 MB), deleted or
duplicated lines; and hostile command lines (huge / negative / NaN / 1e308 numbers; a directory,
/dev/full, a fifo, a symlink, a dangling symlink, a missing directory as paths; standard output
on /dev/full). `record` reads mutated device bytes from a pseudo-terminal given as its port.

What counts as a crash: exit code 101, "panicked" anywhere in stderr, death by a signal (SIGSEGV,
SIGABRT, e.g. an allocation failure under the address-space limit), a message of a failed
allocation, or the per-input timeout (reported separately as a hang). Exit codes 0, 1 and 2 with
a message are the expected answers to bad inputs. Crashes are deduplicated by panic location and
message (digits masked) or by signal; the first input of each kind is shrunk (lines, then byte
ranges, keeping the same kind) and saved under --out as a directory with the input files and a
`repro.sh` to rerun it. The exit status is 1 when any crash or hang was found, else 0.

Semantic files and bounded-input probes (`--only bounds`): endless inputs (/dev/zero as every
kind of file), batch lines over 16 MB, pictures and warps over their caps, saved ratios off
their points, meshes scaled to nothing, CAD scales out of range, `replay --out` onto the start
model its trace names, `morph` into an earlier run's directory, `emulate --link` over a user's
link. Each such case has an oracle run after the binary ends (is the model kept, the directory
unmixed, the link intact, the refusal named?); a wrong outcome is an "oracle violation",
reported and saved like a crash. Kills of `record` are covered by .ci/checks/record-survives.sh.

The window (`--only window`, `--window-count N`, default 40): scripts/crash_hunt_window.py starts
the real window under Xvfb with mutated model files, settings.json, autosave slots and replayed
traces, drives it with xdotool and kills it with SIGKILL at a random moment; its oracles (no
panic in stderr, an exit with a message, autosaves that `nendo check` reads, settings.json still
JSON) are in that file's doc. Needs Xvfb and xdotool; not part of the default run.

Counting: one input is one run of the binary, except `closest` and `curve`, where one input is
one request line and a run answers a batch of up to 8 lines (a crash is then shrunk to its line).
"""

import argparse
import json
import math
import os
import pty
import random
import re
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from concurrent.futures import ThreadPoolExecutor

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

# Share of the total per subcommand (the last hunt's mix, ~84 000 inputs).
SHARES = {
    "sculpt": 10359,
    "check": 13123,
    "render": 3993,
    "export": 6605,
    "replay": 9529,
    "closest": 3246,
    "curve": 8483,
    "figure": 10947,
    "morph": 3731,
    "devices": 4045,
    "record": 4182,
    "refine": 3000,
    "bounds": 1200,
}
DEFAULT_COUNT = 84000
BATCH_LINES = 8

# ---------------------------------------------------------------------------------------------
# JSON with raw tokens (NaN, 1e999, duplicated members) that json.dumps cannot write.


class Raw:
    """A token written verbatim into JSON text."""

    def __init__(self, text):
        self.text = text


class DupObj:
    """An object written with its members in order, duplicates allowed."""

    def __init__(self, items):
        self.items = items


def dump(v):
    """JSON text of v (dicts, lists, Raw, DupObj, scalars; NaN and infinities as bare tokens)."""
    table = {}

    def default(o):
        if isinstance(o, Raw):
            text = o.text
        elif isinstance(o, DupObj):
            text = "{" + ",".join(json.dumps(k) + ":" + dump(x) for k, x in o.items) + "}"
        else:
            raise TypeError(f"cannot write {type(o).__name__}")
        key = f"@@nendo-crash-hunt-raw-{len(table)}@@"
        table[json.dumps(key)] = text
        return key

    out = json.dumps(v, default=default, separators=(",", ":"))
    for k, text in table.items():
        out = out.replace(k, text, 1)
    return out


SPECIAL_NUMBERS = [
    "NaN", "nan", "Infinity", "-Infinity", "1e308", "-1e308", "1.7976931348623157e308",
    "-1.7976931348623157e308", "8.98846567431158e307", "1e999", "-1e999", "1e-320", "-0", "-0.0",
    "0", "1", "-1", "2", "3", "4", "5", "7", "9", "10", "16", "17", "255", "256", "65535", "65536",
    "65537", "4294967295", "4294967296", "2147483647", "-2147483648", "9223372036854775807",
    "9223372036854775808", "18446744073709551615", "18446744073709551616",
    "-9223372036854775809", "100000000000000000000000000000", "1e15", "1e-300", "0.5",
    "1e9", "1000000", "123456789.123456789", '"1"', '"NaN"', '""', "null", "true", "false",
    "[]", "{}", "[1]", "[[]]", '{"a":1}', "[0,0,0]", "[NaN,NaN,NaN]", "[1e308,1e308,1e308]",
]

UNICODE_GARBAGE = [
    "\u0000", "\ufeff", "\ud7ff", "\U0010ffff", "é", "粘土", "\u202e", "\\u0000", "\\ud800",
    "\\udfff", "\\uD83D\\uDE00", "\\", '"', "\n", "\r\n", "\t", "%s%n", "'", "<", "&amp;",
]

BYTE_GARBAGE = [
    b"\xff", b"\xfe\xff", b"\xc0\x80", b"\xed\xa0\x80", b"\xf4\x90\x80\x80", b"\x80", b"\xe2\x82",
    b"\x00", b"\xef\xbb\xbf", b"\xf0\x9f\x98", b"\x1b[2J",
]

NUM_RE = re.compile(rb"-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")
MAX_INPUT = 1 << 20


def rand_special(rng):
    return rng.choice(SPECIAL_NUMBERS)


def is_num(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def pick(rng, doc, pred=lambda x: True, stop=0.2):
    """A random (path, node) with pred(node), found by a random descent (cheap on big documents)."""
    for _ in range(40):
        path, node = (), doc
        while True:
            if isinstance(node, dict):
                kids = list(node.keys())
            elif isinstance(node, list):
                kids = node
            else:
                kids = None
            if pred(node) and (not kids or rng.random() < stop):
                return path, node
            if not kids:
                break
            k = rng.choice(kids) if isinstance(node, dict) else rng.randrange(len(node))
            path += (k,)
            node = node[k]
    return None


def get_at(v, path):
    for p in path:
        v = v[p]
    return v


def set_at(v, path, new):
    if not path:
        return new
    parent = get_at(v, path[:-1])
    parent[path[-1]] = new
    return v


def deep_copy(v):
    return json.loads(json.dumps(v))


def nest(rng, inner):
    depth = rng.choice([64, 128, 200, 257, 1000, 5000, 50000, 200000])
    opener, closer = rng.choice([("[", "]"), ('{"a":', "}")])
    return Raw(opener * depth + inner + closer * depth)


def mutate_value(rng, doc):
    """One structural mutation of a parsed JSON document; returns a value for dump()."""
    doc = deep_copy(doc)
    path, node = pick(rng, doc) or ((), doc)
    kind = rng.randrange(14)
    if kind <= 3:
        # a number (or anything) swapped for a special token
        if kind <= 2:
            path, node = pick(rng, doc, is_num) or (path, node)
        return set_at(doc, path, Raw(rand_special(rng)))
    if kind == 4:
        # unknown member
        found = pick(rng, doc, lambda x: isinstance(x, dict), stop=0.4)
        if found:
            found[1][rng.choice(["extra", "x", "op", "format", "version", "", "\u0000"])] = Raw(rand_special(rng))
        return doc
    if kind == 5:
        # duplicated member (same key twice, maybe with another value)
        found = pick(rng, doc, lambda x: isinstance(x, dict) and bool(x), stop=0.4)
        if found:
            path, node = found
            items = list(node.items())
            k, x = rng.choice(items)
            items.insert(rng.randrange(len(items) + 1), (k, Raw(rand_special(rng)) if rng.random() < 0.5 else x))
            return set_at(doc, path, DupObj(items))
        return doc
    if kind == 6:
        # deleted member or element
        if path:
            parent = get_at(doc, path[:-1])
            del parent[path[-1]]
        return doc
    if kind == 7:
        # deep nesting
        inner = dump(node) if rng.random() < 0.5 else "1"
        return set_at(doc, path, nest(rng, inner if len(inner) < 1000 else "1"))
    if kind == 8:
        # huge array, bounded in text size
        found = pick(rng, doc, lambda x: isinstance(x, list) and bool(x), stop=0.4) if rng.random() < 0.7 else None
        if found:
            path, node = found
            elem = dump(rng.choice(node))
        else:
            elem = dump(node) if isinstance(node, (list, dict)) and len(dump(node)) < 400 else rand_special(rng)
        n = rng.choice([0, 1, 2, 3, 100, 1000, 10000, 100000, 300000])
        n = max(0, min(n, (MAX_INPUT - 1000) // (len(elem) + 1)))
        return set_at(doc, path, Raw("[" + ",".join([elem] * n) + "]"))
    if kind == 9:
        # array elements duplicated / removed / truncated / reordered
        found = pick(rng, doc, lambda x: isinstance(x, list) and bool(x), stop=0.4)
        if found:
            node = found[1]
            r = rng.random()
            if r < 0.3:
                node[:] = node[: rng.randrange(len(node))]
            elif r < 0.6:
                i = rng.randrange(len(node))
                node.insert(i, deep_copy(node[i]))
            elif r < 0.8:
                node.reverse()
            else:
                rng.shuffle(node)
        return doc
    if kind == 10:
        # a string swapped for garbage
        found = pick(rng, doc, lambda x: isinstance(x, str), stop=1.0)
        if found:
            path, node = found
            s = rng.choice(
                [
                    "",
                    node[::-1],
                    node + rng.choice(UNICODE_GARBAGE),
                    node.upper(),
                    "x" * rng.choice([1, 100, 10000, 500000]),
                    rng.choice(UNICODE_GARBAGE) * 3,
                ]
            )
            return set_at(doc, path, s)
        return doc
    if kind == 11:
        # scale numbers of a subtree by a huge / tiny / negative factor
        f = rng.choice([1e300, -1.0, 1e-300, 1e10, 0.0, -1e308, 1e154, 3.0])

        def scale(x):
            if isinstance(x, bool):
                return x
            if isinstance(x, (int, float)):
                try:
                    y = float(x) * f
                except OverflowError:
                    y = float("inf")
                return y if math.isfinite(y) else Raw(rng.choice(["1e308", "-1e308", "1.7976931348623157e308"]))
            if isinstance(x, list):
                return [scale(y) for y in x]
            if isinstance(x, dict):
                return {k: scale(y) for k, y in x.items()}
            return x

        return set_at(doc, path, scale(node))
    if kind == 12:
        # type swap
        return set_at(doc, path, rng.choice([[], {}, "s", None, True, [node], {"a": node}, 0]))
    # a point copied onto another / zeroed (degenerate geometry)
    is_point = lambda x: isinstance(x, list) and bool(x) and all(is_num(y) for y in x)
    p1 = pick(rng, doc, is_point, stop=1.0)
    p2 = pick(rng, doc, is_point, stop=1.0)
    if p1 and p2:
        if rng.random() < 0.5:
            set_at(doc, p1[0], deep_copy(p2[1]))
        else:
            set_at(doc, p1[0], [0.0] * len(p1[1]))
    return doc


def mutate_bytes(rng, data):
    """One byte-level mutation."""
    b = bytearray(data)
    kind = rng.randrange(11)
    n = len(b)
    if n == 0:
        return bytes(rng.choice(BYTE_GARBAGE))
    if kind == 0:
        for _ in range(rng.choice([1, 1, 2, 4, 16])):
            i = rng.randrange(n)
            b[i] ^= 1 << rng.randrange(8)
        return bytes(b)
    if kind == 1:
        i = rng.randrange(n)
        b[i] = rng.randrange(256)
        return bytes(b)
    if kind == 2:
        return bytes(b[: rng.randrange(n)])
    if kind == 3:
        i = rng.randrange(n)
        j = min(n, i + rng.choice([1, 2, 8, 64, 1024]))
        del b[i:j]
        return bytes(b)
    if kind == 4:
        i = rng.randrange(n)
        j = min(n, i + rng.choice([1, 8, 64, 1024, 8192]))
        chunk = b[i:j] * rng.choice([1, 2, 10, 100])
        b[i:i] = chunk[: MAX_INPUT - n]
        return bytes(b)
    if kind == 5:
        return b"\xef\xbb\xbf" + bytes(b)
    if kind == 6:
        i = rng.randrange(n + 1)
        g = rng.choice(BYTE_GARBAGE) if rng.random() < 0.5 else rng.choice(UNICODE_GARBAGE).encode()
        b[i:i] = g
        return bytes(b)
    if kind in (7, 8):
        # a number token swapped
        ms = list(NUM_RE.finditer(bytes(b)))
        if ms:
            m = rng.choice(ms)
            return bytes(b[: m.start()]) + rand_special(rng).encode() + bytes(b[m.end():])
        return bytes(b)
    if kind == 9:
        # a structural character inserted / removed
        i = rng.randrange(n + 1)
        b[i:i] = rng.choice([b"{", b"}", b"[", b"]", b",", b":", b'"', b"\\", b" ", b"\n", b"-", b"e", b"."])
        return bytes(b)
    # random bytes
    i = rng.randrange(n + 1)
    b[i:i] = bytes(rng.randrange(256) for _ in range(rng.choice([1, 4, 32])))
    return bytes(b)


def mutate_json_text(rng, text_or_doc):
    """Mutated JSON text: structural mutations, then sometimes byte-level ones."""
    if isinstance(text_or_doc, (bytes, str)):
        raw = text_or_doc.encode() if isinstance(text_or_doc, str) else text_or_doc
        try:
            doc = json.loads(raw)
        except (ValueError, RecursionError):
            doc = None
    else:
        doc = text_or_doc
        raw = dump(doc).encode()
    r = rng.random()
    if doc is not None and r < 0.75:
        v = doc
        for _ in range(rng.choice([1, 1, 1, 2, 3])):
            v = mutate_value(rng, v if not isinstance(v, (Raw, DupObj)) else doc)
            if isinstance(v, (Raw, DupObj)):
                break
            # keep later mutations on a parseable copy of a small enough text
            if len(dump(v)) > 200000:
                break
            try:
                v = json.loads(dump(v))
            except (ValueError, RecursionError):
                break
        out = dump(v).encode()
        if rng.random() < 0.15:
            out = mutate_bytes(rng, out)
    else:
        out = raw
        for _ in range(rng.choice([1, 1, 2, 3])):
            out = mutate_bytes(rng, out)
    if rng.random() < 0.05:
        out = json.dumps(json.loads(out), indent=1).encode() if _parses(out) else out
    return out[:MAX_INPUT]


def _parses(b):
    try:
        json.loads(b)
        return True
    except (ValueError, RecursionError):
        return False


def mutate_lines(rng, data, line_mutator):
    """Line-oriented mutation: one or a few lines mutated, deleted, duplicated or shuffled."""
    lines = data.split(b"\n")
    for _ in range(rng.choice([1, 1, 2, 3])):
        if not lines:
            lines = [b""]
        i = rng.randrange(len(lines))
        r = rng.random()
        if r < 0.55:
            lines[i] = line_mutator(rng, lines[i])
        elif r < 0.65:
            del lines[i]
        elif r < 0.75:
            lines.insert(i, lines[i])
        elif r < 0.8:
            j = rng.randrange(len(lines))
            lines[i], lines[j] = lines[j], lines[i]
        elif r < 0.85:
            lines = lines[:i]
        elif r < 0.9:
            lines[i] = lines[i] + b"\r"
        else:
            lines[i] = mutate_bytes(rng, lines[i])
    out = b"\n".join(lines)
    if rng.random() < 0.03:
        out = b"\xef\xbb\xbf" + out
    return out[:MAX_INPUT]


def mutate_tokens_line(rng, line):
    """A whitespace-separated line (traces) with tokens swapped, dropped or duplicated."""
    toks = line.split(b" ")
    if not toks:
        return line
    i = rng.randrange(len(toks))
    r = rng.random()
    if r < 0.5:
        toks[i] = rand_special(rng).encode() if rng.random() < 0.8 else rng.choice(BYTE_GARBAGE)
    elif r < 0.65:
        del toks[i]
    elif r < 0.8:
        toks.insert(i, toks[i])
    elif r < 0.9 and toks[i].startswith((b"{", b"[")):
        toks[i] = mutate_json_text(rng, toks[i])
    else:
        toks.append(rand_special(rng).encode())
    return b" ".join(toks)


def mutate_line_json_or_tokens(rng, line):
    s = line.strip()
    if s.startswith((b"{", b"[")):
        return mutate_json_text(rng, s)
    # a line like `hand {...}` or `world_from_tracker {...}`
    if b" {" in line and rng.random() < 0.6:
        head, _, rest = line.partition(b" ")
        return head + b" " + mutate_json_text(rng, rest)
    return mutate_tokens_line(rng, line)


# ---------------------------------------------------------------------------------------------
# Hostile command-line values and paths.

HOSTILE_FLOATS = [
    "NaN", "nan", "inf", "-inf", "infinity", "1e308", "-1e308", "1e309", "1.7976931348623157e308",
    "-0", "0", "-1", "1e-320", "5e-324", "1e-300", "-1e-300", "1e15", "100000", "", " 1", "1,5",
    "0x10", "abc", "1e", "--", "-", "9" * 400,
]
HOSTILE_INTS = [
    "0", "1", "2", "-1", "3", "16", "17", "100", "256", "65535", "65536", "65537", "4294967295",
    "4294967296", "18446744073709551615", "18446744073709551616", "-9223372036854775808",
    "1e3", "NaN", "", "1.5", "abc", "99999999999999999999999",
]
HOSTILE_SIZES = [
    "0x0", "1x1", "0x10", "10x0", "1x100000", "100000x1", "65535x65535", "65536x1", "4294967296x1",
    "-1x10", "10x-1", "NaNx10", "1e3x10", "10", "x", "10x", "x10", "10x10x10", "8x8", "16x9",
    "99999999999999999999x1", " 8x8", "8×8", "", "3000x3000",
]
HOSTILE_PATCHES = [
    "0x0", "1x1", "0x5", "1x0", "2x2", "3x1", "1x3", "256x256", "257x257", "65536x1", "65537x1",
    "1x65537", "4294967296x1", "-1x2", "NaNx1", "1e308x1", "x", "2", "2x2x2", "", "300x300",
    "18446744073709551616x1",
]


class PathSpec:
    """An odd path for an input or output, built inside the case directory."""

    def __init__(self, kind, content=None):
        self.kind = kind  # dir, dev_full, dev_null, fifo, symlink, dangling, loop, missing_dir, file
        self.content = content


def odd_path(rng, content=None, for_output=False):
    kinds = ["dir", "dev_full", "dev_null", "fifo", "symlink", "dangling", "loop", "missing_dir"]
    if for_output:
        kinds += ["existing_dir_slash", "empty_name", "long_name"]
    return PathSpec(rng.choice(kinds), content)


# ---------------------------------------------------------------------------------------------
# Seeds.


def read(path):
    with open(path, "rb") as f:
        return f.read()


class Seeds:
    """Seed inputs: shipped files plus valid inputs generated by the binary."""

    def __init__(self, binary, work):
        self.binary = binary
        d = os.path.join(work, "seeds")
        os.makedirs(d, exist_ok=True)
        self.models = []
        prims = [
            ("plane", ["--patches", "2x2"]),
            ("plane", ["--patches", "3x1"]),
            ("cylinder", ["--patches", "4x1"]),
            ("hemisphere", ["--patches", "6x2"]),
            ("sphere", ["--patches", "6x2"]),
            ("torus", ["--patches", "4x2", "--radius", "2", "--minor-radius", "0.5"]),
            ("tube", ["--patches", "6x3"]),
        ]
        ops = (
            b'{"op":"push","at":[0,0,0],"dir":[0,0,-1],"depth":0.2,"radius":0.5}\n'
            b'{"op":"drag","path":[[-0.5,0,0],[0.5,0,0]],"dir":[0,0,-1],"depth":0.1,"radius":0.3}\n'
        )
        opsf = os.path.join(d, "ops.jsonl")
        with open(opsf, "wb") as f:
            f.write(ops)
        for i, (p, extra) in enumerate(prims):
            for sculpted in (False, True):
                out = os.path.join(d, f"model-{i}-{int(sculpted)}.json")
                argv = [binary, "sculpt", "--primitive", p] + extra + ["--out", out]
                if sculpted:
                    argv += ["--ops", opsf]
                r = subprocess.run(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
                if r.returncode == 0:
                    self.models.append(read(out))
                else:
                    print(f"seed {' '.join(argv)} failed: {r.stderr.decode(errors='replace')}", file=sys.stderr)
        if not self.models:
            sys.exit("crash-hunt: the binary made no seed model; is --bin right?")
        # a model with curves
        try:
            m = json.loads(self.models[0])
            m["curves"] = [
                {"bezier": [[0, 0, 0], [0.3, 0.2, 0.1], [0.6, -0.2, 0.0], [1, 0, 0]]},
                {"bspline": {"degree": 2, "knots": [0, 0, 0, 0.5, 1, 1, 1], "points": [[0, 0, 0], [0.2, 0.4, 0], [0.5, 0.5, 0], [0.9, 0, 0]]}},
            ]
            self.models.append(json.dumps(m).encode())
        except ValueError:
            pass
        self.ops_lines = [
            b'{"op":"push","at":[0,0,0],"dir":[0,0,-1],"depth":0.2,"radius":0.5}',
            b'{"op":"push","at":[0.1,0.2,0],"dir":[0,0,1],"depth":-0.3,"radius":0.4}',
            b'{"op":"drag","path":[[-0.5,0,0],[0.5,0,0]],"dir":[0,0,-1],"depth":0.1,"radius":0.3}',
            b'{"op":"drag","path":[[0,0,1],[0.2,0.1,1],[0.4,0.1,0.9]],"dir":[0,0,-1],"depth":-0.05,"radius":0.2}',
            b'{"op":"push","at":[0,0,1],"dir":[0,0,-1],"depth":0.1,"radius":0.3}',
            b'{"op":"push","at":[0,0,1],"dir":"normal","depth":0.1,"radius":0.3}',
            b'{"op":"drag","path":[[-0.5,0,0],[0,0.2,0],[0.5,0,0]],"dir":"normal","depth":0.1,"radius":0.3}',
            b'{"op":"drag","path":[[-0.5,0,0],[0.5,0,0]],"dirs":[[0,0,-1],[0,0.1,-1]],"depth":0.1,"radius":0.3}',
            b'{"op":"move","at":[0,0,0],"to":[0.1,0.2,0.3],"radius":0.5}',
            b'{"op":"smooth","at":[0.2,0,0],"radius":0.6,"strength":0.5}',
        ]
        batch = read(os.path.join(ROOT, "tests/data/curves/batch.jsonl"))
        self.curve_lines = [l for l in batch.split(b"\n") if l.strip()]
        self.curve_lines += [
            b'{"op":"svg_read","svg":"<?xml version=\\"1.0\\"?><svg xmlns=\\"http://www.w3.org/2000/svg\\" viewBox=\\"0 0 10 10\\"><g transform=\\"translate(1,2) scale(2)\\"><path d=\\"M1,1 L5,5 Q 6 6 7 5 T 9 9 A 2 2 0 0 1 3 3 z m 1 1 h 2 v 2 c 1 1 2 2 3 3 s 1 1 2 2\\"/></g><polyline points=\\"0,0 1,1 2,0\\"/><line x1=\\"0\\" y1=\\"0\\" x2=\\"3\\" y2=\\"4\\"/><rect x=\\"1\\" y=\\"1\\" width=\\"2\\" height=\\"3\\"/><circle cx=\\"5\\" cy=\\"5\\" r=\\"2\\"/><ellipse cx=\\"1\\" cy=\\"1\\" rx=\\"2\\" ry=\\"1\\"/><polygon points=\\"0 0 1 0 1 1\\"/></svg>"}',
            b'{"op":"svg_read","svg":"<svg><path d=\'M 0 0 C 1 1 2 2 3 3\'/><!-- c --><![CDATA[ x ]]><path d=\\"M1e308 0 L -1e308 1\\"/></svg>"}',
            b'{"op":"refine","curve":{"bezier":[[0,0],[1,1],[2,1],[3,0],[4,1]]},"mode":"variation","constraints":[{"u":0,"point":[0,0]},{"u":1,"point":[4,1]},{"u":0,"tangent":[1,1]},{"u":1,"tangent":[1,1]},{"u":0.5,"derivative":[1,0]}]}',
            b'{"op":"grab","curve":{"bspline":{"degree":3,"knots":[0,0,0,0,0.3,0.6,1,1,1,1],"points":[[0,0],[1,2],[2,2],[3,0],[4,1],[5,0]]}},"from":[2,1.5],"to":[2,3],"method":"least_change"}',
        ]
        self.closest_lines = [
            b'{"op":"closest","curve":{"bezier":[[0,0],[1,2],[3,2],[4,0]]},"point":[2,3]}',
            b'{"op":"closest","curve":{"bezier":[[0,0,0],[1,2,1],[3,2,0],[4,0,1]]},"point":[2,3,0],"rmax":1.5}',
            b'{"op":"closest","curve":{"bspline":{"degree":3,"knots":[0,0,0,0,0.5,1,1,1,1],"points":[[0,0],[1,1],[2,1.5],[3,1],[4,0]]}},"point":[2,0]}',
            b'{"op":"pick","curves":[{"bezier":[[0,0],[1,1]]},{"bezier":[[0,1],[1,2],[2,1]]}],"point":[0.5,0.9],"rmax":2}',
            b'{"op":"sphere","curve":{"bezier":[[0,0],[1,2],[3,2],[4,0]]},"center":[2,1],"radius":1}',
            b'{"op":"sphere","curve":{"bezier":[[0,0,0],[1,2,0],[3,2,0],[4,0,0]]},"center":[2,0,0],"radius":1.5}',
            b'{"op":"ray","curve":{"bezier":[[0,0,0],[1,2,0],[3,2,0],[4,0,0]]},"origin":[2,5,0],"dir":[0,-1,0]}',
            b'{"op":"ray","curve":{"bspline":{"degree":2,"knots":[0,0,0,1,2,2,2],"points":[[0,0,0],[1,1,0],[2,0,1],[3,1,0]]}},"origin":[1,1,5],"dir":[0,0,-1]}',
        ]
        self.figures = [read(os.path.join(ROOT, "tests/data/figures", f)) for f in sorted(os.listdir(os.path.join(ROOT, "tests/data/figures"))) if f.endswith(".json")]
        # smaller figures keep the fits quick
        small = []
        for fb in self.figures:
            f = json.loads(fb)
            g = dict(f)
            g["metacircles"] = f.get("metacircles", [])[::12]
            g["contour"] = f.get("contour", [])[::3]
            small.append(json.dumps(g).encode())
        small.append(
            json.dumps(
                {
                    "format": "nendo-figure", "version": 1, "name": "tiny", "threshold": 0.5,
                    "view": {"min": [0, 0], "max": [100, 100]}, "background": "#ffffff",
                    "metacircles": [{"centre": [40, 50], "radius": 30, "density": 1.0}, {"centre": [65, 50], "radius": 25, "density": 0.8, "colour": "#204080"}],
                    "contour": [[10, 50], [40, 20], [80, 30], [90, 50], [80, 70], [40, 80]],
                    "polygons": [{"points": [[20, 20], [30, 20], [25, 30]], "colour": "#ff0000"}],
                    "curves": [{"bezier": [[10, 50], [40, 40], [90, 50]]}, {"bspline": {"degree": 2, "knots": [0, 0, 0, 1, 1, 1], "points": [[40, 20], [50, 50], [40, 80]]}}],
                }
            ).encode()
        )
        self.figures_small = small
        self.shapes = [read(os.path.join(ROOT, "tests/data/shapes", f)) for f in sorted(os.listdir(os.path.join(ROOT, "tests/data/shapes"))) if f.endswith(".json")]
        self.profiles = {f: read(os.path.join(ROOT, "devices/profiles", f)) for f in sorted(os.listdir(os.path.join(ROOT, "devices/profiles"))) if f.endswith(".json")}
        self.traces = {}
        for f in sorted(os.listdir(os.path.join(ROOT, "devices/traces"))):
            if f.endswith(".trace"):
                data = read(os.path.join(ROOT, "devices/traces", f))
                # keep the header and a bounded number of frames so a replay stays quick
                head, sep, frames = data.partition(b"\nframes\n")
                lines = frames.split(b"\n")
                self.traces[f] = head + sep + b"\n".join(lines[:150]) + b"\n"
                # the same trace as version 4, with the gate's marks (`held=`) on some frames
                self.traces[f[:-6] + "-marked.trace"] = marked_trace(head, lines[:150])
        # device byte streams for `record`: valid-looking records per protocol
        self.device_bytes = {
            "fastrak": [
                b"01   1.000   2.000   3.000 1.00000 0.00000 0.00000 0.00000\r\n" * 20,
                bytes([0x30, 0x31, 0x20]) + bytes(range(40)) * 10,
            ],
            "flock": [bytes([0x80 | 1, 0, 2, 0, 3, 0, 4, 0, 5, 0, 6, 0]) * 30],
            "cyberglove": [b"G" + bytes(range(1, 19)) + b"\x00" for _ in range(1)] * 1 + [b"\x07" + bytes(22) + b"\x00"],
            "5dt": [bytes([0x80] + [10] * 5 + [0, 0x40]) * 30, bytes([0x3C, 0x44] + [0] * 30 + [0x3E]) * 20],
            "random": [bytes(range(256)) * 4],
        }


# ---------------------------------------------------------------------------------------------
# Cases. A case is a dict: sub, argv (strings; "{d}" is the case directory, "{pty}" the
# pseudo-terminal's slave), files {name: bytes}, paths {name: PathSpec}, stdin bytes or None,
# stdout_full, pty_bytes, lines (closest/curve: how many inputs it counts), shrink (the name of the
# file to shrink, or "stdin").


def fpath(name):
    return "{d}/" + name


def pick_model(rng, seeds):
    return rng.choice(seeds.models)


def maybe(rng, p):
    return rng.random() < p


def model_input(rng, seeds, case, name="model.json", mutate_p=0.85):
    """Put a (mutated) model file or an odd path in the case; returns the argv string."""
    if maybe(rng, 0.04):
        case["paths"][name] = odd_path(rng, pick_model(rng, seeds))
        return fpath(name)
    data = pick_model(rng, seeds)
    if maybe(rng, mutate_p):
        data = mutate_json_text(rng, data)
        case["shrink"] = case.get("shrink") or name
    case["files"][name] = data
    return fpath(name)


def out_path(rng, case, name, p=0.05):
    if maybe(rng, p):
        case["paths"][name] = odd_path(rng, for_output=True)
    return fpath(name)


def new_case(sub):
    return {"sub": sub, "argv": [sub], "files": {}, "paths": {}, "stdin": None, "stdout_full": False, "pty_bytes": None, "lines": 1, "shrink": None}


def gen_sculpt(rng, seeds):
    c = new_case("sculpt")
    if maybe(rng, 0.35):
        c["argv"] += ["--model", model_input(rng, seeds, c, mutate_p=0.5)]
    else:
        prim = rng.choice(["plane", "cylinder", "hemisphere", "sphere", "torus", "tube"]) if maybe(rng, 0.93) else rng.choice(["", "cube", "Plane", "plane\u0000", "spheres"])
        c["argv"] += ["--primitive", prim]
        # small grids keep the runs quick; the default grid now and then
        if maybe(rng, 0.95):
            c["argv"] += ["--patches", rng.choice(HOSTILE_PATCHES) if maybe(rng, 0.2) else rng.choice(["2x2", "3x2", "4x2", "1x1", "6x2", "4x4"])]
        for flag in ("--radius", "--height", "--minor-radius"):
            if maybe(rng, 0.3):
                c["argv"] += [flag, rng.choice(HOSTILE_FLOATS) if maybe(rng, 0.5) else rng.choice(["0.5", "1", "2", "0.1"])]
    if maybe(rng, 0.2):
        c["argv"] += ["--regulation", rng.choice(["none", "c1", "g1", "exact", "default", "", "G1", "x"])]
    if maybe(rng, 0.15):
        c["argv"] += ["--mirror", rng.choice(["x", "y", "z"]) if maybe(rng, 0.9) else rng.choice(["", "X", "w", "xy"])]
    if maybe(rng, 0.15):
        c["argv"].append("--auto-refine")
    if maybe(rng, 0.8):
        lines = [rng.choice(seeds.ops_lines) for _ in range(rng.choice([1, 1, 2, 3, 5]))]
        data = b"\n".join(lines) + b"\n"
        if maybe(rng, 0.9):
            data = mutate_lines(rng, data, lambda r, l: mutate_json_text(r, l))
        if maybe(rng, 0.3):
            c["argv"] += ["--ops", "-"]
            c["stdin"] = data
            c["shrink"] = "stdin"
        elif maybe(rng, 0.05):
            c["paths"]["ops.jsonl"] = odd_path(rng, data)
            c["argv"] += ["--ops", fpath("ops.jsonl")]
        else:
            c["files"]["ops.jsonl"] = data
            c["argv"] += ["--ops", fpath("ops.jsonl")]
            c["shrink"] = "ops.jsonl"
    c["argv"] += ["--out", out_path(rng, c, "out.json")]
    return c


def gen_check(rng, seeds):
    c = new_case("check")
    c["argv"].append(model_input(rng, seeds, c))
    if maybe(rng, 0.15):
        c["argv"] += ["--samples", rng.choice(HOSTILE_INTS + ["33", "100000", "100001", "32"])]
    if maybe(rng, 0.2):
        c["argv"] += ["--against", model_input(rng, seeds, c, "other.json", mutate_p=0.5)]
    c["stdout_full"] = maybe(rng, 0.05)
    return c


def gen_export(rng, seeds):
    c = new_case("export")
    c["argv"].append(model_input(rng, seeds, c))
    ext = rng.choice([".obj", ".stl", ".glb", ".step", ".stp", ".igs", ".iges"]) if maybe(rng, 0.95) else rng.choice(["", ".OBJ", ".ply", ".glb.tmp", ".STEP"])
    c["argv"].append(out_path(rng, c, "mesh" + ext))
    if maybe(rng, 0.15):
        c["argv"] += ["--up", rng.choice(["y", "z"]) if maybe(rng, 0.8) else rng.choice(["x", "", "Y", "-z"])]
    if maybe(rng, 0.15):
        c["argv"] += ["--scale", rng.choice(HOSTILE_FLOATS) if maybe(rng, 0.6) else rng.choice(["1", "25.4", "1000"])]
    tol = rng.choice(HOSTILE_FLOATS) if maybe(rng, 0.3) else rng.choice(["0.05", "0.01", "0.1", "0.2"])
    # fine tolerances are heavy: keep them rare
    if tol in ("1e-320", "5e-324", "1e-300") and not maybe(rng, 0.3):
        tol = "0.05"
    c["argv"] += ["--tolerance", tol]
    return c


def gen_refine(rng, seeds):
    c = new_case("refine")
    c["argv"].append(model_input(rng, seeds, c, mutate_p=0.6))
    if maybe(rng, 0.5):
        k = rng.choice(HOSTILE_INTS) if maybe(rng, 0.3) else rng.choice(["1", "2", "3"])
        c["argv"] += ["--uniform", k]
    for flag in ("--insert-u", "--insert-v"):
        if maybe(rng, 0.45):
            ts = [rng.choice(HOSTILE_FLOATS) if maybe(rng, 0.3) else f"{rng.uniform(0, 4):.3f}" for _ in range(rng.choice([1, 1, 2, 3]))]
            c["argv"] += [flag, ",".join(ts) if maybe(rng, 0.95) else ",".join(ts) + ","]
    c["argv"] += ["--out", out_path(rng, c, "out.json")]
    return c


def gen_render(rng, seeds):
    c = new_case("render")
    c["argv"].append(model_input(rng, seeds, c, mutate_p=0.75))
    c["argv"] += ["--png", out_path(rng, c, "out.png")]
    size = rng.choice(HOSTILE_SIZES) if maybe(rng, 0.12) else rng.choice(["48x32", "32x32", "64x48", "1x1"])
    if size in ("65535x65535", "3000x3000", "100000x1", "1x100000") and not maybe(rng, 0.3):
        size = "64x48"
    c["argv"] += ["--size", size]
    c["argv"] += ["--view", rng.choice(["front", "back", "left", "right", "top", "bottom", "iso"]) if maybe(rng, 0.95) else rng.choice(["", "up", "ISO"])]
    if maybe(rng, 0.3):
        c["argv"].append("--heat")
    if maybe(rng, 0.15):
        c["argv"] += ["--heat-max", rng.choice(HOSTILE_FLOATS)]
    if maybe(rng, 0.3):
        c["argv"].append("--control-net")
    if maybe(rng, 0.2):
        c["argv"].append("--no-edges")
    c["argv"] += ["--samples", rng.choice(["1", "1", "4"]) if maybe(rng, 0.9) else rng.choice(HOSTILE_INTS)]
    return c


def gen_batch(sub, rng, seeds):
    c = new_case(sub)
    c["argv"].append("--batch")
    pool = seeds.closest_lines if sub == "closest" else seeds.curve_lines
    lines = []
    for _ in range(BATCH_LINES):
        l = rng.choice(pool)
        r = rng.random()
        if r < 0.85:
            l = mutate_json_text(rng, l)
            if b"\n" in l:
                l = l.replace(b"\n", b" ")
        elif r < 0.9:
            l = mutate_bytes(rng, l).replace(b"\n", b" ")
        elif sub == "curve" and r < 0.97:
            l = hostile_svg_line(rng)
        lines.append(l)
    c["stdin"] = b"\n".join(lines) + (b"\n" if maybe(rng, 0.9) else b"")
    c["lines"] = BATCH_LINES
    c["shrink"] = "stdin"
    c["stdout_full"] = maybe(rng, 0.03)
    return c


def hostile_svg_line(rng):
    """An svg_read request with hostile SVG / XML."""
    path_d = rng.choice(
        [
            "M0 0 C 1 1 2 2 3 3", "M 1e308 1e308 L -1e308 -1e308", "M0,0 A 1e308 1e308 0 1 1 1,1",
            "M0 0 A 0 0 0 0 0 0 0", "M NaN 0 L 1 1", "M0 0" + " L1 1" * rng.choice([1, 1000, 30000]),
            "m0 0" + " c1 1 2 2 3 3" * rng.choice([10, 10000]), "M0 0 Z Z Z z", "L 1 1", "M", "M0", "M0 0 C 1",
            "M0 0 S1 1", "M0 0 T 1 1 t 2 2", "M0 0 Q 1 1 2 2 q 1 1", "M.5.5.5.5", "M0-1e-5-1e-5",
            "M 0 0 H 1e309 V -1e309", "M0 0 a1 1 0 1 0 1e-320 0", "\u0000", "M0 0 L" + " 9" * 500,
        ]
    )
    transform = rng.choice(
        ["", "matrix(0 0 0 0 0 0)", "scale(1e308)", "scale(0)", "rotate(NaN)", "translate(1e308,1e308) scale(1e308)", "skewX(90)", "matrix(1 2 3)", "scale(" + "1 " * 1000 + ")"]
    )
    body = f'<path d="{path_d}" transform="{transform}"/>'
    r = rng.random()
    if r < 0.15:
        body = "<g>" * rng.choice([10, 1000, 100000]) + body + "</g>" * rng.choice([0, 10, 1000])
    elif r < 0.25:
        body = '<!DOCTYPE svg [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;"><!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;">]>' + body + "&c;"
    elif r < 0.3:
        body = body + '<use href="#p"/><path id="p" d="M0 0 L1 1"/>' * rng.choice([1, 100])
    elif r < 0.35:
        body = '<svg width="1e308" height="NaN" viewBox="0 0 0 0">' + body + "</svg>"
    elif r < 0.4:
        body = body.replace("<path", "<path " + 'a="1" ' * rng.choice([10, 10000]))
    elif r < 0.45:
        body = "<polyline points=\"" + ",".join(["1e308"] * rng.choice([1, 3, 1001])) + "\"/>"
    elif r < 0.5:
        body = "<circle r=\"-1\"/><ellipse rx=\"NaN\" ry=\"1e308\"/><rect width=\"1e308\" height=\"1e308\" rx=\"-5\"/>"
    svg = "<svg xmlns='http://www.w3.org/2000/svg'>" + body + "</svg>"
    if rng.random() < 0.2:
        svg = svg[: rng.randrange(len(svg) + 1)]
    req = {"op": "svg_read", "svg": svg}
    if rng.random() < 0.3:
        req["flip_y"] = rng.choice([True, False, None, 1])
    s = json.dumps(req).encode()
    return s[:MAX_INPUT]


def figure_input(rng, seeds, c, name="figure.json", small=True, mutate_p=0.85):
    if maybe(rng, 0.03):
        c["paths"][name] = odd_path(rng, rng.choice(seeds.figures_small))
        return fpath(name)
    data = rng.choice(seeds.figures_small if small or maybe(rng, 0.7) else seeds.figures)
    if maybe(rng, mutate_p):
        data = mutate_json_text(rng, data)
        c["shrink"] = c.get("shrink") or name
    c["files"][name] = data
    return fpath(name)


def picture_flags(rng, c, small=True):
    if maybe(rng, 0.5):
        c["argv"] += ["--png", out_path(rng, c, "out.png")]
    if maybe(rng, 0.4):
        c["argv"] += ["--svg", out_path(rng, c, "out.svg")]
    size = rng.choice(HOSTILE_SIZES) if maybe(rng, 0.1) else rng.choice(["32x32", "48x40", "16x64"])
    if size in ("65535x65535", "3000x3000", "100000x1", "1x100000") and not maybe(rng, 0.3):
        size = "32x32"
    c["argv"] += ["--size", size]
    c["argv"] += ["--samples", rng.choice(HOSTILE_INTS) if maybe(rng, 0.1) else rng.choice(["1", "2", "4"])]
    if maybe(rng, 0.2):
        c["argv"].append("--no-curves")


def gen_figure(rng, seeds):
    c = new_case("figure")
    which = rng.choices(["fit", "render", "warp", "measure", "shape"], [3, 2, 2, 2, 2])[0]
    c["argv"].append(which)
    if which == "fit":
        c["argv"].append(figure_input(rng, seeds, c))
        c["argv"] += ["--out", out_path(rng, c, "fit.json")]
        c["argv"] += ["--circles", rng.choice(HOSTILE_INTS) if maybe(rng, 0.1) else rng.choice(["4", "8", "12"])]
        c["argv"] += ["--seed-resolution", rng.choice(HOSTILE_INTS) if maybe(rng, 0.1) else rng.choice(["8", "16"])]
        c["argv"] += ["--guard-resolution", rng.choice(HOSTILE_INTS) if maybe(rng, 0.1) else rng.choice(["4", "8"])]
        c["argv"] += ["--iterations", rng.choice(HOSTILE_INTS) if maybe(rng, 0.05) else rng.choice(["2", "5"])]
        if maybe(rng, 0.1):
            c["argv"] += ["--contour-samples", rng.choice(HOSTILE_INTS)]
        if maybe(rng, 0.3):
            c["argv"].append("--descent")
        if maybe(rng, 0.1):
            c["argv"] += ["--colour", rng.choice(["#000000", "#fff", "red", "", "#gggggg", "#12345678", "#ffffff\u0000"])]
        if maybe(rng, 0.4):
            picture_flags(rng, c)
    elif which == "render":
        c["argv"].append(figure_input(rng, seeds, c, small=maybe(rng, 0.8)))
        picture_flags(rng, c)
    elif which == "warp":
        c["argv"].append(figure_input(rng, seeds, c))
        # the deformed curves: a figure, an array of curves or {"curves": [...]}, mutated
        f = json.loads(rng.choice(seeds.figures_small))
        curves = f.get("curves", [])
        shape = rng.choice(["figure", "array", "object"])
        doc = f if shape == "figure" else (curves if shape == "array" else {"curves": curves})
        data = mutate_json_text(rng, doc) if maybe(rng, 0.8) else dump(doc).encode()
        c["files"]["curves.json"] = data
        if c["shrink"] is None:
            c["shrink"] = "curves.json"
        c["argv"] += ["--curves", fpath("curves.json"), "--out", out_path(rng, c, "warped.json")]
        for flag in ("--a", "--b", "--p"):
            if maybe(rng, 0.2):
                c["argv"] += [flag, rng.choice(HOSTILE_FLOATS)]
        c["argv"] += ["--max-edge", rng.choice(HOSTILE_FLOATS) if maybe(rng, 0.2) else rng.choice(["inf", "5", "20"])]
        if c["argv"][-1] in ("1e-320", "5e-324", "1e-300", "0", "-0") and not maybe(rng, 0.3):
            c["argv"][-1] = "inf"
        if maybe(rng, 0.3):
            picture_flags(rng, c)
    elif which == "measure":
        c["argv"].append(figure_input(rng, seeds, c, small=maybe(rng, 0.8)))
        c["stdout_full"] = maybe(rng, 0.05)
    else:
        name = "shape.json"
        if maybe(rng, 0.03):
            c["paths"][name] = odd_path(rng, seeds.shapes[0])
        else:
            data = rng.choice(seeds.shapes)
            if maybe(rng, 0.85):
                data = mutate_json_text(rng, data)
                c["shrink"] = name
            c["files"][name] = data
        c["argv"].append(fpath(name))
        c["argv"] += ["--mesh", out_path(rng, c, rng.choice(["m.obj", "m.stl", "m.glb", "m.ply"]))]
        c["argv"] += ["--resolution", rng.choice(HOSTILE_INTS) if maybe(rng, 0.1) else rng.choice(["4", "8"])]
        c["argv"] += ["--balls", rng.choice(HOSTILE_INTS) if maybe(rng, 0.1) else rng.choice(["2", "3"])]
        c["argv"] += ["--iterations", rng.choice(HOSTILE_INTS) if maybe(rng, 0.05) else rng.choice(["2", "4"])]
        c["argv"] += ["--guard-resolution", rng.choice(HOSTILE_INTS) if maybe(rng, 0.1) else rng.choice(["4", "6"])]
        if maybe(rng, 0.1):
            c["argv"] += ["--samples", rng.choice(HOSTILE_INTS + ["100", "400", "401", "99"])]
        for flag in ("--a", "--b", "--p", "--reach", "--max-edge"):
            if maybe(rng, 0.1):
                c["argv"] += [flag, rng.choice(HOSTILE_FLOATS)]
        for flag in ("--no-bridges", "--descent", "--refit"):
            if maybe(rng, 0.2):
                c["argv"].append(flag)
        if maybe(rng, 0.3):
            c["argv"] += ["--out", out_path(rng, c, "shape-out.json")]
        if maybe(rng, 0.02):
            c["argv"] += ["--png", out_path(rng, c, "shape.png")]
    # iteration-heavy values are bounded so inputs stay quick
    for i, a in enumerate(c["argv"]):
        if c["argv"][i - 1] in ("--iterations", "--circles", "--balls", "--seed-resolution", "--guard-resolution", "--resolution", "--contour-samples") and a.isdigit() and int(a) > 300 and not maybe(rng, 0.2):
            c["argv"][i] = "8"
    return c


def gen_morph(rng, seeds):
    c = new_case("morph")
    c["argv"].append(figure_input(rng, seeds, c, "src.json", mutate_p=0.6))
    c["argv"].append(figure_input(rng, seeds, c, "dst.json", mutate_p=0.6))
    c["argv"] += ["--out", out_path(rng, c, "frames")]
    frames = rng.choice(HOSTILE_INTS) if maybe(rng, 0.1) else rng.choice(["2", "3"])
    if frames.isdigit() and int(frames) > 10 and not maybe(rng, 0.1):
        frames = "2"
    c["argv"] += ["--frames", frames]
    size = rng.choice(HOSTILE_SIZES) if maybe(rng, 0.08) else rng.choice(["16x16", "32x24"])
    if size in ("65535x65535", "3000x3000", "100000x1", "1x100000") and not maybe(rng, 0.3):
        size = "16x16"
    c["argv"] += ["--size", size]
    c["argv"] += ["--samples", rng.choice(HOSTILE_INTS) if maybe(rng, 0.08) else "1"]
    if maybe(rng, 0.4):
        c["argv"].append("--no-svg")
    if maybe(rng, 0.3):
        c["argv"].append("--skeleton")
    if maybe(rng, 0.15):
        c["argv"] += ["--match-distance", rng.choice(HOSTILE_FLOATS)]
    return c


def mutated_profile(rng, seeds):
    name, data = rng.choice(sorted(seeds.profiles.items()))
    if maybe(rng, 0.9):
        data = mutate_json_text(rng, data)
    return name, data


def gen_devices(rng, seeds):
    c = new_case("devices")
    if maybe(rng, 0.05):
        c["paths"]["profiles"] = odd_path(rng)
        c["argv"] += ["--profiles", fpath("profiles")]
        return c
    n = rng.choice([1, 1, 2, 3])
    for i in range(n):
        name, data = mutated_profile(rng, seeds)
        fname = "profiles/" + (name if maybe(rng, 0.9) else rng.choice(["x.json", "a b.json", ".json", "z.JSON", "noext"]))
        if fname in c["files"]:
            fname = f"profiles/{i}-{name}"
        c["files"][fname] = data
        if c["shrink"] is None:
            c["shrink"] = fname
    if maybe(rng, 0.05):
        c["paths"]["profiles/sub.json"] = PathSpec(rng.choice(["dir", "fifo_empty", "dangling", "loop", "dev_null"]))
    c["argv"] += ["--profiles", fpath("profiles")]
    c["stdout_full"] = maybe(rng, 0.05)
    return c


def gen_record(rng, seeds):
    c = new_case("record")
    if maybe(rng, 0.15):
        c["argv"] += ["--profile", rng.choice(sorted(p[:-5] for p in seeds.profiles) + ["", "nope", "../x", "/dev/null"])]
    elif maybe(rng, 0.04):
        c["paths"]["profile.json"] = odd_path(rng, rng.choice(list(seeds.profiles.values())))
        c["argv"] += ["--profile", fpath("profile.json")]
    else:
        _, data = mutated_profile(rng, seeds)
        c["files"]["profile.json"] = data
        c["shrink"] = "profile.json"
        c["argv"] += ["--profile", fpath("profile.json")]
    c["argv"] += ["--out", out_path(rng, c, "t.trace")]
    c["argv"] += ["--seconds", rng.choice(HOSTILE_FLOATS) if maybe(rng, 0.15) else rng.choice(["0.05", "0.1"])]
    try:
        if float(c["argv"][-1]) > 0.2 and not maybe(rng, 0.02):
            c["argv"][-1] = "0.1"
    except ValueError:
        pass
    # the device bytes come from a pseudo-terminal given as the port
    r = rng.random()
    if r < 0.7:
        c["argv"] += [rng.choice(["--port", "--port", "--glove-port", "--tracker-port"]), "{pty}"]
        if maybe(rng, 0.3):
            c["argv"] += [rng.choice(["--glove-port", "--tracker-port"]), "{pty}"]
    elif r < 0.8:
        c["argv"] += ["--port", rng.choice(["/dev/null", "/dev/full", "/nonexistent/tty", "", "{d}", "/dev/zero"])]
    stream = rng.choice(rng.choice(list(seeds.device_bytes.values())))
    for _ in range(rng.choice([0, 1, 2, 5, 20])):
        stream = mutate_bytes(rng, stream)
    c["pty_bytes"] = stream[:65536]
    return c


def marked_trace(head, frames):
    """A trace as version 4 with the gate's marks: `marks held` in its header and `held=` on
    every seventh frame line with a tracker pose (the first joint column too when it has one)."""
    hl = head.split(b"\n")
    hl[0] = b"nendo-hand-trace 4"
    at = next((i for i, l in enumerate(hl) if l.startswith(b"scene ")), len(hl))
    hl.insert(at, b"marks held")
    joints = next((l.split()[1:] for l in hl if l.startswith(b"joints")), [])
    out = []
    for k, line in enumerate(frames):
        w = line.split()
        if k % 7 == 3 and len(w) > 6 and w[1].startswith(b"ok") and w[5] != b"-":
            marks = b"position,orientation"
            j = w.index(b"J") if b"J" in w else -1
            if joints and 0 <= j < len(w) - 1 and w[j + 1] not in (b"-", b"?"):
                marks += b"," + joints[0]
            line = line + b" held=" + marks
        out.append(line)
    return b"\n".join(hl) + b"\nframes\n" + b"\n".join(out) + b"\n"


def gen_replay(rng, seeds):
    c = new_case("replay")
    name, data = rng.choice(sorted(seeds.traces.items()))
    if maybe(rng, 0.04):
        c["paths"]["in.trace"] = odd_path(rng, data)
    else:
        if maybe(rng, 0.9):
            data = mutate_lines(rng, data, mutate_line_json_or_tokens)
            c["shrink"] = "in.trace"
        c["files"]["in.trace"] = data
    c["argv"].append(fpath("in.trace"))
    if maybe(rng, 0.2):
        c["argv"] += ["--model", model_input(rng, seeds, c, mutate_p=0.3)]
    else:
        prim = rng.choice(["plane", "sphere", "cylinder", "torus", "tube", "hemisphere"])
        c["argv"] += ["--primitive", prim, "--patches", rng.choice(HOSTILE_PATCHES) if maybe(rng, 0.08) else rng.choice(["2x2", "4x2"])]
        for flag in ("--radius", "--height", "--minor-radius"):
            if maybe(rng, 0.08):
                c["argv"] += [flag, rng.choice(HOSTILE_FLOATS)]
    if maybe(rng, 0.1):
        c["argv"] += ["--regulation", rng.choice(["none", "c1", "g1", "exact", "x"])]
    if maybe(rng, 0.1):
        c["argv"] += ["--finger", rng.choice(["thumb", "index", "middle", "ring", "pinky", "ray", "toe", ""])]
    if maybe(rng, 0.1):
        c["argv"] += ["--finger-radius", rng.choice(HOSTILE_FLOATS)]
    if maybe(rng, 0.15):
        if maybe(rng, 0.5):
            c["argv"] += ["--profile", rng.choice(sorted(p[:-5] for p in seeds.profiles) + ["nope", ""])]
        else:
            _, pdata = mutated_profile(rng, seeds)
            c["files"]["profile.json"] = pdata
            c["argv"] += ["--profile", fpath("profile.json")]
    c["argv"] += ["--out", out_path(rng, c, "out.json")]
    return c


# ---------------------------------------------------------------------------------------------
# `bounds`: semantic files and bounded-input probes (issue 28). Each case carries an oracle,
# `expect(d, rc, out, err)`, run in the case directory after the binary ends: None when the
# outcome is right, else what went wrong (counted as a "violation", like a crash). The probes:
# endless inputs (/dev/zero as trace, profile, figure, curves, shape, model), over-long batch
# lines (16 MB and more: answered with an error, the next line read), pictures and warps beyond
# their caps (refused up front), saved ratios off their points (refused naming the line),
# meshes scaled to nothing and CAD scales out of range (refused, nothing written), `replay
# --out` onto the start model its trace names (refused, the model kept), `morph` into a
# directory of an earlier run (refused unless --replace, never mixed) and `emulate --link`
# over a user's link (refused, the link kept). Kills of `record` are covered by
# .ci/checks/record-survives.sh.


def _refused(rc, err, needle=None):
    if rc not in (1, 2):
        return f"expected a refusal (exit 1 or 2), got exit {rc}"
    if needle is not None and needle.encode() not in err:
        return f"refused without naming {needle!r}: {err[-300:]!r}"
    return None


def _scaled_model(data, k):
    m = json.loads(data)
    m["surface"]["patches"] = [[[x * k for x in p] for p in patch] for patch in m["surface"]["patches"]]
    return json.dumps(m).encode()


def _set_scene(trace, scene):
    lines = trace.split(b"\n")
    out = [l for l in lines if not l.startswith(b"scene ")]
    i = out.index(b"frames")
    return b"\n".join(out[:i] + [b"scene " + scene] + out[i:])


def gen_bounds(rng, seeds):
    import hashlib
    c = new_case("bounds")
    c["argv"] = []
    kind = rng.choice(["zero", "zero", "long_line", "picture", "warp", "ratio", "tiny_mesh", "cad_scale", "start_model", "morph_dir", "emulate_link"])
    c["kind"] = kind
    if kind == "zero":
        z = "/dev/zero"
        c["argv"] = rng.choice([
            ["replay", z, "--primitive", "plane", "--out", fpath("o.json")],
            ["replay", fpath("t.trace"), "--profile", z, "--out", fpath("o.json")],
            ["figure", "render", z, "--png", fpath("x.png")],
            ["figure", "measure", z],
            ["figure", "fit", z, "--out", fpath("f.json")],
            ["figure", "warp", fpath("f.json"), "--curves", z, "--out", fpath("o.json")],
            ["figure", "shape", z, "--mesh", fpath("x.obj")],
            ["morph", z, fpath("f.json"), "--out", fpath("frames")],
            ["check", z],
            ["export", z, fpath("x.stl")],
        ])
        c["files"]["t.trace"] = rng.choice(sorted(seeds.traces.values()))
        c["files"]["f.json"] = rng.choice(seeds.figures_small)
        c["expect"] = lambda d, rc, out, err: _refused(rc, err)
    elif kind == "long_line":
        sub = rng.choice(["closest", "curve"])
        good = rng.choice(seeds.closest_lines if sub == "closest" else seeds.curve_lines)
        n = rng.choice([(16 << 20) + 1, 17 << 20, 40 << 20])
        filler = rng.choice([b"x", b" ", b"[", b"\xff", b"9"])
        long = (filler * n)[:n]
        c["argv"] = [sub, "--batch"]
        c["stdin"] = good + b"\n" + long + b"\n" + good + b"\n"
        c["capture"] = True
        c["lines"] = 3

        def expect(d, rc, out, err, n=n):
            lines = out.split(b"\n")
            if len(lines) < 3:
                return f"{len(lines) - 1} answers to 3 lines (the line of {n} bytes)"
            if b"longer than the limit" not in lines[1]:
                return f"the line of {n} bytes was not refused as too long: {lines[1][:200]!r}"
            return None
        c["expect"] = expect
    elif kind == "picture":
        w, h = rng.choice([(8193, 8193), (9000, 8000), (16384, 4097), (12000, 12000), (16384, 16384)])
        c["files"]["f.json"] = rng.choice(seeds.figures_small)
        c["argv"] = rng.choice([
            ["figure", "render", fpath("f.json"), "--png", fpath("x.png"), "--size", f"{w}x{h}"],
            ["morph", fpath("f.json"), fpath("f.json"), "--out", fpath("frames"), "--size", f"{w}x{h}"],
        ])
        c["expect"] = lambda d, rc, out, err: _refused(rc, err, "GB while drawing")
    elif kind == "warp":
        pairs = rng.choice([10, 1001, 5000, 100000])
        points = 10_000_001 // pairs + rng.choice([1, 10, 1000])
        pair = '[{"bezier":[[0,0],[1,0]]},{"bezier":[[0,0],[1,0.1]]}]'
        line = '{"op":"warp","pairs":[' + ",".join([pair] * pairs) + '],"points":[' + ",".join(["[0.5,0.5]"] * points) + "]}"
        c["argv"] = ["curve", "--batch"]
        c["stdin"] = line.encode() + b"\n"
        c["capture"] = True
        c["expect"] = lambda d, rc, out, err: None if b"weight evaluations" in out else f"a warp of {pairs} x {points} was not refused up front: {out[:200]!r}"
    elif kind == "ratio":
        # the unsculpted planes (seeds 0 and 2): every shared line's rows share ratio 1
        data = seeds.models[rng.choice([0, 2])]
        m = json.loads(data)
        u = m["surface"]["ratios"]["u"]
        k = rng.randrange(1, len(u) - 1)
        u[k] = u[k] * (1 + rng.choice([1e-6, 1e-5, 1e-3, 0.1, -1e-5, -0.3]))
        c["files"]["m.json"] = json.dumps(m).encode()
        c["argv"] = rng.choice([["check", fpath("m.json")], ["export", fpath("m.json"), fpath("x.obj")], ["refine", fpath("m.json"), "--uniform", "2", "--out", fpath("o.json")]])
        c["expect"] = lambda d, rc, out, err, k=k: _refused(rc, err, f"surface.ratios.u[{k}]")
    elif kind == "tiny_mesh":
        k = 10.0 ** rng.randrange(-300, -12)
        c["files"]["m.json"] = _scaled_model(seeds.models[rng.choice([0, 2])], k)
        ext = rng.choice(["stl", "obj", "glb"])
        c["argv"] = ["export", fpath("m.json"), fpath("x." + ext)]

        def expect(d, rc, out, err):
            if os.path.exists(os.path.join(d, "x." + ext)):
                return f"a plane scaled by {k:g} was written as .{ext}"
            return _refused(rc, err)
        c["expect"] = expect
    elif kind == "cad_scale":
        scale = rng.choice(["1e-9", "1e40", "1e-300", "1e300", "9e-5", "1.0001e4", "5e-324"])
        ext = rng.choice(["step", "igs"])
        c["files"]["m.json"] = rng.choice(seeds.models)
        c["argv"] = ["export", fpath("m.json"), fpath("x." + ext), "--scale", scale]

        def expect(d, rc, out, err):
            if os.path.exists(os.path.join(d, "x." + ext)):
                return f"--scale {scale} wrote a .{ext}"
            return _refused(rc, err, "--scale")
        c["expect"] = expect
    elif kind == "start_model":
        model = rng.choice(seeds.models)
        name, trace = rng.choice(sorted(seeds.traces.items()))
        scene = json.dumps({"model_file": {"path": "start.json", "sha256": hashlib.sha256(model).hexdigest()}}).encode()
        c["files"]["start.json"] = model
        c["files"]["t.trace"] = _set_scene(trace, scene)
        c["files"]["sub/keep"] = b""
        out = rng.choice(["start.json", "sub/../start.json", "./start.json"])
        c["argv"] = ["replay", fpath("t.trace"), "--out", fpath(out)] + rng.choice([[], ["--primitive", "plane"], ["--model", fpath("start.json")]])

        def expect(d, rc, out_, err):
            with open(os.path.join(d, "start.json"), "rb") as f:
                if f.read() != model:
                    return "replay --out replaced the start model its trace names"
            return _refused(rc, err, "start model")
        c["expect"] = expect
    elif kind == "morph_dir":
        old = {f"frames/frame_{i:04d}.png": b"old" for i in range(rng.choice([1, 3, 12]))}
        if maybe(rng, 0.5):
            old["frames/notes.txt"] = b"mine"
        c["files"].update(old)
        c["files"]["f.json"] = rng.choice(seeds.figures_small)
        replace = maybe(rng, 0.5)
        frames = rng.choice([2, 3])
        no_svg = maybe(rng, 0.5)
        c["argv"] = ["morph", fpath("f.json"), fpath("f.json"), "--frames", str(frames), "--size", "16x16", "--samples", "1", "--out", fpath("frames")] + (["--replace"] if replace else []) + (["--no-svg"] if no_svg else [])

        def expect(d, rc, out, err):
            names = sorted(os.listdir(os.path.join(d, "frames")))
            frames_now = [n for n in names if n.startswith("frame_")]
            if not replace:
                if sorted("frames/" + n for n in names) != sorted(old):
                    return "morph changed a directory that was not empty without --replace"
                return _refused(rc, err, "not empty")
            if rc != 0:
                return f"morph --replace failed: {err[-300:]!r}"
            if len(frames_now) != frames * (1 if no_svg else 2):
                return f"{len(frames_now)} frame files after --replace of {frames} frames: old frames left"
            if "frames/notes.txt" in old and "notes.txt" not in names:
                return "morph --replace removed a file that is not a frame"
            return None
        c["expect"] = expect
    else:  # emulate_link
        c["paths"]["link"] = PathSpec("symlink", b"mine")
        c["argv"] = ["emulate", rng.choice(["fastrak", "flock", "cyberglove"]), "--seconds", "0.2", "--link", fpath("link")]

        def expect(d, rc, out, err):
            link = os.path.join(d, "link")
            if not os.path.islink(link) or os.readlink(link) != link + ".real":
                return "emulate --link replaced or removed the user's own link"
            with open(link + ".real", "rb") as f:
                if f.read() != b"mine":
                    return "emulate --link changed the user's file"
            return _refused(rc, err, "not one an emulator made")
        c["expect"] = expect
    c["sub"] = "bounds"
    return c


GENERATORS = {
    "sculpt": gen_sculpt,
    "check": gen_check,
    "render": gen_render,
    "export": gen_export,
    "replay": gen_replay,
    "closest": lambda r, s: gen_batch("closest", r, s),
    "curve": lambda r, s: gen_batch("curve", r, s),
    "figure": gen_figure,
    "morph": gen_morph,
    "devices": gen_devices,
    "record": gen_record,
    "refine": gen_refine,
    "bounds": gen_bounds,
}


# ---------------------------------------------------------------------------------------------
# Running one case.


def make_path(d, name, spec):
    p = os.path.join(d, name)
    os.makedirs(os.path.dirname(p), exist_ok=True)
    k = spec.kind
    content = spec.content if spec.content is not None else b"{}"
    if k == "dir":
        os.makedirs(p, exist_ok=True)
    elif k == "existing_dir_slash":
        os.makedirs(p, exist_ok=True)
        return p + "/"
    elif k == "dev_full":
        os.symlink("/dev/full", p)
    elif k == "dev_null":
        os.symlink("/dev/null", p)
    elif k in ("fifo", "fifo_empty"):
        os.mkfifo(p)
    elif k == "symlink":
        real = p + ".real"
        with open(real, "wb") as f:
            f.write(content)
        os.symlink(real, p)
    elif k == "dangling":
        os.symlink(os.path.join(d, "nowhere", "x"), p)
    elif k == "loop":
        os.symlink(p, p)
    elif k == "missing_dir":
        pass  # the argv already names {d}/name; replaced below by a path under a missing dir
    elif k == "empty_name":
        pass
    elif k == "long_name":
        pass
    return None


def argv_path_override(d, name, spec):
    p = os.path.join(d, name)
    if spec.kind == "missing_dir":
        return os.path.join(d, "missing", "deeper", os.path.basename(name))
    if spec.kind == "empty_name":
        return ""
    if spec.kind == "long_name":
        return os.path.join(d, "n" * 300 + os.path.splitext(name)[1])
    if spec.kind == "existing_dir_slash":
        return p + "/"
    return p


def fifo_feeder(path, data, stop):
    """Write data into a fifo once the program opens it for reading (never blocks for good)."""
    while not stop.is_set():
        try:
            fd = os.open(path, os.O_WRONLY | os.O_NONBLOCK)
        except OSError:
            time.sleep(0.005)
            continue
        try:
            os.set_blocking(fd, True)
            view = memoryview(data)
            while view and not stop.is_set():
                try:
                    n = os.write(fd, view[:65536])
                    view = view[n:]
                except BlockingIOError:
                    time.sleep(0.001)
        except OSError:
            pass
        finally:
            os.close(fd)
        return


def pty_feeder(master, data, stop):
    """Feed the device bytes into the pseudo-terminal, drain what the program sends."""
    os.set_blocking(master, False)
    view = memoryview(data)
    while not stop.is_set():
        try:
            os.read(master, 4096)
        except (BlockingIOError, OSError):
            pass
        if view:
            try:
                n = os.write(master, view[:256])
                view = view[n:]
            except (BlockingIOError, OSError):
                pass
        time.sleep(0.002)


class Result:
    def __init__(self, rc, err, timed_out, seconds):
        self.rc = rc
        self.err = err
        self.timed_out = timed_out
        self.seconds = seconds
        self.violation = None


def run_case(cfg, case):
    """Run a case in a fresh directory; returns a Result."""
    d = tempfile.mkdtemp(prefix="c", dir=cfg.work)
    stop = threading.Event()
    threads = []
    master = slave = None
    try:
        for name, data in case["files"].items():
            p = os.path.join(d, name)
            os.makedirs(os.path.dirname(p), exist_ok=True)
            with open(p, "wb") as f:
                f.write(data)
        overrides = {}
        for name, spec in case["paths"].items():
            make_path(d, name, spec)
            overrides["{d}/" + name] = argv_path_override(d, name, spec)
            if spec.kind == "fifo" and spec.content is not None:
                t = threading.Thread(target=fifo_feeder, args=(os.path.join(d, name), spec.content, stop), daemon=True)
                t.start()
                threads.append(t)
        ptyname = "/nonexistent/pty"
        if any("{pty}" in a for a in case["argv"]):
            master, slave = pty.openpty()
            ptyname = os.ttyname(slave)
            t = threading.Thread(target=pty_feeder, args=(master, case["pty_bytes"] or b"", stop), daemon=True)
            t.start()
            threads.append(t)
        argv = [cfg.binary]
        # an argument cannot hold a NUL byte (exec refuses it): generators may produce one
        case["argv"] = [a.replace("\x00", "") for a in case["argv"]]
        for a in case["argv"]:
            if a in overrides:
                argv.append(overrides[a])
            else:
                argv.append(a.replace("{d}", d).replace("{pty}", ptyname))
        stdout = open("/dev/full", "wb") if case["stdout_full"] else (subprocess.PIPE if case.get("capture") else subprocess.DEVNULL)
        limit = cfg.mem_bytes

        def pre():
            resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
            resource.setrlimit(resource.RLIMIT_CORE, (0, 0))

        t0 = time.monotonic()
        timed_out = False
        p = subprocess.Popen(
            argv,
            stdin=subprocess.PIPE if case["stdin"] is not None else subprocess.DEVNULL,
            stdout=stdout,
            stderr=subprocess.PIPE,
            cwd=d,
            env=cfg.env,
            preexec_fn=pre,
            start_new_session=True,
        )
        try:
            out, err = p.communicate(input=case["stdin"], timeout=cfg.timeout)
        except subprocess.TimeoutExpired:
            timed_out = True
            try:
                os.killpg(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            out, err = p.communicate()
        if stdout not in (subprocess.DEVNULL, subprocess.PIPE):
            stdout.close()
        res = Result(p.returncode, err or b"", timed_out, time.monotonic() - t0)
        if "expect" in case and not timed_out and p.returncode >= 0:
            res.violation = case["expect"](d, p.returncode, out or b"", err or b"")
        return res
    finally:
        stop.set()
        for t in threads:
            t.join(timeout=2)
        for fd in (master, slave):
            if fd is not None:
                try:
                    os.close(fd)
                except OSError:
                    pass
        shutil.rmtree(d, ignore_errors=True)


PANIC_RE = re.compile(rb"panicked at ([^\n]*?):(\d+):\d+:\n([^\n]*)")
PANIC_OLD_RE = re.compile(rb"panicked at '([^\n]*)', ([^\n]*?):(\d+):\d+")


def classify(case, res):
    """None for an expected outcome, else (kind, dedup key, summary)."""
    err = res.err
    if res.timed_out:
        return ("timeout", f"timeout in {case['sub']} {case['argv'][1] if case['sub'] == 'figure' else ''}".strip(), "timed out")
    crashed = res.rc == 101 or b"panicked" in err or res.rc < 0 or b"memory allocation of" in err
    if not crashed:
        if res.violation:
            return ("violation", f"violation {case.get('kind', case['sub'])}: {re.sub(r'[0-9]+', '#', res.violation)[:80]}", res.violation[:300])
        return None
    m = PANIC_RE.search(err)
    if m:
        loc = m.group(1).decode(errors="replace")
        msg = m.group(3).decode(errors="replace")
        key = f"panic {loc} {re.sub(r'[0-9]+', '#', msg)[:120]}"
        if loc.startswith("/rustc/") or "/.cargo/" in loc:
            # a panic inside std or a dependency: which subcommand reached it tells them apart
            key += f" in {case['sub']}" + (f" {case['argv'][1]}" if case["sub"] == "figure" else "")
        return ("panic", key, f"panicked at {loc}:{m.group(2).decode()}: {msg[:300]}")
    m = PANIC_OLD_RE.search(err)
    if m:
        loc = m.group(2).decode(errors="replace")
        msg = m.group(1).decode(errors="replace")
        key = f"panic {loc} {re.sub(r'[0-9]+', '#', msg)[:120]}"
        return ("panic", key, f"panicked at {loc}: {msg[:300]}")
    if b"memory allocation of" in err:
        return ("alloc", f"allocation failure in {case['sub']}", err.decode(errors="replace")[:300])
    if res.rc < 0:
        try:
            sig = signal.Signals(-res.rc).name
        except ValueError:
            sig = str(-res.rc)
        return ("signal", f"signal {sig} in {case['sub']}", f"killed by {sig}: {err.decode(errors='replace')[-300:]}")
    return ("panic", f"exit 101 in {case['sub']}", err.decode(errors="replace")[-300:])


# ---------------------------------------------------------------------------------------------
# Shrinking and saving reproducers.


def shrink(cfg, case, key, budget=120):
    """Smaller input with the same crash key: fewer lines, then fewer bytes (bounded effort)."""
    target = case["shrink"]
    if target is None:
        return case

    def get(c):
        return c["stdin"] if target == "stdin" else c["files"].get(target)

    def put(c, data):
        c = dict(c)
        c["files"] = dict(c["files"])
        if target == "stdin":
            c["stdin"] = data
        else:
            c["files"][target] = data
        return c

    data = get(case)
    if data is None:
        return case
    tries = [0]

    def same(d):
        if tries[0] >= budget:
            return False
        tries[0] += 1
        c = put(case, d)
        res = run_case(cfg, c)
        cl = classify(c, res)
        return cl is not None and cl[1] == key

    # lines first (batch requests, ops, traces keep their header by trying single removals)
    lines = data.split(b"\n")
    if len(lines) > 1:
        for i in range(len(lines)):
            if lines[i].strip() and same(lines[i] + b"\n"):
                data = lines[i] + b"\n"
                lines = [lines[i]]
                break
        i = len(lines) - 1
        while i >= 0 and len(lines) > 1 and tries[0] < budget:
            cand = lines[:i] + lines[i + 1:]
            if same(b"\n".join(cand)):
                lines = cand
            i -= 1
        data = b"\n".join(lines)
    # then byte chunks, halving
    chunk = max(1, len(data) // 2)
    while chunk >= 1 and tries[0] < budget:
        i = 0
        changed = False
        while i < len(data) and tries[0] < budget:
            cand = data[:i] + data[i + chunk:]
            if same(cand):
                data = cand
                changed = True
            else:
                i += chunk
        if not changed:
            chunk //= 2
    return put(case, data)


def shell_quote(s):
    if re.fullmatch(r"[A-Za-z0-9_./:=@%+,-]+", s):
        return s
    return "'" + s.replace("'", "'\"'\"'") + "'"


def save_repro(cfg, idx, case, crash, res):
    d = os.path.join(cfg.out, f"crash-{idx:03d}")
    os.makedirs(d, exist_ok=True)
    for name, data in case["files"].items():
        p = os.path.join(d, "input", name)
        os.makedirs(os.path.dirname(p), exist_ok=True)
        with open(p, "wb") as f:
            f.write(data)
    setup = []
    for name, spec in case["paths"].items():
        parent = f'mkdir -p "$(dirname "$D/{name}")"'
        k = spec.kind
        if k == "dir" or k == "existing_dir_slash":
            setup.append(f'mkdir -p "$D/{name}"')
        elif k in ("dev_full", "dev_null"):
            setup += [parent, f'ln -sf /dev/{k[4:]} "$D/{name}"']
        elif k in ("fifo", "fifo_empty"):
            setup += [parent, f'rm -f "$D/{name}"; mkfifo "$D/{name}"']
            if spec.content is not None:
                p = os.path.join(d, "input", name + ".content")
                os.makedirs(os.path.dirname(p), exist_ok=True)
                with open(p, "wb") as f:
                    f.write(spec.content)
                setup.append(f'(cat "$D/{name}.content" > "$D/{name}" &)')
        elif k == "symlink":
            p = os.path.join(d, "input", name + ".real")
            os.makedirs(os.path.dirname(p), exist_ok=True)
            with open(p, "wb") as f:
                f.write(spec.content or b"{}")
            setup += [f'ln -sf "$D/{name}.real" "$D/{name}"']
        elif k == "dangling":
            setup += [parent, f'ln -sf "$D/nowhere/x" "$D/{name}"']
        elif k == "loop":
            setup += [parent, f'ln -sf "$D/{name}" "$D/{name}"']
    args = []
    for a in case["argv"]:
        spec = None
        for name, s in case["paths"].items():
            if a == "{d}/" + name:
                spec = (name, s)
        if spec is not None and spec[1].kind in ("missing_dir", "empty_name", "long_name", "existing_dir_slash"):
            name, s = spec
            a = {"missing_dir": "{d}/missing/deeper/" + os.path.basename(name), "empty_name": "", "long_name": "{d}/" + "n" * 300 + os.path.splitext(name)[1], "existing_dir_slash": "{d}/" + name + "/"}[s.kind]
        if "{pty}" in a:
            a = a.replace("{pty}", "$PTY")
        if "{d}" in a:
            args.append('"' + a.replace("{d}", "$D") + '"')
        else:
            args.append(shell_quote(a))
    cmd = '"$BIN" ' + " ".join(args)
    if case["stdin"] is not None:
        with open(os.path.join(d, "stdin"), "wb") as f:
            f.write(case["stdin"])
        cmd += ' < "$HERE/stdin"'
    if case["stdout_full"]:
        cmd += " > /dev/full"
    notes = ""
    if case["pty_bytes"] is not None and any("{pty}" in a for a in case["argv"]):
        with open(os.path.join(d, "device.bin"), "wb") as f:
            f.write(case["pty_bytes"])
        notes = "# $PTY: a pseudo-terminal whose other end sends device.bin (e.g. socat -d PTY,link=/tmp/pty,raw SYSTEM:'cat device.bin'; PTY=/tmp/pty)\n"
    script = (
        "#!/bin/sh\n"
        f"# {crash[0]}: {crash[2]}\n"
        f"# subcommand {case['sub']}, case {case.get('id', '?')} (rerun: scripts/crash-hunt.py --seed {cfg.seed} --replay-case {case.get('id', '?')})\n"
        + notes
        + 'HERE="$(cd "$(dirname "$0")" && pwd)"\n'
        'BIN="${BIN:-target/release/nendo}"\n'
        'D="$(mktemp -d)"\n'
        'if [ -d "$HERE/input" ]; then cp -a "$HERE/input/." "$D/"; fi\n'
        'PTY="${PTY:-/nonexistent/pty}"\n'
        + "".join(s + "\n" for s in setup)
        + "ulimit -v " + str(cfg.mem_bytes // 1024) + "\n"
        + cmd
        + "\necho \"exit status $?\"\n"
    )
    with open(os.path.join(d, "repro.sh"), "w") as f:
        f.write(script)
    os.chmod(os.path.join(d, "repro.sh"), 0o755)
    with open(os.path.join(d, "stderr.txt"), "wb") as f:
        f.write(res.err[-20000:])
    return d, cmd


# ---------------------------------------------------------------------------------------------


class Config:
    pass


def case_for(cfg, seeds, sub, i):
    """The i-th case of a subcommand; depends only on (seed, sub, i)."""
    rng = random.Random(f"{cfg.seed}:{sub}:{i}")
    c = GENERATORS[sub](rng, seeds)
    c["id"] = f"{sub}:{i}"
    return c


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "target/release/nendo"))
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--count", type=int, default=DEFAULT_COUNT, help="total inputs (default 84 000)")
    ap.add_argument("--only", default="", help="comma-separated subcommands")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=20.0)
    ap.add_argument("--mem-gb", type=float, default=4.0)
    ap.add_argument("--out", default=os.path.join(ROOT, "target", "crash-hunt"))
    ap.add_argument("--replay-case", default="", help="SUB:I — run that one input and print its outcome")
    ap.add_argument("--no-shrink", action="store_true", help="save crashes as found, without shrinking")
    ap.add_argument("--window-count", type=int, default=40, help="cases of the window class (--only window)")
    ap.add_argument("--max-seconds", type=float, default=0, help="stop starting inputs after this long and report (0: no limit)")
    args = ap.parse_args()

    cfg = Config()
    cfg.binary = os.path.abspath(args.bin)
    if not os.access(cfg.binary, os.X_OK):
        sys.exit(f"crash-hunt: no executable at {cfg.binary} (cargo build --release --bin nendo)")
    cfg.seed = args.seed
    cfg.timeout = args.timeout
    cfg.mem_bytes = int(args.mem_gb * (1 << 30))
    cfg.out = os.path.abspath(args.out)
    os.makedirs(cfg.out, exist_ok=True)
    cfg.work = tempfile.mkdtemp(prefix="nendo-crash-hunt-")
    runtime = os.path.join(cfg.work, "xdg-runtime")
    os.makedirs(runtime, mode=0o700)
    cfg.env = dict(os.environ)
    cfg.env.update(
        {
            "XDG_RUNTIME_DIR": os.environ.get("XDG_RUNTIME_DIR") or runtime,
            "XDG_STATE_HOME": os.path.join(cfg.work, "state"),
            "RUST_BACKTRACE": "0",
            "LC_ALL": "C.UTF-8",
        }
    )
    try:
        seeds = Seeds(cfg.binary, cfg.work)
        if args.replay_case:
            sub, _, i = args.replay_case.partition(":")
            c = case_for(cfg, seeds, sub, int(i))
            print("argv:", c["argv"], "files:", {k: len(v) for k, v in c["files"].items()}, "paths:", {k: v.kind for k, v in c["paths"].items()})
            res = run_case(cfg, c)
            print("exit", res.rc, "timed out" if res.timed_out else "", f"{res.seconds:.2f}s")
            print(res.err.decode(errors="replace")[-3000:])
            cl = classify(c, res)
            print("crash:" if cl else "no crash", cl or "")
            if cl:
                save_repro(cfg, 999, c, cl, res)
            return 1 if cl else 0
        only = [o for o in args.only.split(",") if o]
        window_found = []
        if "window" in only:
            # The window class (scripts/crash_hunt_window.py): its own count, cases one at a
            # time on one Xvfb display; run before the other classes named with it.
            sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
            import crash_hunt_window
            n = args.window_count
            print(f"crash-hunt: window class, seed {cfg.seed}, {n} cases, binary {cfg.binary}", flush=True)
            ran, window_found, outcomes = crash_hunt_window.run_window_hunt(
                cfg, seeds, n, (mutate_json_text, mutate_lines, mutate_line_json_or_tokens)
            )
            print(f"\nwindow: {ran} cases ({', '.join(f'{v} {k}' for k, v in sorted(outcomes.items()))}), {len(window_found)} with a violation")
            for cid, violations, repro in window_found:
                print(f"- [{cid}] {'; '.join(violations)[:400]}\n    reproducer {repro}")
            only = [o for o in only if o != "window"]
            if not only:
                return 1 if window_found else 0
        subs = [s for s in SHARES if not only or s in only]
        total_share = sum(SHARES[s] for s in subs)
        plan = []
        counts = {}
        for s in subs:
            n_inputs = max(1, round(args.count * SHARES[s] / total_share))
            per = BATCH_LINES if s in ("closest", "curve") else 1
            n_runs = max(1, (n_inputs + per - 1) // per)
            counts[s] = [0, 0, 0.0]  # inputs, runs, seconds
            plan += [(s, i) for i in range(n_runs)]
        # interleave the subcommands so a partial run still covers all of them
        random.Random(cfg.seed).shuffle(plan)
        crashes = {}
        kinds = {"panic": 0, "signal": 0, "alloc": 0, "timeout": 0, "violation": 0}
        harness_errors = []
        lock = threading.Lock()
        stop_flag = threading.Event()

        def on_signal(signum, frame):
            print(f"\n  signal {signum}: finishing the inputs under way, then reporting", flush=True)
            stop_flag.set()

        signal.signal(signal.SIGINT, on_signal)
        signal.signal(signal.SIGTERM, on_signal)
        done = [0]
        t_start = time.monotonic()

        def one(item):
            s, i = item
            if stop_flag.is_set() or (args.max_seconds and time.monotonic() - t_start > args.max_seconds):
                stop_flag.set()
                return
            try:
                c = case_for(cfg, seeds, s, i)
                res = run_case(cfg, c)
            except Exception as e:  # a harness bug must not end the run; it is counted
                with lock:
                    harness_errors.append(f"{s}:{i}: {type(e).__name__}: {e}")
                    if len(harness_errors) <= 5:
                        print(f"  harness error in {s}:{i}: {type(e).__name__}: {e}", flush=True)
                return
            cl = classify(c, res)
            with lock:
                counts[s][0] += c["lines"]
                counts[s][1] += 1
                counts[s][2] += res.seconds
                done[0] += 1
                if cl and cl[1] not in crashes:
                    crashes[cl[1]] = {"case": c, "crash": cl, "res": res, "hits": 0}
                    print(f"  NEW {cl[0]}: {cl[2][:200]}  [{c['id']}]", flush=True)
                if cl:
                    crashes[cl[1]]["hits"] += 1
                    kinds[cl[0]] = kinds.get(cl[0], 0) + 1
                if done[0] % 2000 == 0:
                    el = time.monotonic() - t_start
                    per = ", ".join(f"{k} {v[0]}" for k, v in counts.items())
                    print(f"  {done[0]}/{len(plan)} runs, {el:.0f} s, {len(crashes)} distinct crashes; inputs: {per}", flush=True)

        print(f"crash-hunt: seed {cfg.seed}, {sum(max(1, round(args.count * SHARES[s] / total_share)) for s in subs)} inputs in {len(plan)} runs, {args.jobs} workers, binary {cfg.binary}", flush=True)
        with ThreadPoolExecutor(max_workers=args.jobs) as ex:
            for _ in ex.map(one, plan):
                pass
        elapsed = time.monotonic() - t_start
        if stop_flag.is_set():
            print(f"\nSTOPPED EARLY after {done[0]} of {len(plan)} runs (--max-seconds or a signal): not a full run")
        print(f"\nper subcommand (inputs, runs, CPU-seconds of runs):")
        for s in subs:
            n, r, sec = counts[s]
            print(f"  {s:8s} {n:7d} inputs {r:7d} runs {sec:8.0f} s")
        print(f"  {'total':8s} {sum(v[0] for v in counts.values()):7d} inputs {sum(v[1] for v in counts.values()):7d} runs, wall {elapsed:.0f} s")
        print("  outcomes: " + ", ".join(f"{n} {k}{'s' if n != 1 else ''}" for k, n in kinds.items()) + " (panics, signals, allocation failures, timeouts, oracle violations)")
        if harness_errors:
            print(f"  {len(harness_errors)} inputs not run (harness errors), e.g. {harness_errors[0]}")
        idx = 0
        panics = [v for v in crashes.values() if v["crash"][0] not in ("timeout", "violation")]
        violations = [v for v in crashes.values() if v["crash"][0] == "violation"]
        hangs = [v for v in crashes.values() if v["crash"][0] == "timeout"]
        for title, group in (("crashes", panics), ("timeouts", hangs), ("oracle violations", violations)):
            print(f"\n{len(group)} distinct {title}:")
            for v in sorted(group, key=lambda v: v["crash"][1]):
                idx += 1
                c = v["case"]
                if not args.no_shrink and v["crash"][0] not in ("timeout", "violation"):
                    c = shrink(cfg, c, v["crash"][1])
                d, cmd = save_repro(cfg, idx, c, v["crash"], v["res"])
                print(f"- [{v['crash'][0]}] {v['crash'][2][:400]}\n    hits {v['hits']}, first {c['id']}, reproducer {d}/repro.sh\n    {cmd[:400]}")
        return 1 if crashes or harness_errors or window_found else 0
    finally:
        shutil.rmtree(cfg.work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())

"""The network kinds of benchmarks/fuzz.py: mutated ``bus.yml`` files (kind ``yaml``) and
CiA 306-3 ``.cpj`` projects (kind ``cpj``) through ``network check`` and ``network build``.

Seeds: the network files under tests/ (their node files copied next to the variant, so the
references resolve) plus the built-in ones below. YAML mutations: truncation, a value of
the wrong type anywhere (a list, a mapping, null, a float, a string, a date, a tag), huge
numbers, alias bombs ("billion laughs"), deep nesting, 10,000 slaves, repeated keys,
broken indentation, hostile node files (missing, a directory, a FIFO, /dev/zero, an empty
name), random known keys, and the byte and encoding mutations of the DCFs. .cpj mutations:
the INI mutations of the DCFs, random NodeX keys (X out of range, values not 0/1), hostile
DCF names, 127 present nodes, more [TopologyN] sections. ``--net N`` is drawn for a .cpj.
"""
from __future__ import annotations

import os
import random
import re
import shutil
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
NET_FIXTURES = ROOT / "tests" / "fixtures" / "network"
GOLDEN = ROOT / "tests" / "golden" / "network"

# what a dcf: / NodeXDCFName may name in the variant's folder (Runner.setup makes them)
HOSTILE_FILES = ["missing.eds", "adir", "fifo", "/dev/zero", "", ".", "..", "plc.dcf/x",
                 "x" * 300, "a\x00b", "IoX4_8AI.eds", "technosoft.eds", "canopennode.eds",
                 "plc.dcf", "check/io.dcf", "~/x.eds", "\u00e9.eds", "empty.eds"]
WRONG = ["[1, 2]", "{a: 1}", "~", "null", "1.5", "-1", "true", "no", "'x'", "\"0x1A0G\"",
         "2001-01-01", "!!binary AAAA", "!!python/object:os.system x", "0b1111", "0o17",
         "010", "0x" + "F" * 300, "9" * 400, "1e309", ".inf", ".nan", "auto", "''", "[]",
         "{}", "*undefined", "&a", "\"$NODEID+1\"", "-0x80000000", "4294967296",
         "18446744073709551616", "{index: 0x6000}", "[{index: 1, sub_index: 300}]"]
KEYS = ["node_id", "dcf", "eds", "heartbeat_producer", "heartbeat_consumer", "sync_period",
        "sync_window", "tpdo", "rpdo", "mapping", "cob_id", "transmission", "event_timer",
        "inhibit_time", "enabled", "sdo", "mandatory", "boot", "retry_factor", "guard_time",
        "vendor_id", "bitrate", "baudrate", "heartbeat_multiplier", "name", "defaults",
        "nodes", "options", "master", "<<", "heartbeat_prodcuer", "driver", "sub_index",
        "index", "value", "software_version", "life_time_factor", "boot_time"]

BUILTIN_CPJ = (b"[Topology]\nNetName=fuzz\nNodes=3\nEDSBaseName=.\n"
               b"Node1Present=0x01\nNode1Name=plc\nNode1DCFName=plc.dcf\n"
               b"Node2Present=0x01\nNode2Name=io\nNode2DCFName=io.dcf\nNode2Refd=1\n"
               b"Node3Present=1\nNode3Name=spare\nNode3DCFName=io3.dcf\n"
               b"[Topology2]\nNetName=second\nNodes=1\nNode5Present=1\nNode5DCFName=io.dcf\n")


def _local(text: bytes) -> bytes:
    """A seed's node files named as they lie next to the variant (in the net folder)."""
    text = text.replace(b"@BUS_CONFIG_PATH@/../../../fixtures/network/", b"")
    return re.sub(rb"dcf: \.\./", b"dcf: ", text)


def seeds(kind: str) -> list[tuple[str, bytes]]:
    """(name, bytes) of every seed of ``kind`` ('yaml' or 'cpj'), sorted."""
    out = []
    if kind == "yaml":
        files = sorted(NET_FIXTURES.rglob("*.yml")) + sorted(GOLDEN.glob("*/bus.yml"))
        for p in files:
            out.append((p.relative_to(ROOT).as_posix(), _local(p.read_bytes())))
    else:
        for p in sorted(NET_FIXTURES.rglob("*.cpj")):
            out.append((p.relative_to(ROOT).as_posix(), p.read_bytes()))
        out.append(("builtin.cpj", BUILTIN_CPJ))
    return out


def setup(workdir: Path) -> Path:
    """The folder variants are written to: the network fixtures, and what hostile names
    point at (a directory, a FIFO, an empty file)."""
    net = workdir / "net"
    shutil.copytree(NET_FIXTURES, net)
    (net / "adir").mkdir()
    (net / "empty.eds").write_bytes(b"")
    if hasattr(os, "mkfifo"):
        os.mkfifo(net / "fifo")
        os.mkfifo(net / "check" / "fifo")
    return net


# -- YAML mutations ---------------------------------------------------------------------------

_VALUE_LINE = re.compile(rb"(?m)^(\s*-?\s*[A-Za-z_<][\w<]*:)[ \t]*(\S.*)$")
_NUMBER = re.compile(rb"(?<=[\s:,\[{-])(?:0[xX][0-9A-Fa-f]+|[0-9]+)(?=[\s,\]}]|$)")


def y_value(rng, data, other):
    spots = list(_VALUE_LINE.finditer(data))
    if not spots:
        return y_key(rng, data, other)
    m = rng.choice(spots)
    value = rng.choice(WRONG).encode("utf-8", "surrogatepass")
    return data[:m.start(2)] + value + data[m.end(2):], f"value {value[:12]!r}"


def y_huge(rng, data, other):
    spots = [m.span() for m in _NUMBER.finditer(data)]
    if not spots:
        return y_value(rng, data, other)
    a, b = rng.choice(spots)
    value = rng.choice(["9" * 30, "0x" + "F" * 40, "128", "0", "65536", "4294967295",
                        "-1", "1" * 5000, "99999999999999999999999"])
    return data[:a] + value.encode() + data[b:], f"huge {value[:12]}"


def y_bomb(rng, data, other):
    """A billion-laughs alias bomb, used by a slave's sdo: or a top-level key."""
    width = rng.choice([9, 10, 30])
    text = 'lol0: &lol0 ["lol"' + ',"lol"' * (width - 1) + "]\n"
    for n in range(1, rng.choice([4, 9, 12])):
        text += f"lol{n}: &lol{n} [" + ",".join([f"*lol{n - 1}"] * width) + "]\n"
    use = rng.choice([f"bomb: *lol{n}\n", f"  sdo: *lol{n}\n"])
    lines = data.split(b"\n")
    lines.insert(rng.randrange(len(lines) + 1), use.rstrip("\n").encode())
    return text.encode() + b"\n".join(lines), f"alias-bomb {width}^{n}"


def y_deep(rng, data, other):
    depth = rng.choice([100, 1000, 50000])
    style = rng.choice(["flow-list", "flow-map", "block"])
    if style == "flow-list":
        text = "deep: " + "[" * depth + "]" * depth + "\n"
    elif style == "flow-map":
        text = "deep: " + "{a: " * depth + "1" + "}" * depth + "\n"
    else:
        depth = min(depth, 2000)
        text = "deep:\n" + "".join(" " * (i + 1) + f"k{i}:\n" for i in range(depth))
    return data + b"\n" + text.encode(), f"deep {style} {depth}"


def y_many_slaves(rng, data, other):
    n = rng.choice([127, 1000, 10000])
    eds = rng.choice(["IoX4_8AI.eds", "canopennode.eds", "missing.eds"])
    text = "".join(f"s{i}:\n  dcf: {eds}\n  node_id: {i % 127 + 1}\n" for i in range(n))
    return data + b"\n" + text.encode(), f"slaves {n}"


def y_dup_key(rng, data, other):
    lines = data.split(b"\n")
    i = rng.randrange(len(lines))
    lines.insert(i + 1, lines[i])
    return b"\n".join(lines), "dup-key"


def y_indent(rng, data, other):
    lines = data.split(b"\n")
    i = rng.randrange(len(lines))
    lines[i] = rng.choice([b" ", b"\t", b"   ", b""]) + lines[i].lstrip(b" ")
    return b"\n".join(lines), "indent"


def y_file(rng, data, other):
    name = rng.choice(HOSTILE_FILES)
    spots = [m.span(1) for m in re.finditer(rb"(?m)^\s*(?:dcf|eds):\s*(\S.*)$", data)]
    if not spots:
        return data + f"\nx:\n  node_id: 9\n  dcf: {name}\n".encode(), f"file {name[:12]!r}"
    a, b = rng.choice(spots)
    return data[:a] + f'"{name}"'.encode("utf-8", "surrogatepass") + data[b:], \
        f"file {name[:12]!r}"


def y_key(rng, data, other):
    lines = data.split(b"\n")
    i = rng.randrange(len(lines) + 1)
    indent = rng.choice(["", "  ", "    ", "      "])
    lines.insert(i, f"{indent}{rng.choice(KEYS)}: {rng.choice(WRONG)}".encode())
    return b"\n".join(lines), "key"


def y_truncate(rng, data, other):
    return data[:rng.randrange(len(data) + 1)], "truncate"


# -- .cpj mutations ---------------------------------------------------------------------------

def p_node(rng, data, other):
    x = rng.choice(["1", "2", "3", "5", "0", "127", "128", "99999", "-1", "x", "01", "1 "])
    key = rng.choice(["Present", "Name", "DCFName", "Refd", "Other"])
    value = rng.choice(["0", "1", "0x01", "2", "yes", "", "io.dcf", "plc.dcf", "x" * 200,
                        "0x" + "F" * 40] + HOSTILE_FILES)
    line = f"Node{x}{key}={value}".encode("utf-8", "surrogatepass")
    lines = data.split(b"\n")
    lines.insert(rng.randrange(1, len(lines) + 1), line)
    return b"\n".join(lines), f"node {line[:20]!r}"


def p_file(rng, data, other):
    name = rng.choice(HOSTILE_FILES)
    spots = [m.span(1) for m in re.finditer(rb"(?mi)^Node\d+DCFName=(.*)$", data)]
    if not spots:
        return p_node(rng, data, other)
    a, b = rng.choice(spots)
    return data[:a] + name.encode("utf-8", "surrogatepass") + data[b:], f"file {name[:12]!r}"


def p_many(rng, data, other):
    files = ["plc.dcf", "io.dcf", "io3.dcf", "../IoX4_8AI.eds"]
    text = "[Topology]\nNodes=127\n" + "".join(
        f"Node{x}Present=1\nNode{x}DCFName={rng.choice(files)}\n" for x in range(1, 128))
    return text.encode(), "127 nodes"


def p_topology(rng, data, other):
    n = rng.choice([2, 3, 10, 1000])
    text = "".join(f"\n[Topology{i}]\nNodes=1\nNode{i % 127 + 1}Present=1\n"
                   f"Node{i % 127 + 1}DCFName=io.dcf\n" for i in range(2, n + 2))
    return data + text.encode(), f"topologies {n}"


def mutations(kind: str, fuzz) -> list:
    """The mutation table of ``kind``; ``fuzz`` is benchmarks/fuzz.py (its byte mutations)."""
    common = [fuzz.m_flip, fuzz.m_nul, fuzz.m_bad_utf8, fuzz.m_utf16, fuzz.m_splice,
              fuzz.m_del_lines, fuzz.m_dup_line, fuzz.m_cr_only, fuzz.m_binary]
    if kind == "yaml":
        return common + [y_value, y_value, y_value, y_huge, y_huge, y_bomb, y_deep,
                         y_many_slaves, y_dup_key, y_indent, y_file, y_file, y_key, y_key,
                         y_truncate]
    return common + [fuzz.m_huge_number, fuzz.m_truncate, fuzz.m_long_line, fuzz.m_swap,
                     p_node, p_node, p_node, p_file, p_file, p_many, p_topology]


def commands(rng: random.Random, kind: str, path: Path, out: Path) -> list[list[str]]:
    check = ["network", "check", str(path), "-f", rng.choice(["text", "json", "sarif",
                                                              "github"])]
    if rng.random() < 0.3:
        check += rng.choice([["--strict"], ["--max-load", "0"], ["--select", "NET2"],
                             ["--ignore", "DCF"], ["-q"]])
    if kind == "cpj":
        if rng.random() < 0.3:
            check += ["--net", str(rng.choice([1, 2, 3, 1000]))]
        return [check]
    cmds = [check]
    if rng.random() < 0.4:
        cmds.append(["network", "build", str(path), "-o", str(out)] +
                    (["-v"] if rng.random() < 0.3 else []))
    return cmds

#!/usr/bin/env python3
"""Fuzz dcf2bin with mutated DCF/EDS files and containers, in-process, reproducibly.

    python benchmarks/fuzz.py --seed 1 --iterations 300             # a short run (the test)
    python benchmarks/fuzz.py --seed 7 --iterations 20000 --kind both --save-crashes crashes/
    python benchmarks/fuzz.py --seed 7 --only 1234                  # re-run one variant

Every variant is made from the seed files (``samples/``, ``tests/fixtures/lint/`` and, when
present, the corpus in ``../shared/corpus/files``) by one to three mutations chosen from
``(--seed, variant number)`` alone, so any variant can be rebuilt with ``--only N``.
DCF mutations: byte flips, NULs, line duplication and deletion, huge numbers, huge counts
(NrOfSeg, Lines, SubNumber, CompactSubObj, NrOfRXPDO ...), CR-only or mixed line ends,
truncation, random sections and keys, very long lines, UTF-16, bad UTF-8, splices of two
files, hostile DownloadFile names (a FIFO, a device, a symlink out of the folder, NUL).
Container mutations: byte flips, header fields set to edge values, huge counts and sizes,
truncation, appended, inserted and duplicated bytes, splices.
CSV mutations (allocate's ``name,type,direction`` lists, seeded from ``*.csv`` under samples/
and tests/ and CSV_SEEDS): random rows (names duplicated, empty, non-ASCII, 300 characters;
types by name or 0x code, invalid ones too; directions), many rows (up to 100,000, bounded
so a variant stays below 1 MB), mangled headers, broken quoting, other delimiters, hostile
cells, NULs, and the line and encoding mutations of the DCFs.

Each DCF variant goes through ``compile`` (random options), ``validate`` and, when compile
wrote a container, ``dump`` (text and JSON), sometimes ``compile --format c``, then
``simulate`` (sometimes ``--format json``, ``--emit-od``, target limits) and ``map`` in two
formats drawn from the seed; each container through ``dump`` (text, JSON, and ``compile`` of
that JSON), ``bin2dcf``, ``validate``, ``simulate`` and ``map`` (one format); each CSV through
``allocate`` and ``allocate --into samples/plc.dcf`` (and sometimes ``map`` of what
allocate wrote). ``--kind all`` (the default) takes dcf, container, csv in turn; ``both``
dcf and container only; ``network`` (or ``yaml``, ``cpj``) network files through
``network check`` and ``network build`` (benchmarks/fuzz_network.py). These are the real commands, run
in-process through click, with ``--debug`` so that an internal error surfaces as the
exception it is. A *crash* is exit status 70 or any exception; the expected outcomes
are exit 0 (ok), 1 (diagnostics) and 3 (unreadable input). A variant that runs longer
than ``--timeout`` seconds counts as a crash too (``hang``). The report gives the number of
variants, the crashes (grouped by where they happen), the slowest variant (wall-clock,
and in CPU time, which a busy machine does not inflate) and the peak memory (the
process's maximum RSS; with ``--tracemalloc``, the largest traced peak of a single
variant as well). Exit status: 0 no crash, 1 crashes, 2 usage.
"""
from __future__ import annotations

import argparse
import contextlib
import json
import os
import random
import re
import shutil
import signal
import sys
import tempfile
import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

try:
    import resource
except ImportError:  # Windows
    resource = None

CORPUS = ROOT.parent / "shared" / "corpus" / "files"
MAX_SEED_SIZE = 64 * 1024      # larger seed files make each variant slow, not more varied
MAX_GROWTH = 4 << 20           # what one duplication may add (bytes)
PLC_DCF = ROOT / "samples" / "plc.dcf"     # the base of allocate --into
MAP_FORMATS = ["text", "csv", "json", "iec", "c", "svg", "html"]
KINDS = {"both": ["dcf", "container"], "all": ["dcf", "container", "csv"],
         "network": ["yaml", "cpj"]}
NETWORK_KINDS = ("yaml", "cpj")       # benchmarks/fuzz_network.py


def _network():
    """benchmarks/fuzz_network.py, the yaml and cpj kinds (loaded when they are fuzzed)."""
    if str(HERE) not in sys.path:
        sys.path.insert(0, str(HERE))
    import fuzz_network
    return fuzz_network

# -- seeds ------------------------------------------------------------------------------------


def seed_files(kind: str, corpus: Path | None, max_size: int = MAX_SEED_SIZE) -> list[Path]:
    """The seed files of ``kind`` ('dcf', 'container' or 'csv'), sorted, so a seed is a seed.
    csv: the variable lists of samples/ and tests/ (no corpus) plus CSV_SEEDS."""
    suffixes = {"dcf": (".dcf", ".eds"), "container": (".bin",), "csv": (".csv",)}[kind]
    folders = [ROOT / "samples", ROOT / "tests" / "fixtures"]
    if kind == "csv":
        folders = [ROOT / "samples", ROOT / "tests"]
    elif corpus is not None and corpus.is_dir():
        folders.append(corpus)
    files = []
    for folder in folders:
        for p in folder.rglob("*"):
            if p.is_file() and p.suffix.lower() in suffixes and 0 < p.stat().st_size <= max_size:
                files.append(p)
    return sorted(files)


# -- mutations --------------------------------------------------------------------------------

HUGE = ["0x" + "F" * 4400, "9" * 25, "1" * 5000, "0xFFFFFFFF", "4294967296", "-1",
        "-0x80000000", "1000000", "0", "08", "0x", "+-1", "1e309", "nan", "0x" + "0" * 70 + "1",
        "18446744073709551616", "$NODEID+0xFFFFFFFF", "0x10000000000000000", "077777777777"]
COUNT_KEYS = [("DynamicChannels", "NrOfSeg"), ("Comments", "Lines"), ("2000", "SubNumber"),
              ("2000", "CompactSubObj"), ("DeviceInfo", "NrOfRXPDO"), ("DeviceInfo", "NrOfTXPDO"),
              ("DeviceInfo", "CompactPDO"), ("MandatoryObjects", "SupportedObjects"),
              ("2000Name", "NrOfEntries"), ("DynamicChannels", "MaxCnt1"),
              ("DynamicChannels", "PPOffset1"), ("1600", "SubNumber")]
KEYS = ["ParameterName", "ObjectType", "DataType", "AccessType", "DefaultValue",
        "ParameterValue", "PDOMapping", "ObjFlags", "LowLimit", "HighLimit", "SubNumber",
        "CompactSubObj", "DownloadFile", "Denotation", "NodeID", "Type1", "Dir1", "Range1",
        "PPOffset1", "PIOffset1", "MaxCnt1", "NrOfSeg", "Lines", "Line1", "1", "2", "255",
        "SupportedObjects", "Dummy0001", "CompactPDO", "NrOfRXPDO", "NrOfTXPDO", "Granularity",
        "PIOffset", "Range", "MaxCnt", "FileName", "NrOfEntries", "UploadFile"]
VALUES = ["0", "1", "0x7", "0x0007", "0x0005", "0x000F", "0x0009", "0x0008", "0x8", "0x9", "ro",
          "rw", "wo", "const", "rww", "rwr", "xx", "$NODEID+0x180", "0x180+$NODEID", "$NODEID",
          "$nodeid+", "0xA000-0xA0FF", "0xA900-0xAFFF", "0xAFFF-0xA000", "1, 2", "0, 1",
          '"quoted"', '""', "0A0B0C", "0x0A", "1.5", "-2e3", "inf", "TRUE", "x ; comment",
          "5 # c", "Motor #1", "\u00e9t\u00e9", "a\tb", "=", "=" * 20, "[2000]", "0x80000000",
          "0xC0000181"] + HUGE
DOWNLOAD_NAMES = ["payload.bin", "../outside.bin", "link", "fifo", "sub", "/dev/zero",
                  "/etc/passwd", "a\x00b", ".", "payload.bin\r", "x" * 300, "sub/../payload.bin",
                  "missing.bin", "~/payload.bin"]
SECTIONS = ["2000", "2001", "2000sub1", "2000sub0", "2000subFF", "2000sub100", "A000",
            "A000sub1", "A4C0", "A4C0sub3", "A900", "A900sub1", "AFFF", "1400", "1400sub1",
            "1600", "1600sub1", "1800", "1A00", "1A00sub1", "1018", "1018sub5", "0001",
            "2000Name", "2000Value", "2000Denotation", "2000ObjectLinks", "DynamicChannels",
            "DeviceInfo", "DeviceComissioning", "DeviceCommissioning", "DummyUsage", "Comments",
            "MandatoryObjects", "OptionalObjects", "ManufacturerObjects", "FileInfo", "",
            "1018sub01", "10", "1A00sub", "Tool1", "M1ModuleInfo", "x]", "[", "1000 ; c"]
LONG = ["=", "9", " ", "-", ";", "a=", "0x", "[", "\t", "$NODEID+"]


def _lines(data: bytes) -> list[bytes]:
    return data.split(b"\n")


def _random_value(rng: random.Random) -> str:
    return rng.choice(VALUES) if rng.random() < 0.9 else rng.choice(DOWNLOAD_NAMES)


def m_flip(rng, data, other):
    b = bytearray(data)
    for _ in range(rng.randint(1, 8)):
        if b:
            b[rng.randrange(len(b))] = rng.randrange(256)
    return bytes(b), "flip"


def m_nul(rng, data, other):
    at = rng.randrange(len(data) + 1)
    return data[:at] + b"\x00" * rng.choice([1, 1, 2, 16]) + data[at:], "nul"


def m_dup_line(rng, data, other):
    lines = _lines(data)
    i = rng.randrange(len(lines))
    n = rng.choice([1, 2, 10, 1000, 20000])
    n = max(1, min(n, MAX_GROWTH // (len(lines[i]) + 1)))   # a variant of at most ~4 MB
    return b"\n".join(lines[:i] + [lines[i]] * n + lines[i:]), f"dup-line x{n}"


def m_dup_block(rng, data, other):
    lines = _lines(data)
    i = rng.randrange(len(lines))
    j = min(len(lines), i + rng.randint(1, 40))
    return b"\n".join(lines[:j] + lines[i:j] * rng.randint(1, 5) + lines[j:]), "dup-block"


def m_del_lines(rng, data, other):
    lines = _lines(data)
    i = rng.randrange(len(lines))
    j = min(len(lines), i + rng.choice([1, 1, 3, 20, 200]))
    return b"\n".join(lines[:i] + lines[j:]), "del-lines"


_NUMBER = re.compile(rb"(?<=[=\s,-])(?:0[xX][0-9A-Fa-f]+|[0-9]+)")


def m_huge_number(rng, data, other):
    spots = [m.span() for m in _NUMBER.finditer(data)]
    if not spots:
        return m_count_key(rng, data, other)
    a, b = rng.choice(spots)
    value = rng.choice(HUGE)
    return data[:a] + value.encode() + data[b:], f"huge-number {value[:12]}"


def m_count_key(rng, data, other):
    section, key = rng.choice(COUNT_KEYS)
    value = rng.choice(HUGE + ["1000000", "30000000", "99999999999999999999"])
    text = f"\n[{section}]\n{key}={value}\n".encode()
    return data + text, f"count {section}.{key}={value[:12]}"


def m_cr_only(rng, data, other):
    return data.replace(b"\r\n", b"\n").replace(b"\n", b"\r"), "cr-only"


def m_line_ends(rng, data, other):
    lines = _lines(data)
    i = rng.randrange(len(lines))
    end = rng.choice([b"\r", b"\r\r", b"\n\r", b" \r"])
    lines[i] = lines[i] + end
    return b"\n".join(lines), "line-end"


def m_truncate(rng, data, other):
    return data[:rng.randrange(len(data) + 1)], "truncate"


def m_section(rng, data, other):
    name = rng.choice(SECTIONS) if rng.random() < 0.8 else f"{rng.randrange(0x10000):04X}"
    keys = "".join(f"{rng.choice(KEYS)}={_random_value(rng)}\n"
                   for _ in range(rng.randint(0, 6)))
    lines = _lines(data)
    i = rng.randrange(len(lines) + 1)
    block = f"[{name}]\n{keys}".encode("utf-8")
    return b"\n".join(lines[:i] + [block] + lines[i:]), f"section [{name[:12]}]"


def m_key(rng, data, other):
    lines = _lines(data)
    i = rng.randrange(len(lines) + 1)
    line = f"{rng.choice(KEYS)}={_random_value(rng)}"
    if rng.random() < 0.1:
        line = rng.choice(["  " + line, line + " ", "=" + line, "no equals sign", "[", "]",
                           ";" + line, "#" + line, "\t" + line])
    return b"\n".join(lines[:i] + [line.encode("utf-8")] + lines[i:]), "key"


def m_long_line(rng, data, other):
    piece = rng.choice(LONG)
    n = rng.choice([300, 5000, 60000])
    key = rng.choice(["X", "ParameterName", "DefaultValue", "ParameterValue", "Range1",
                      "DataType", "Line1"])
    return data + f"\n{key}={piece * (n // len(piece))}\n".encode(), f"long-line {piece!r}"


def m_utf16(rng, data, other):
    text = data.decode("latin-1")
    codec = rng.choice(["utf-16", "utf-16-le", "utf-16-be"])
    return text.encode(codec), codec


def m_bad_utf8(rng, data, other):
    at = rng.randrange(len(data) + 1)
    junk = rng.choice([b"\xff\xfe", b"\xc3", b"\xe9", b"\xef\xbb\xbf", b"\x80\x81", b"\xed\xa0\x80"])
    return data[:at] + junk + data[at:], "bad-utf8"


def m_splice(rng, data, other):
    lines, more = _lines(data), _lines(other)
    i, j = rng.randrange(len(lines) + 1), rng.randrange(len(more) + 1)
    return b"\n".join(lines[:i] + more[j:j + rng.randint(1, 200)] + lines[i:]), "splice"


def m_swap(rng, data, other):
    lines = _lines(data)
    i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
    lines[i], lines[j] = lines[j], lines[i]
    return b"\n".join(lines), "swap"


def m_download(rng, data, other):
    name = rng.choice(DOWNLOAD_NAMES)
    obj = rng.choice(["2000", "2FFF", "1F50sub1"])
    dtype = rng.choice(["0x000F", "0x000F", "0x000A", "0x0007"])
    head = f"[{obj}]\n" if "sub" in obj else f"[{obj}]\nObjectType=0x7\n"
    text = f"\n{head}ParameterName=Domain\nDataType={dtype}\nAccessType=rw\nDownloadFile={name}\n"
    return data + text.encode("utf-8"), f"download {name[:20]!r}"


def m_binary(rng, data, other):
    return bytes(rng.randrange(256) for _ in range(rng.choice([1, 64, 9000]))), "binary"


DCF_MUTATIONS = [m_flip, m_nul, m_dup_line, m_dup_block, m_del_lines, m_huge_number,
                 m_count_key, m_cr_only, m_line_ends, m_truncate, m_section, m_key, m_key,
                 m_section, m_long_line, m_utf16, m_bad_utf8, m_splice, m_swap, m_download,
                 m_huge_number, m_binary]

# container: 40-byte header of DWORD/WORD fields (SPEC §3.1)
_FIELDS = [(0, 4), (4, 2), (6, 2), (8, 4), (12, 4), (16, 4), (20, 4), (24, 4), (28, 4), (32, 4),
           (36, 4)]


def _edge(rng, size: int, total: int) -> int:
    top = (1 << (8 * size)) - 1
    return rng.choice([0, 1, 2, 39, 40, 41, total, total - 1, total + 1, top, top >> 1,
                       rng.randrange(top + 1), 44, 0x10000])


def c_flip(rng, data, other):
    return m_flip(rng, data, other)[0], "flip"


def c_field(rng, data, other):
    off, size = rng.choice(_FIELDS)
    if len(data) < off + size:
        return c_flip(rng, data, other)
    value = _edge(rng, size, len(data)) & ((1 << (8 * size)) - 1)
    return data[:off] + value.to_bytes(size, "little") + data[off + size:], f"field@{off}"


def c_dword(rng, data, other):
    """Any DWORD (an entry count, an entry size, a PI value) set to an edge value."""
    if len(data) < 4:
        return c_flip(rng, data, other)
    off = rng.randrange(len(data) - 3)
    value = _edge(rng, 4, len(data))
    return data[:off] + value.to_bytes(4, "little") + data[off + 4:], f"dword@{off}"


def c_truncate(rng, data, other):
    return data[:rng.randrange(len(data) + 1)], "truncate"


def c_append(rng, data, other):
    return data + bytes(rng.randrange(256) for _ in range(rng.choice([1, 4, 100]))), "append"


def c_insert(rng, data, other):
    at = rng.randrange(len(data) + 1)
    return data[:at] + bytes(rng.randrange(256) for _ in range(rng.randint(1, 16))) + data[at:], \
        "insert"


def c_dup(rng, data, other):
    i = rng.randrange(len(data) + 1)
    j = min(len(data), i + rng.randint(1, 64))
    return data[:j] + data[i:j] * rng.randint(1, 4) + data[j:], "dup"


def c_splice(rng, data, other):
    i, j = rng.randrange(len(data) + 1), rng.randrange(len(other) + 1)
    return data[:i] + other[j:], "splice"


def c_fix_total(rng, data, other):
    """Keep the total-size field right after other damage, so the reader looks further."""
    if len(data) < 4:
        return data, "fix-total"
    return len(data).to_bytes(4, "little") + data[4:], "fix-total"


BIN_MUTATIONS = [c_flip, c_field, c_field, c_dword, c_dword, c_truncate, c_append, c_insert,
                 c_dup, c_splice, c_fix_total]


# allocate input: a CSV name,type,direction (dcf2bin allocate)
CSV_SEEDS = [b"name,type,direction\n",
             b"name,type,direction\nA,UNSIGNED8,input\nB,INTEGER16,output\nC,REAL32,input\n"
             b"D,BOOLEAN,output\nE,UNSIGNED64,input\nF,0x0007,output\n",
             b"name,type,direction\r\nx,0x0005,in\r\ny,0x0008,out\r\n"]
CSV_NAMES = ["A", "B", "IN0_IN7", "", " ", "Motor #1", "\u00e9t\u00e9", "\u6e29\u5ea6", "a,b",
             '"q"', "x" * 300, "1abc", "a b", "a;b", "\t", "\U0001F600", "NaN", "name",
             "_", "A" * 64, "\u0000x", "a\"b", "..", "%IX0.0"]
CSV_TYPES = ["BOOLEAN", "INTEGER8", "INTEGER16", "INTEGER32", "INTEGER64", "UNSIGNED8",
             "UNSIGNED16", "UNSIGNED32", "UNSIGNED64", "REAL32", "REAL64", "INTEGER24",
             "UNSIGNED24", "VISIBLE_STRING", "OCTET_STRING", "DOMAIN", "unsigned8", " UNSIGNED8 ",
             "0x0001", "0x0002", "0x0005", "0x0007", "0x0008", "0x0011", "0x001B", "0x7", "7",
             "0x0000", "0xFFFF", "0x10000", "0x" + "F" * 40, "0x", "0xZZ", "-1", "", "BYTE",
             "WORD", "UINT", "INT", "uint8_t", "0x0009", "0x000F", "0x0010", "0x0015"]
CSV_DIRS = ["input", "output", "input", "output", "in", "out", "INPUT", "Output", "", " input",
            "both", "tx", "rx", "inout", "\u00fcber", "input ", "0", "1"]
CSV_HEADERS = [b"name,type,direction", b"direction,type,name", b"name,type", b"name",
               b"name,type,direction,extra", b"Name,Type,Direction", b"name;type;direction",
               b"\xef\xbb\xbfname,type,direction", b"", b"name,,direction", b"name,name,name",
               b'"name","type","direction"', b"name,type,direction,", b" name , type , direction"]
MAX_CSV = 1 << 20             # a csv variant stays below 1 MB


def _csv_row(rng, names=None) -> bytes:
    if names and rng.random() < 0.3:
        name = rng.choice(names)                      # a duplicate
    elif rng.random() < 0.6:
        name = f"{rng.choice(['V', 'IN', 'OUT', 'x', 'Var_'])}{rng.randrange(10000)}"
    else:
        name = rng.choice(CSV_NAMES)
    cells = [name, rng.choice(CSV_TYPES), rng.choice(CSV_DIRS)]
    r = rng.random()
    if r < 0.05:
        cells.append(rng.choice(["", "x", "0x10", '"extra"']))
    elif r < 0.1:
        cells.pop()
    if rng.random() < 0.1:
        i = rng.randrange(len(cells))
        cells[i] = '"' + cells[i].replace('"', '""') + '"'
    return ",".join(cells).encode("utf-8", "surrogatepass")


def _csv_names(data: bytes) -> list[str]:
    return [line.split(b",")[0].decode("utf-8", "replace") for line in _lines(data)[1:6]]


def v_rows(rng, data, other):
    names = _csv_names(data)
    rows = [_csv_row(rng, names) for _ in range(rng.randint(1, 12))]
    body = data if data.endswith(b"\n") or not data else data + b"\n"
    return body + b"\n".join(rows) + b"\n", f"rows x{len(rows)}"


def v_many_rows(rng, data, other):
    row = _csv_row(rng, _csv_names(data))
    n = rng.choice([100, 1000, 10000, 100000])
    vary = rng.random() < 0.5         # numbered names (distinct) or the same row (duplicates)
    size = len(row) + 8
    n = max(1, min(n, (MAX_CSV - len(data)) // (size + 1) - 1))
    if vary:
        parts = row.split(b",", 1)
        rows = [parts[0] + str(k).encode() + (b"," + parts[1] if len(parts) > 1 else b"")
                for k in range(n)]
    else:
        rows = [row] * n
    body = data if data.endswith(b"\n") or not data else data + b"\n"
    return body + b"\n".join(rows) + b"\n", f"many-rows x{n}{' distinct' if vary else ''}"


def v_header(rng, data, other):
    lines = _lines(data)
    head = rng.choice(CSV_HEADERS)
    if rng.random() < 0.2:
        return b"\n".join([head] + lines), "header+"        # a second header line
    return b"\n".join([head] + lines[1:]), f"header {head[:20]!r}"


def v_quote(rng, data, other):
    at = rng.randrange(len(data) + 1)
    junk = rng.choice([b'"', b'"', b'""', b'"a""b', b'"\n', b',"', b'\\"', b"'", b'"x"y'])
    return data[:at] + junk + data[at:], "quote"


def v_delim(rng, data, other):
    sep = rng.choice([b";", b"\t", b"|", b", ", b",,"])
    return data.replace(b",", sep), f"delim {sep!r}"


def v_cell(rng, data, other):
    """One cell of one row replaced with a hostile value."""
    lines = _lines(data)
    i = rng.randrange(len(lines))
    cells = lines[i].split(b",")
    j = rng.randrange(len(cells))
    value = rng.choice(CSV_NAMES + CSV_TYPES + CSV_DIRS + HUGE)
    cells[j] = value.encode("utf-8", "surrogatepass")
    lines[i] = b",".join(cells)
    return b"\n".join(lines), "cell"


CSV_MUTATIONS = [v_rows, v_rows, v_rows, v_many_rows, v_header, v_quote, v_quote, v_delim,
                 v_cell, v_cell, m_nul, m_flip, m_truncate, m_dup_line, m_del_lines, m_swap,
                 m_cr_only, m_line_ends, m_utf16, m_bad_utf8, m_splice, m_binary]


def mutate(rng: random.Random, data: bytes, other: bytes, kind: str) -> tuple[bytes, list[str]]:
    if kind in NETWORK_KINDS:
        table = _network().mutations(kind, sys.modules[__name__])
    else:
        table = {"dcf": DCF_MUTATIONS, "container": BIN_MUTATIONS, "csv": CSV_MUTATIONS}[kind]
    ops = []
    for _ in range(rng.choice([1, 1, 2, 3])):
        data, what = rng.choice(table)(rng, data, other)
        ops.append(what)
    if kind == "csv" and len(data) >= MAX_CSV:     # m_dup_line may grow past the bound
        data, ops = data[:MAX_CSV - 1], ops + ["cut"]
    if kind == "container" and rng.random() < 0.5:
        data, what = c_fix_total(rng, data, other)
        ops.append(what)
    return data, ops


# -- running ----------------------------------------------------------------------------------


class Hang(BaseException):
    """Raised by the alarm: a BaseException, so that no ``except Exception`` swallows it."""


@dataclass
class Crash:
    key: str                 # where: exception type and innermost dcf2bin frame
    variant: int
    kind: str
    seed_file: str
    ops: list[str]
    command: list[str]
    detail: str


@dataclass
class Report:
    seed: int
    variants: int = 0
    by_kind: dict = field(default_factory=dict)
    commands: int = 0
    exit_codes: dict = field(default_factory=dict)
    crashes: list[Crash] = field(default_factory=list)
    slowest: tuple = (0.0, None)           # (wall-clock seconds, description)
    slowest_cpu: tuple = (0.0, None)       # (CPU seconds of this process, description)
    peak_rss_mib: float = 0.0
    peak_traced: tuple = (0.0, None)       # (MiB, description)
    seconds: float = 0.0
    ops: dict = field(default_factory=dict)

    def unique_crashes(self) -> dict[str, list[Crash]]:
        out: dict[str, list[Crash]] = {}
        for c in self.crashes:
            out.setdefault(c.key, []).append(c)
        return out

    def text(self) -> str:
        lines = [f"seed {self.seed}: {self.variants} variants "
                 f"({', '.join(f'{k} {v}' for k, v in sorted(self.by_kind.items()))}), "
                 f"{self.commands} commands in {self.seconds:.1f} s",
                 "exit codes: " + ", ".join(f"{k}: {v}" for k, v in sorted(self.exit_codes.items())),
                 f"crashes: {len(self.crashes)} ({len(self.unique_crashes())} distinct)"]
        for key, group in self.unique_crashes().items():
            c = group[0]
            lines.append(f"  {len(group)} x {key}")
            lines.append(f"     e.g. variant {c.variant} ({c.kind}, {c.seed_file}, "
                         f"{' + '.join(c.ops)}): dcf2bin {' '.join(c.command)}")
        secs, what = self.slowest
        lines.append(f"slowest variant: {secs:.2f} s wall-clock ({what})")
        secs, what = self.slowest_cpu
        lines.append(f"slowest variant in CPU time: {secs:.2f} s ({what})")
        lines.append(f"peak memory: max RSS {self.peak_rss_mib:.0f} MiB")
        if self.peak_traced[1] is not None:
            lines.append(f"largest traced peak of one variant: {self.peak_traced[0]:.1f} MiB "
                         f"({self.peak_traced[1]})")
        return "\n".join(lines) + "\n"

    def as_dict(self) -> dict:
        return {"seed": self.seed, "variants": self.variants, "by_kind": self.by_kind,
                "commands": self.commands, "exit_codes": self.exit_codes,
                "crashes": [c.__dict__ for c in self.crashes],
                "slowest_seconds": self.slowest[0], "slowest": self.slowest[1],
                "slowest_cpu_seconds": self.slowest_cpu[0], "slowest_cpu": self.slowest_cpu[1],
                "peak_rss_mib": self.peak_rss_mib, "peak_traced_mib": self.peak_traced[0],
                "peak_traced": self.peak_traced[1], "seconds": self.seconds, "ops": self.ops}


def _shown(path: Path, corpus: Path | None) -> str:
    for base, prefix in ((ROOT, ""), (corpus, "corpus/")):
        if base is not None and base in path.parents:
            return prefix + path.relative_to(base).as_posix()
    return path.name


def _max_rss_mib() -> float:
    if resource is None:
        return 0.0
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return rss / (1 << 20) if sys.platform == "darwin" else rss / 1024


# compiled up front: after a MemoryError in a command there may be no memory left to
# compile a pattern (a 15,000-variant run died there instead of reporting the crash)
_FRAME = re.compile(r'File "([^"]*dcf2bin[/\\][^"]*)", line (\d+), in (\S+)')


def _crash_key(exc_text: str) -> str:
    """Exception type and the innermost frame inside dcf2bin, from a traceback text."""
    frames = _FRAME.findall(exc_text)
    last = exc_text.strip().splitlines()[-1] if exc_text.strip() else "?"
    where = ""
    if frames:
        path, line, fn = frames[-1]
        where = f" at {Path(path).name}:{line} in {fn}"
    return f"{last.split(':')[0]}{where}"


def _forget_click_streams() -> None:
    """click caches a text wrapper per sys.stdout/sys.stderr object in a WeakKeyDictionary
    whose values keep their keys alive; CliRunner gives every invocation new streams, so
    in one process that runs thousands of commands the cache keeps every captured output
    (2.4 GB after 20,000 variants). A real dcf2bin process invokes one command; forget
    them here so that the peak memory measures dcf2bin, not the harness."""
    from weakref import WeakKeyDictionary

    from click import _compat
    for name in ("_default_text_stdin", "_default_text_stdout", "_default_text_stderr"):
        for cell in getattr(getattr(_compat, name, None), "__closure__", None) or ():
            if isinstance(cell.cell_contents, WeakKeyDictionary):
                cell.cell_contents.clear()


class Runner:
    def __init__(self, workdir: Path, timeout: float, use_tracemalloc: bool):
        from click.testing import CliRunner

        from dcf2bin.cli import main
        self.main = main
        self.cli = CliRunner()
        self.timeout = timeout
        self.current: list[str] = []       # the command running (named when it hangs)
        self.tracemalloc = use_tracemalloc
        self.dir = workdir / "dcf"
        self.dir.mkdir()
        # what hostile DownloadFile names point at
        (workdir / "outside.bin").write_bytes(b"outside")
        (self.dir / "payload.bin").write_bytes(b"\x01\x02\x03")
        (self.dir / "sub").mkdir()
        if hasattr(os, "mkfifo"):
            os.mkfifo(self.dir / "fifo")
        with contextlib.suppress(OSError, NotImplementedError):
            os.symlink(workdir / "outside.bin", self.dir / "link")
        self.net = None                    # the network kinds' folder, made when needed
        self.workdir = workdir

    def invoke(self, args: list[str]) -> tuple[int, str]:
        """(exit code, traceback text or '') of one command; Hang propagates."""
        try:
            res = self.cli.invoke(self.main, ["--debug"] + args, catch_exceptions=True)
        finally:
            _forget_click_streams()
        if res.exception is not None and not isinstance(res.exception, SystemExit):
            return 70, "".join(traceback.format_exception(*res.exc_info))
        code = res.exit_code
        if code == 70:   # validate: a check crashed (INT001); --debug printed the traceback
            return 70, res.stderr or res.stdout or ""
        return code, ""

    def commands(self, rng: random.Random, kind: str, path: Path) -> list[list[str]]:
        out = self.dir / "out.bin"
        if kind in NETWORK_KINDS:
            return _network().commands(rng, kind, path, self.workdir / "netout")
        if kind == "dcf":
            opts = []
            if rng.random() < 0.3:
                opts += ["--node-id", str(rng.choice([1, 5, 127]))]
            if rng.random() < 0.3:
                opts += ["--select", "all"]
            if rng.random() < 0.15:
                opts += ["--profile", "dis2"]
            if rng.random() < 0.1:
                opts += ["--pi-align", "1", "--address-base", "area"]
            cmds = [["compile", "-q", *opts, str(path), "-o", str(out)],
                    ["validate", "-q", "--format", rng.choice(["text", "text", "json", "sarif"]),
                     str(path)]]
            if rng.random() < 0.2:
                cmds.append(["export", "-q", "--format", rng.choice(["lenze-st", "port-c"]),
                             str(path), "-o", str(self.dir / "out.txt")])
            cmds.append(["@dump-if-written"])
            # the newer commands (their draws come after the ones above: older variants
            # run the same commands as before, plus these)
            if rng.random() < 0.3:
                cmds.append(["compile", "-q", "--format", "c", *opts, str(path),
                             "-o", str(self.dir / "out.c")])
            cmds.append(self.simulate(rng, path, dcf=True))
            for fmt in rng.sample(MAP_FORMATS, 2):
                cmds.append(self.map(rng, fmt, path, dcf=True))
            return cmds
        if kind == "csv":
            cmds = [["allocate", str(path), "-o", str(self.dir / "alloc.dcf")],
                    ["allocate", str(path), "--into", str(PLC_DCF),
                     "-o", str(self.dir / "into.dcf")]]
            if rng.random() < 0.2:
                cmds[rng.randrange(2)].append("-v")
            if rng.random() < 0.3:
                cmds.append(["@map-allocated", rng.choice(MAP_FORMATS)])
            return cmds
        return [["dump", "-q", str(path)],
                ["dump", "-q", "-f", "json", str(path), "-o", str(self.dir / "out.json")],
                ["@compile-json"],
                ["bin2dcf", "-q", str(path), "-o", str(self.dir / "back.dcf")],
                ["validate", "-q", str(path)],
                self.simulate(rng, path, dcf=False),
                self.map(rng, rng.choice(MAP_FORMATS), path, dcf=False)]

    def simulate(self, rng: random.Random, path: Path, dcf: bool) -> list[str]:
        cmd = ["simulate", str(path)]
        if rng.random() < 0.4:
            cmd += ["--format", "json"]
        if rng.random() < 0.3:
            cmd += ["--emit-od", str(self.dir / "od.dcf")]
        if rng.random() < 0.2:
            cmd += rng.choice([["--pi-size", str(rng.choice([0, 8, 100]))],
                               ["--tx-cobs", "1", "--rx-cobs", "0"], ["--granularity", "8"],
                               ["--no-bit-mapping"], ["--address-base", "area"]])
        if dcf and rng.random() < 0.2:
            cmd += ["--select", "all"]
        return cmd

    def map(self, rng: random.Random, fmt: str, path: Path, dcf: bool) -> list[str]:
        cmd = ["map", "-q", "--format", fmt, str(path), "-o", str(self.dir / "map.out")]
        if fmt == "iec" and rng.random() < 0.5:
            cmd += ["--iec-addressing", "element"]
        if not dcf and rng.random() < 0.2:
            cmd += ["--address-base", "area"]
        if dcf and rng.random() < 0.2:
            cmd += ["--pi-align", rng.choice(["1", "2", "4", "8"])]
        return cmd

    def run_variant(self, rng: random.Random, kind: str, data: bytes) -> list[tuple]:
        """Run the commands; -> [(command, exit code, traceback text)]."""
        if kind in NETWORK_KINDS:
            if self.net is None:
                self.net = _network().setup(self.workdir)
            # a .cpj names the DCFs of check/; a bus.yml the EDS files beside it
            path = self.net / ("check/fuzz.cpj" if kind == "cpj" else "fuzz.yml")
            shutil.rmtree(self.workdir / "netout", ignore_errors=True)
        else:
            suffix = {"container": ".bin", "csv": ".csv"}.get(kind) or rng.choice(
                [".dcf", ".dcf", ".eds"])
            path = self.dir / f"fuzz{suffix}"
        path.write_bytes(data)
        for name in ("out.bin", "out.json", "back.dcf", "out.txt", "out.c", "od.dcf", "map.out",
                     "alloc.dcf", "into.dcf"):
            with contextlib.suppress(FileNotFoundError):
                (self.dir / name).unlink()
        results = []
        for cmd in self.commands(rng, kind, path):
            if cmd == ["@dump-if-written"]:
                if not (self.dir / "out.bin").exists():
                    continue
                cmd = ["dump", "-q", "-f", rng.choice(["text", "json"]), str(self.dir / "out.bin")]
            elif cmd == ["@compile-json"]:
                if not (self.dir / "out.json").exists():
                    continue
                cmd = ["compile", "-q", str(self.dir / "out.json"), "-o", str(self.dir / "rt.bin")]
            elif cmd[0] == "@map-allocated":
                if not (self.dir / "alloc.dcf").exists():
                    continue
                cmd = ["map", "-q", "--format", cmd[1], str(self.dir / "alloc.dcf"),
                       "-o", str(self.dir / "map.out")]
            self.current = cmd
            code, tb = self.invoke(cmd)
            results.append((cmd, code, tb))
        return results


def fuzz(seed: int, iterations: int, kind: str = "all", corpus: Path | None = CORPUS,
         timeout: float = 60.0, use_tracemalloc: bool = False, only: int | None = None,
         save: Path | None = None, progress: bool = False, max_size: int = MAX_SEED_SIZE,
         memory_limit_mib: int | None = None) -> Report:
    kinds = KINDS.get(kind, [kind])
    seeds = {k: seed_files(k, corpus, max_size) for k in kinds if k not in NETWORK_KINDS}
    for k, files in seeds.items():
        if not files and k != "csv":
            raise SystemExit(f"fuzz: no {k} seed files found")
    blobs = {k: [p.read_bytes() for p in files] for k, files in seeds.items()}
    for k in kinds:
        if k in NETWORK_KINDS:
            found = _network().seeds(k)
            seeds[k] = [Path(name) for name, _ in found]
            blobs[k] = [data for _, data in found]
    if "csv" in seeds:
        seeds["csv"] = seeds["csv"] + [Path(f"builtin-{n}.csv") for n in range(len(CSV_SEEDS))]
        blobs["csv"] = blobs["csv"] + CSV_SEEDS
    report = Report(seed)
    if memory_limit_mib and resource is not None:
        limit = memory_limit_mib << 20
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    if use_tracemalloc:
        import tracemalloc
        tracemalloc.start()
    old_handler = None
    if hasattr(signal, "SIGALRM"):
        def on_alarm(signum, frame):
            raise Hang()
        old_handler = signal.signal(signal.SIGALRM, on_alarm)
    env_debug = os.environ.pop("DCF2BIN_DEBUG", None)
    started = time.perf_counter()
    workdir = Path(tempfile.mkdtemp(prefix="dcf2bin-fuzz-"))
    try:
        runner = Runner(workdir, timeout, use_tracemalloc)
        numbers = [only] if only is not None else range(iterations)
        for i in numbers:
            rng = random.Random(f"{seed}:{i}")
            k = kinds[i % len(kinds)]
            j = rng.randrange(len(seeds[k]))
            base, other = blobs[k][j], rng.choice(blobs[k])
            data, ops = mutate(rng, base, other, k)
            seed_name = _shown(seeds[k][j], corpus)
            what = f"variant {i}, {k}, {seed_name}, {' + '.join(ops)}"
            report.variants += 1
            report.by_kind[k] = report.by_kind.get(k, 0) + 1
            for op in ops:
                name = op.split()[0].split("@")[0]
                report.ops[name] = report.ops.get(name, 0) + 1
            if use_tracemalloc:
                tracemalloc.reset_peak()
            t0, c0 = time.perf_counter(), time.process_time()
            if old_handler is not None:
                signal.setitimer(signal.ITIMER_REAL, timeout)
            try:
                results = runner.run_variant(rng, k, data)
            except Hang:
                results = [(runner.current, 70, f"Hang: longer than {timeout} s")]
            finally:
                if old_handler is not None:
                    signal.setitimer(signal.ITIMER_REAL, 0)
            secs, cpu = time.perf_counter() - t0, time.process_time() - c0
            if secs > report.slowest[0]:
                report.slowest = (secs, what + f" ({len(data)} bytes)")
            if cpu > report.slowest_cpu[0]:
                report.slowest_cpu = (cpu, what + f" ({len(data)} bytes)")
            if use_tracemalloc:
                peak = tracemalloc.get_traced_memory()[1] / (1 << 20)
                if peak > report.peak_traced[0]:
                    report.peak_traced = (peak, what)
            for cmd, code, tb in results:
                report.commands += 1
                report.exit_codes[code] = report.exit_codes.get(code, 0) + 1
                if code not in (0, 1, 3):
                    key = "Hang" if tb.startswith("Hang") else _crash_key(tb)
                    if code != 70:
                        key = f"unexpected exit {code}"
                    report.crashes.append(Crash(key, i, k, seed_name, ops, cmd, tb[-2000:]))
                    if save is not None:
                        save.mkdir(parents=True, exist_ok=True)
                        suffix = {"container": ".bin", "csv": ".csv", "yaml": ".yml",
                                  "cpj": ".cpj"}.get(k, ".dcf")
                        (save / f"seed{seed}-variant{i}{suffix}").write_bytes(data)
            if progress and (i + 1) % 500 == 0:
                print(f"  {i + 1} variants, {len(report.crashes)} crashes, "
                      f"{time.perf_counter() - started:.0f} s, max RSS {_max_rss_mib():.0f} MiB",
                      file=sys.stderr, flush=True)
    finally:
        if old_handler is not None:
            signal.signal(signal.SIGALRM, old_handler)
        if env_debug is not None:
            os.environ["DCF2BIN_DEBUG"] = env_debug
        if use_tracemalloc:
            tracemalloc.stop()
        shutil.rmtree(workdir, ignore_errors=True)
    report.seconds = time.perf_counter() - started
    report.peak_rss_mib = _max_rss_mib()
    return report


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seed", type=int, default=1, help="seed of the run (default 1)")
    ap.add_argument("--iterations", type=int, default=300, help="number of variants")
    ap.add_argument("--kind", choices=["dcf", "container", "csv", "yaml", "cpj", "both", "all",
                                       "network"], default="all",
                    help="what to mutate (all: dcf, container, csv in turn; both: dcf and "
                         "container; network: yaml and cpj in turn)")
    ap.add_argument("--only", type=int, metavar="N", help="run only variant N of this seed")
    ap.add_argument("--corpus", type=Path, default=CORPUS,
                    help=f"folder of extra seed files (default {CORPUS}; ignored if absent)")
    ap.add_argument("--no-corpus", action="store_true", help="seed from samples and fixtures only")
    ap.add_argument("--max-seed-size", type=int, default=MAX_SEED_SIZE,
                    help="skip seed files larger than this many bytes")
    ap.add_argument("--timeout", type=float, default=60.0,
                    help="seconds one variant may take before it counts as a hang")
    ap.add_argument("--memory-limit", type=int, metavar="MIB",
                    help="address-space limit of this process (a MemoryError is a crash)")
    ap.add_argument("--tracemalloc", action="store_true",
                    help="also measure each variant's traced peak (slower)")
    ap.add_argument("--save-crashes", type=Path, metavar="DIR",
                    help="write every crashing input to DIR")
    ap.add_argument("--json", type=Path, metavar="FILE", help="also write the report as JSON")
    ap.add_argument("--progress", action="store_true", help="a line every 500 variants")
    args = ap.parse_args(argv)
    if args.iterations < 0:
        ap.error("--iterations must be >= 0")
    report = fuzz(args.seed, args.iterations, args.kind,
                  None if args.no_corpus else args.corpus, args.timeout, args.tracemalloc,
                  args.only, args.save_crashes, args.progress, args.max_seed_size,
                  args.memory_limit)
    sys.stdout.write(report.text())
    if args.json:
        args.json.write_text(json.dumps(report.as_dict(), indent=1) + "\n")
    for key, group in report.unique_crashes().items():
        sys.stdout.write(f"\n--- {key}\n{group[0].detail}\n")
    return 1 if report.crashes else 0


if __name__ == "__main__":
    sys.exit(main())

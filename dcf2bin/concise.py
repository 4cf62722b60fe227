"""The CiA 302-3 concise DCF, read and written as one pair (SPEC §3.2).

A concise DCF is what a configuration manager writes to a node, entry by entry: a ``DWORD``
count, then per entry ``WORD index, BYTE subindex, DWORD size`` and ``size`` bytes of data,
little-endian, ending exactly where the file ends. It is the layout of a container's index
segment (``schema.IndexSegment``), what ``network build`` writes for each slave
(``<slave>.bin``) and for a lely master's own entries (``master.bin``), and what 0x1F22
holds for each node.

* ``to_bytes(entries)`` writes one (the entries in order, the count recomputed);
* ``read_concise(data, name)`` reads one: ``(entries, diagnostics)``, the entries ``None``
  when the bytes are not a whole concise DCF, and one error naming the byte offset of the
  first thing that is wrong (CON001...CON004, validate's rule ids);
* ``fills(data)`` is the content test: a count and exactly that many entries, filling the
  file to its last byte; ``damaged(data)`` the looser one of a concise DCF whose count or
  end is wrong (``dcf2bin.filekind`` uses both);
* ``offsets(entries)`` is the byte offset of each entry's head.

The structs are the schema's (``schema.COUNT``, ``schema.ENTRY_HEAD``, derived from the
construct declaration), declared here again so that ``network build`` and ``--help`` do not
import construct; tests/test_concise.py checks that both agree byte for byte.

    >>> data = to_bytes([(0x1017, 0, b"\\x64\\x00")])
    >>> data.hex(" ")
    '01 00 00 00 17 10 00 02 00 00 00 64 00'
    >>> read_concise(data, "drive.bin")
    ([(4119, 0, b'd\\x00')], [])
"""
from __future__ import annotations

import struct
from itertools import accumulate

from dcf2bin.diagnostics import Diagnostic, Severity

COUNT = struct.Struct("<L")           # = schema.COUNT
ENTRY_HEAD = struct.Struct("<HBL")    # = schema.ENTRY_HEAD: index, subindex, size
HEAD = ENTRY_HEAD.size                # 7

#: validate's ids of what ``read_concise`` finds (registered in dcf2bin/lint/rules_concise.py)
R_SHORT = "CON001"        # fewer than 4 bytes: no count
R_PAST_END = "CON002"     # an entry runs past the end of the file
R_TRAILING = "CON003"     # bytes after the last entry the count names
R_COUNT = "CON004"        # whole entries fill the file, but not as many as the count says

#: the lowest index a concise DCF writes: below it CiA 301 puts the data type definitions
FIRST_OBJECT = 0x1000

Entry = tuple[int, int, bytes]


class ConciseError(Exception):
    """Bytes that are not a whole concise DCF: ``message``, the byte ``offset`` it is at,
    and the ``rule`` (CON00x) that names it."""

    def __init__(self, message: str, offset: int, rule: str):
        super().__init__(message)
        self.offset = offset
        self.rule = rule


# -- writing ----------------------------------------------------------------------------------

def to_bytes(entries) -> bytes:
    """The concise DCF of ``entries`` ((index, subindex, data), in the order they are
    written); the count is their number."""
    # one growing buffer: b"".join of 120,000 parts would hold a buffer descriptor for each
    # part at once (about 10 MiB at 60,000 entries, the peak of a compile)
    pack = ENTRY_HEAD.pack
    out = bytearray(COUNT.pack(len(entries)))
    for index, sub, data in entries:
        out += pack(index, sub, len(data))
        out += data
    return bytes(out)


def size_of(entries) -> int:
    """``len(to_bytes(entries))``, without making the bytes."""
    return COUNT.size + HEAD * len(entries) + sum(len(e[2]) for e in entries)


def offsets(entries, base: int = 0) -> list[int]:
    """The byte offset of each entry's head (its WORD index), from ``base`` (the count's)."""
    if not entries:
        return []
    sizes = map(HEAD.__add__, map(len, [e[2] for e in entries[:-1]]))
    return list(accumulate(sizes, initial=base + COUNT.size))


# -- reading ----------------------------------------------------------------------------------

def parse(data: bytes) -> list[Entry]:
    """The entries of a whole concise DCF, in order. Raises ConciseError (CON001...CON004)
    naming the first thing that is wrong."""
    n = len(data)
    if n < COUNT.size:
        raise ConciseError(f"{n} byte{'s' if n != 1 else ''}: too short for the entry count "
                           "(a DWORD)", 0, R_SHORT)
    (count,) = COUNT.unpack_from(data, 0)
    entries = _exact(data, count)
    if entries is not None:
        return entries
    return _problem(data, count)


def read_concise(data: bytes, name: str) -> tuple[list[Entry] | None, list[Diagnostic]]:
    """A concise DCF's entries (None when the bytes are not a whole one) and its
    diagnostics: none, or the one error of ``parse`` at its byte offset."""
    try:
        return parse(data), []
    except ConciseError as exc:
        return None, [Diagnostic(Severity.ERROR, str(exc), name, offset=exc.offset,
                                 rule=exc.rule)]


def fills(data: bytes) -> bool:
    """True for a whole concise DCF: a count, then exactly that many entries, the last one
    ending at the file's last byte (``00 00 00 00`` is one, without entries). A container is
    never one: its first DWORD is its own size, which a count of entries of 7 bytes or more
    never reaches."""
    n = len(data)
    if n < COUNT.size:
        return False
    (count,) = COUNT.unpack_from(data, 0)
    if count > (n - COUNT.size) // HEAD:
        return False
    return _walk(data, COUNT.size, count) == n


def damaged(data: bytes) -> bool:
    """True for bytes that begin as a concise DCF but whose count or end is wrong: a first
    DWORD smaller than the file (a container's, its own size, is not), and a first entry
    that lies whole inside the file and writes an object (index 0x1000 or above; a
    container's bytes 4-5 are its version, 1)."""
    n = len(data)
    if n < COUNT.size + HEAD or fills(data):
        return False
    (count,) = COUNT.unpack_from(data, 0)
    index, _, size = ENTRY_HEAD.unpack_from(data, COUNT.size)
    return count < n and index >= FIRST_OBJECT and COUNT.size + HEAD + size <= n


def _walk(data: bytes, at: int, count: int) -> int:
    """Where ``count`` entries from ``at`` end (past the end when they do not fit)."""
    unpack = ENTRY_HEAD.unpack_from
    n = len(data)
    for _ in range(count):
        if at + HEAD > n:
            return n + 1
        at += HEAD + unpack(data, at)[2]
    return at


def _exact(data: bytes, count: int) -> list[Entry] | None:
    """The ``count`` entries of bytes that hold them exactly, read without a bounds check
    each; None when they do not (``_problem`` then says where not)."""
    if count > (len(data) - COUNT.size) // HEAD:     # never allocate from a wrong count
        return None
    unpack = ENTRY_HEAD.unpack_from
    data = bytes(data)
    entries: list[Entry] = []
    append = entries.append
    pos = COUNT.size
    try:
        for _ in range(count):
            index, sub, size = unpack(data, pos)
            pos += HEAD
            append((index, sub, data[pos:pos + size]))
            pos += size
    except struct.error:
        return None
    return entries if pos == len(data) else None


def _whole(data: bytes) -> int | None:
    """How many entries fill ``data`` after its count exactly, whatever the count says
    (None when they do not)."""
    n, at, k = len(data), COUNT.size, 0
    unpack = ENTRY_HEAD.unpack_from
    while at + HEAD <= n:
        at += HEAD + unpack(data, at)[2]
        k += 1
    return k if at == n else None


def _problem(data: bytes, count: int) -> list[Entry]:
    """The ConciseError of bytes that do not hold ``count`` entries exactly: a count that
    disagrees with the whole entries that fill the file, else the entry that runs past the
    end, else the bytes after the last entry."""
    n = len(data)
    whole = _whole(data)
    if whole is not None:
        raise ConciseError(f"the count says {_entries(count)}, but {_entries(whole)} "
                           f"fill{'s' if whole == 1 else ''} the file exactly", 0, R_COUNT)
    unpack = ENTRY_HEAD.unpack_from
    at = COUNT.size
    for i in range(count):
        if at + HEAD > n:
            raise ConciseError(f"entry {i + 1} of {count} is cut short: its head needs "
                               f"{HEAD} bytes, {n - at} remain", at, R_PAST_END)
        index, sub, size = unpack(data, at)
        if at + HEAD + size > n:
            raise ConciseError(f"entry {i + 1} of {count} (0x{index:04X}sub{sub:X}) claims "
                               f"{size} data byte{'s' if size != 1 else ''}, "
                               f"{n - at - HEAD} remain", at + 3, R_PAST_END)
        at += HEAD + size
    raise ConciseError(f"{n - at} byte{'s' if n - at != 1 else ''} after the last of "
                       f"{_entries(count)}", at, R_TRAILING)


def _entries(n: int) -> str:
    return f"{n} entr{'y' if n == 1 else 'ies'}"


__all__ = ["COUNT", "ENTRY_HEAD", "FIRST_OBJECT", "HEAD", "ConciseError", "Entry", "R_COUNT",
           "R_PAST_END", "R_SHORT", "R_TRAILING", "damaged", "fills", "offsets", "parse",
           "read_concise", "size_of", "to_bytes"]

"""What a check sees: the parsed file and cached helpers (no findings here).

``DcfContext`` holds the INI file, the model built from it (with the layout
computed) and the options; ``BinContext`` holds a container's bytes, parsed as far
as they can be parsed; ``ConciseContext`` a concise DCF's entries and the types of its
device. Checks must never crash on broken input: helpers return None
for anything they cannot work out, and the check that owns that problem reports it.
"""
from __future__ import annotations

import os
from array import array
from dataclasses import dataclass, field
from functools import cached_property
from itertools import accumulate
from operator import add

from dcf2bin import datatypes as dt
from dcf2bin import ini as ini_mod
from dcf2bin import schema, values
from dcf2bin.lint import tables


def _blank_comment(text: str | bytes) -> bool:
    """``re.search(r"=[^=\n]*?[ \t][;#]", text) is not None``, from the few ';' and '#'
    of a file instead of from its every '=' (a 60,000-variable file has 400,000)."""
    b = isinstance(text, bytes)
    nl, eq, blanks = (b"\n", b"=", (b" ", b"\t")) if b else ("\n", "=", (" ", "\t"))
    for mark in ((b";", b"#") if b else (";", "#")):
        line_end = -1          # the line of the last candidate, and its first '='
        first_eq = -1
        at = text.find(mark, 1)
        while at >= 0:
            if text[at - 1:at] in blanks:
                if at > line_end:
                    start = text.rfind(nl, 0, at) + 1
                    line_end = text.find(nl, at)
                    if line_end < 0:
                        line_end = len(text)
                    first_eq = text.find(eq, start, line_end)
                if 0 <= first_eq < at - 1:
                    return True
            at = text.find(mark, at + 1)
    return False


def _line_starts(text: str | bytes, block: int = 1 << 20) -> array:
    """The offset in ``text`` of the start of each of its lines (``text.split("\n")``'s
    items), worked out one block of about ``block`` characters at a time."""
    nl = b"\n" if isinstance(text, bytes) else "\n"
    starts = array("q", [0])
    pos, find = 0, text.find
    while True:
        end = find(nl, pos + block)
        part = text[pos:] if end < 0 else text[pos:end]
        # the start of each line after one of ``part``: the last one is ``end + 1``, the
        # next block's first line, or past the text after the last block
        after = accumulate(map((1).__add__, map(len, part.split(nl))), add, initial=pos)
        next(after)
        starts.extend(after)
        if end < 0:
            starts.pop()
            return starts
        pos = end + 1


@dataclass
class Options:
    node_id: int | None = None
    pi_size: int | None = None
    pi_align: int = 8
    address_base: str = "image"
    profile: str = "cia301"
    allow_external_files: bool = False
    active: set[str] | None = None      # rule ids to run; None = all
    strict: bool = False
    # the DynBuildOd emulation (TGT0xx, SPEC §8): what the target was built with
    target_check: bool = True
    tx_cobs: int | None = None
    rx_cobs: int | None = None
    granularity: int = 64
    bit_mapping: bool = True
    static_od: str | None = None        # the target's static OD (an EDS path), checked first
    eds: str | None = None              # a concise DCF's types (an EDS/DCF path), checked first


class DcfContext:
    def __init__(self, path: str, data: bytes, opts: Options, parsed: ini_mod.IniFile, dev):
        from dcf2bin.profiles import get_profile
        self.path = path
        self.data = data
        self.opts = opts
        self.ini = parsed
        self.dev = dev
        self.profile = get_profile(opts.profile)
        self.layout = None
        self.cache: dict = {}          # for checks that share derived data
        self._ints: dict[int, tuple[int | None, bool]] = {}

    # -- raw text ----------------------------------------------------------------------------
    @cached_property
    def text(self) -> str | bytes:
        """The file's text for the rules that scan it (DCF052, DCF057, DCF203, columns):
        the bytes themselves when each is one character (ASCII, or a Latin-1 file
        without a BOM), else the decoded text: a 60 MB file is not copied (issue 26)."""
        if self.ini.rejected or self.ini.format != "ini":
            return ""   # not text (DCF008), or not CiA 306 text: no rule looks at its "lines"
        data = self.data
        if data.isascii() or self.ini.encoding == "latin-1" and not data.startswith(
                b"\xef\xbb\xbf"):
            return data
        return ini_mod.decode_bytes(data)[0]

    @cached_property
    def line_starts(self) -> array:
        """Where each line starts in ``text``: 8 bytes a line, where a list of the lines
        held a string each (a 60 MB file of short lines: 200 MB)."""
        return _line_starts(self.text)

    def raw_line(self, line: int) -> str | None:
        """Line ``line`` (1-based) as written, its CR kept, or None beyond the file."""
        starts = self.line_starts
        if not 1 <= line <= len(starts):
            return None
        text, start = self.text, starts[line - 1]
        end = starts[line] - 1 if line < len(starts) else len(text)
        raw = text[start:end]
        return raw.decode("latin-1") if isinstance(raw, bytes) else raw

    def value_column(self, line: int | None) -> int | None:
        """1-based column of the value on a ``key=value`` line."""
        raw = self.raw_line(line) if line is not None else None
        if raw is None:
            return None
        raw = raw.rstrip("\r")
        eq = raw.find("=")
        if eq < 0:
            return None
        col = eq + 1
        while col < len(raw) and raw[col] in " \t":
            col += 1
        return col + 1

    # -- sections ----------------------------------------------------------------------------
    def section(self, name: str) -> ini_mod.Section | None:
        return self.ini.sections.get(name)

    @staticmethod
    def key_names(sec: ini_mod.Section):
        """Lower-case key names of a section without building per-key line records."""
        names = getattr(sec, "key_names", None)     # ini.Section: without building values
        if names is not None:
            return names()
        vals = getattr(sec, "values", None)
        return vals.keys() if isinstance(vals, dict) else sec.keys.keys()

    @property
    def kinds(self) -> dict[str, str | None]:
        """canonical section name -> its CiA 306 kind (see vocabulary.classify)."""
        return tables.kinds(self)

    def of_kind(self, *kinds: str | None) -> list[tuple[str, ini_mod.Section]]:
        """(canonical name, section) of the sections of these kinds, in file order."""
        if len(kinds) == 1:
            return tables.of_kind(self, kinds[0])
        return sorted((x for k in kinds for x in tables.of_kind(self, k)),
                      key=lambda cs: cs[1].line)

    def each_of_kind(self, kind: str | None):
        """``of_kind(kind)``'s pairs one after the other (no list of them)."""
        return tables.each_of_kind(self, kind)

    @property
    def sub_sections(self) -> dict[int, dict[int, ini_mod.Section]]:
        """index -> {subindex: [<index>subN] section} as they stand in the file."""
        return tables.sub_sections(self)

    @property
    def groups(self) -> list[tuple[str | None, dict | None, list]]:
        """(kind, shared template, its sections): see ``tables.groups``."""
        return tables.groups(self)

    @property
    def blank_comment(self) -> bool:
        """Whether some line has an '=' and later a blank followed by ';' or '#' (a value
        that may carry a comment, DCF057/DCF203): without one, those rules skip their walk."""
        got = self.cache.get("blank_comment")
        if got is None:
            got = self.cache["blank_comment"] = _blank_comment(self.text)
        return got

    # -- values ------------------------------------------------------------------------------
    def int_value(self, entry, text: str | None = None) -> tuple[int | None, bool]:
        """(value, uses_nodeid) of an integer entry's effective value (or ``text``).

        A ``$NODEID`` formula without a known node-ID is evaluated with node-ID 0, so
        callers can still compare offsets; ``uses_nodeid`` tells them. None when the
        value cannot be worked out (DCF200 reports it).
        """
        if text is None:
            key = id(entry)
            got = self._ints.get(key)
            if got is not None:
                return got
            text = entry.value_text
        else:
            key = None
        result: tuple[int | None, bool] = (None, False)
        dtype = entry.dtype
        if text is not None and dtype is not None and dtype.is_integer:
            # the model's encodings (Device.encoded, filled by the selection) hold only
            # values encoded without a numeric comment, with the file's node-ID: the same
            # bytes as encoding ``t`` here (a $NODEID value without a node-ID is never there)
            data = self.dev.encoded.get((dtype.code, text))
            if data is not None:
                result = (int.from_bytes(data, "little", signed=dtype.kind == dt.SINT),
                          values.uses_nodeid(text))
            else:
                t = values.split_numeric_comment(text)[0] if dtype.kind != dt.BOOL else text
                nodeid = values.uses_nodeid(t)
                node = self.dev.node_id if self.dev.node_id is not None else 0
                try:
                    data = values.encode(dtype, t, node_id=node)
                    result = (int.from_bytes(data, "little", signed=dtype.kind == dt.SINT),
                              nodeid)
                except values.ValueProblem:
                    result = (None, nodeid)
        if key is not None:
            self._ints[key] = result
        return result


# -- containers ------------------------------------------------------------------------------

@dataclass
class Segment:
    name: str
    offset: int
    size: int
    field_offset: int    # where its offset field stands in the header

    @property
    def end(self) -> int:
        return self.offset + self.size


@dataclass
class BinContext:
    path: str
    data: bytes
    opts: Options
    header: dict[str, int] | None = None
    segments: list[Segment] = field(default_factory=list)      # size > 0, inside, in order
    bad_segments: set[str] = field(default_factory=set)       # outside the container
    cut_segments: set[str] = field(default_factory=set)       # inside it, but the file is cut
    entries: list[tuple[int, int, int, int]] | None = None     # (index, sub, size, data offset)
    index_problem: tuple[str, int] | None = None               # (message, offset)

    def __post_init__(self) -> None:
        data = self.data
        if len(data) < schema.HEADER_SIZE:
            return
        self.header = dict(zip(schema.HEADER_FIELDS, schema.HEADER.unpack_from(data, 0)))
        for i, name in enumerate(schema.SEGMENTS):
            off, size = self.header[f"{name}_offset"], self.header[f"{name}_size"]
            if size == 0:
                continue
            seg = Segment(name, off, size, 8 + 8 * i)
            if off < schema.HEADER_SIZE or off + size > self.total:
                self.bad_segments.add(name)
                continue
            if off + size > len(data):
                self.cut_segments.add(name)   # CNT002 reports the truncation
                continue
            self.segments.append(seg)
        self.segments.sort(key=lambda s: (s.offset, s.end))
        idx = self.segment("index")
        if idx is not None:
            self._parse_index(idx)

    @property
    def total(self) -> int:
        return self.header["total_size"] if self.header else 0

    def segment(self, name: str) -> Segment | None:
        for s in self.segments:
            if s.name == name:
                return s
        return None

    def segment_bytes(self, name: str) -> bytes | None:
        s = self.segment(name)
        return None if s is None else self.data[s.offset:s.end]

    def _parse_index(self, seg: Segment) -> None:
        data, base, n = self.data, seg.offset, seg.size
        if n < 4:
            self.index_problem = (f"index segment has {n} bytes, too short for its count", base)
            return
        (count,) = schema.COUNT.unpack_from(data, base)
        head = schema.ENTRY_HEAD.size
        unpack = schema.ENTRY_HEAD.unpack_from
        entries = []
        pos = 4
        for i in range(count):
            if pos + head > n:
                self.index_problem = (f"index segment claims {count} entries, but entry {i + 1} "
                                      "is truncated", base + pos)
                break
            index, sub, size = unpack(data, base + pos)
            if pos + head + size > n:
                self.index_problem = (f"index entry {i + 1} (0x{index:04X}sub{sub:X}) claims "
                                      f"{size} data bytes, only {n - pos - head} remain",
                                      base + pos + 3)
                break
            entries.append((index, sub, size, base + pos + head))
            pos += head + size
        else:
            if pos != n:
                self.index_problem = (f"{n - pos} bytes after the last of {count} index entries",
                                      base + pos)
        self.entries = entries

    @cached_property
    def entry_offsets(self) -> list[int]:
        """Byte offset of each entry's header (for diagnostics)."""
        return [off - schema.ENTRY_HEAD.size for _, _, _, off in self.entries or ()]


# -- concise DCFs ----------------------------------------------------------------------------

#: the EDS of each path given to --eds or found beside a concise DCF, read once per process
_EDS_CACHE: dict[str, object] = {}


@dataclass
class ConciseContext:
    """A concise DCF (CiA 302-3) as its checks see it: the entries in order (None when the
    bytes are not a whole one: ``diagnostics`` says why), the byte offset of each, and the
    types of the device (``eds``, a ``dump.EdsInfo``) from ``--eds`` or from the DCF of
    the same name beside it (``eds_name`` names that file in messages)."""
    path: str
    data: bytes
    opts: Options
    entries: list[tuple[int, int, bytes]] | None = None
    offsets: list[int] = field(default_factory=list)
    diagnostics: list = field(default_factory=list)
    eds: object | None = None
    eds_name: str = ""
    cache: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        from dcf2bin import concise
        self.entries, self.diagnostics = concise.read_concise(self.data, self.path)
        if self.entries is None:
            return
        self.offsets = concise.offsets(self.entries)
        eds_path = self.opts.eds or concise_description(self.path)
        if eds_path is not None:
            self.eds = _load_eds(eds_path)
            self.eds_name = eds_path if self.opts.eds else os.path.basename(eds_path)


def concise_description(path: str) -> str | None:
    """The description beside a concise DCF that gives its types: ``<stem>.dcf``, else
    ``<stem>.eds``, in the same folder (network build writes ``drive.dcf`` beside
    ``drive.bin``); None for standard input or when there is none."""
    if path.startswith("<"):
        return None
    stem = os.path.splitext(path)[0]
    for suffix in (".dcf", ".eds"):
        if os.path.isfile(stem + suffix) and stem + suffix != path:
            return stem + suffix
    return None


def _load_eds(path: str):
    """``dump.load_eds``'s names and types, or None when the file cannot be read (it is
    checked on its own: it sits in the folder, or the command checked --eds first)."""
    if path not in _EDS_CACHE:
        from dcf2bin.diagnostics import DcfError
        from dcf2bin.dump import load_eds
        try:
            _EDS_CACHE[path] = load_eds(path)[0]
        except (OSError, DcfError, ValueError):
            _EDS_CACHE[path] = None
    return _EDS_CACHE[path]

"""A line-tracking reader for CiA 306 INI text (SPEC.md §1).

Not configparser: names are case-insensitive, every section and key keeps its
line number, duplicates are reported with both lines, nothing is dropped
silently, and it is fast (one pass, no regex on the common path).
"""
from __future__ import annotations

import re
import weakref
from array import array
from bisect import bisect_left
from itertools import chain
from dataclasses import dataclass, field
from typing import Callable

from dcf2bin.diagnostics import LIMIT, Capped, Diagnostics, Where, shorten

# What one file is read into at most (issue 26: a file under the 64 MiB input cap made of
# millions of sections or keys took gigabytes); what lies beyond is one error and is not
# read. A section has at most MAX_KEYS key lines: an object list ([OptionalObjects],
# [ManufacturerObjects]) names each index at most once, and there are 65,536 indexes;
# other sections have a few dozen keys ([xxxxValue]: 255).
MAX_KEYS = 1 << 16
# A file has at most MAX_SECTIONS sections: as many as the whole network-variable area
# 0xA000-0xAFFF holds, 4,096 arrays of 256 sections each (the object, sub 0 and 254
# variables); every variable of CiA 405's standard ranges (A000-A8FF, 36 ranges of 0x40
# arrays) is 589,824 sections, and the largest PLC files seen have about 60,000.
MAX_SECTIONS = 1 << 20

# "[1018sub01]" and "[1018sub1]" are the same section (SPEC §1): canonical form
# is lower case with the subindex in hex without leading zeros. More than 2 digits
# ("[1018sub001]", lint DCF061) is that section too, so a repeat is a duplicate.
_SUB_RE = re.compile(r"([0-9a-f]{4})sub([0-9a-f]+)")


def canonical_section(name: str) -> str:
    low = name.strip().lower()
    m = _SUB_RE.fullmatch(low)
    if m:
        return f"{m.group(1)}sub{int(m.group(2), 16):x}"
    return low


@dataclass(slots=True)
class Key:
    """One key of a section: its name as written, its value (trimmed) and its line."""
    name: str   # as written
    value: str  # trimmed
    line: int


class Section:
    """One section: its name as written, line, values by lower-case key, and each key's
    name and line (``keys``).

    The exact reader's sections (``_WrittenSection``) hold all of these. The fast
    reader's (``_SharedSection``) hold little of their own, since a large PLC file has
    tens of thousands of them: ``rest`` is a ``_Template``, the values of the section's
    lines with the values of its ``ParameterName=`` and ``Denotation=`` lines left empty,
    one dict shared by every section whose text is the same but for those names (the
    254 sub-objects of a network-variable array differ only in them), and
    ``param_name``/``denotation`` are the values that were cut out (None: that line is
    not cut out of the template). The model builds such entries once. The exact reader
    leaves ``rest``, ``param_name`` and ``denotation`` None.
    """
    __slots__ = ()
    param_name: str | None = None
    rest: _Template | None = None
    denotation: str | None = None
    name: str
    line: int
    values: dict[str, str]     # lower-case key name -> value (blanks trimmed)
    keys: dict[str, Key]       # lower-case key name -> Key(name as written, value, line)

    def has(self, key: str) -> bool:
        return key in self.values

    def get(self, key: str) -> str | None:
        """The value of ``key`` (lower case), or None when absent or empty."""
        return self.values.get(key) or None

    def key_names(self):
        """The lower-case key names, in file order (``values.keys()``, without building
        ``values`` for a section read through a shared template)."""
        return self.values.keys()

    def line_of(self, key: str) -> int:
        if not self.has(key):
            return self.line
        return self.keys[key].line


class _WrittenSection(Section):
    """A section of the exact reader: what it read, key by key."""
    __slots__ = ("name", "line", "values", "keys")

    def __init__(self, name: str, line: int):
        self.name = name
        self.line = line
        self.values: dict[str, str] = {}
        self.keys: dict[str, Key] = {}

    def add(self, key: Key) -> None:
        low = key.name.lower()
        self.values[low] = key.value
        self.keys[low] = key


class _SharedSection(Section):
    """A section of the fast reader: its line, its names and its template (see
    ``Section``), in four slots (64 bytes: a PLC file has tens of thousands of these).
    ``values`` is worked out from the template on first use, ``keys`` too (kept by the
    file's ``_Source``, by line), the name as written from the file's text each time it
    is asked for, so the common case, which never prints a diagnostic, pays little.
    ``_read_sections`` makes these without ``__init__`` (it sets every slot); a section
    whose Denotation= is cut out of its template is a ``_DenotedSection``."""
    __slots__ = ("line", "param_name", "rest", "_values")

    @property
    def name(self) -> str:
        return self.rest.source.name_at(self.line)

    @property
    def values(self) -> dict[str, str]:
        if self._values is None:
            self._values = dict(self.rest)
            if self.param_name is not None:
                self._values["parametername"] = self.param_name   # in its place
            if self.denotation is not None:
                self._values["denotation"] = self.denotation
        return self._values

    @property
    def keys(self) -> dict[str, Key]:
        known = self.rest.source.keys
        keys = known.get(self.line)
        if keys is None:
            # the template's text has the section's lines (the names' values left out);
            # a section read by _Templates.big has no text: the file has them
            text = self.rest.text
            if text is None:               # _Templates.big: its values are the file's
                values = self.rest
                keys = known[self.line] = {}
                for k, i in self.rest.source.keys_at(self.line):
                    keys.setdefault(k.lower(), Key(k, values.get(k.lower(), ""), i))
                return keys
            keys = known[self.line] = {}
            for i, raw in enumerate(text.split("\n"), self.line + 1):
                k, eq, v = raw.partition("=")
                k = k.strip(" \t\r")
                if eq and k and k[0] not in ";#":
                    keys.setdefault(k.lower(), Key(k, v.strip(" \t\r"), i))
            for low, value in (("parametername", self.param_name),
                               ("denotation", self.denotation)):
                if value is not None:           # its line is in the template, empty
                    keys[low] = Key(keys[low].name, value, keys[low].line)
        return keys

    def has(self, key: str) -> bool:
        if self._values is None:         # from the template, without building ``values``
            return key in self.rest     # the names' lines are in it, with empty values
        return key in self._values

    def get(self, key: str) -> str | None:
        if self._values is None:         # from the template, without building ``values``
            if key == "parametername" and self.param_name is not None:
                return self.param_name or None
            if key == "denotation" and self.denotation is not None:
                return self.denotation or None
            return self.rest.get(key) or None
        return self._values.get(key) or None

    def key_names(self):
        return (self.rest if self._values is None else self._values).keys()

    def line_of(self, key: str) -> int:
        """As ``Section.line_of``; a section read by ``_Templates.big`` finds the key in
        the file rather than making a Key of each of its lines (it can have millions)."""
        if not self.has(key):
            return self.line
        source = self.rest.source
        if self.rest.text is None and self.line not in source.keys:
            for _, line in source.keys_at(self.line, key):
                return line
        return self.keys[key].line


class _DenotedSection(_SharedSection):
    """A shared section with the value of its Denotation= line (see ``Section``)."""
    __slots__ = ("denotation",)


class _Template(dict):
    """The values of the lines of sections that have the same text but for the values of
    their names (see ``Section``), read once per file. It carries what those sections
    have in common beyond their values: ``text``, their lines (with the names' values
    left out), ``step``, the number of lines from one such section's header to the next
    header (the same text has the same number of lines), and ``source``, the file in
    which they look up their names as written."""
    __slots__ = ("text", "step", "source")


class _Source:
    """The text of a file read by the fast reader (or its bytes, see ``parse_bytes``),
    where its sections look up their names as written, by their line. Where the header
    lines start is found on the first such question (a message), once per file: the
    text cut as ``_read_sections`` cuts it, one part per section, in file order."""

    def __init__(self, src: str | bytes, nl: str, stop: int | None = None):
        self.src, self.nl = src, nl
        # where the sections read end (the '[' of the first not read, MAX_SECTIONS), or None
        self.stop = stop
        # the file whose sections these are (a weak reference: they refer to this source
        # through their templates, and the file would outlive its last user in a cycle)
        self.file: Callable[[], IniFile | None] = lambda: None
        self.keys: dict[int, dict[str, Key]] = {}  # _SharedSection.keys, by line
        self._lines: array | None = None       # the sections' lines, ascending
        self._offsets: array | None = None     # where their header lines start

    def name_at(self, line: int) -> str:
        if self._lines is None:
            self._index()
        src = self.src
        at = self._offsets[bisect_left(self._lines, line)] + 1     # after its '['
        if isinstance(src, bytes):
            return src[at:src.find(b"]", at)].decode("latin-1").strip(" \t")
        return src[at:src.find("]", at)].strip(" \t")

    def keys_at(self, line: int, only: str | None = None) -> list[tuple[str, int]]:
        """(name as written, line) of each key line of the section whose header is at
        ``line``, found in the file (``_Templates.big`` keeps no text of its own), as
        ``_SharedSection.keys`` reads a template's text; no value is copied. ``only``: the
        first key of that lower-case name alone (a section can have millions). The first
        MAX_KEYS key lines only: the others are not read (DCF014)."""
        if self._lines is None:
            self._index()
        src, k = self.src, bisect_left(self._lines, line)
        binary = isinstance(src, bytes)
        nl = self.nl.encode("latin-1") if binary else self.nl
        eq_sign = b"=" if binary else "="
        find, n_nl = src.find, len(nl)
        end = self._offsets[k + 1] - n_nl if k + 1 < len(self._offsets) else \
            len(src) if self.stop is None else self.stop - n_nl
        pos = find(nl, self._offsets[k], end) + n_nl
        out, seen = [], 0
        if pos < n_nl:
            return out                         # a header right before the next one
        while pos <= end:
            line += 1
            j = find(nl, pos, end)
            stop = end if j < 0 else j
            eq = find(eq_sign, pos, stop)
            if eq > pos:
                name = src[pos:eq]
                name = (name.decode("latin-1") if binary else name).strip(" \t\r")
                if name and name[0] not in ";#":
                    seen += 1
                    if seen > MAX_KEYS:
                        break
                    if only is None or name.lower() == only:
                        out.append((name, line))
                        if only is not None:
                            break
            if j < 0:
                break
            pos = j + n_nl
        return out

    def _index(self) -> None:
        src = self.src
        nl = self.nl.encode("latin-1") if isinstance(src, bytes) else self.nl
        sep = nl + (b"[" if isinstance(src, bytes) else "[")
        # the k-th section's "[" is the one after the k-th "<nl>[" (or the file's first
        # character); the header lines counted from the text itself (not taken from the
        # file's sections dict, whose order a caller may change). No copy of the text:
        # it can be 60 MB.
        # arrays: 16 bytes a section, where lists of ints held 80 (a million sections)
        offsets, lines = (array("q", [0]), array("q", [1])) if src[:1] == sep[-1:] else (
            array("q"), array("q"))
        find, tally, n_nl = src.find, src.count, len(nl)
        line, prev, at = 1, 0, src.find(sep)
        stop = len(src) if self.stop is None else self.stop
        while 0 <= at < stop - n_nl:           # (the sections read: MAX_SECTIONS)
            at += n_nl
            line += tally(nl, prev, at)
            offsets.append(at)
            lines.append(line)
            prev, at = at, find(sep, at)
        self._offsets, self._lines = offsets, lines


@dataclass(slots=True)
class Duplicate:
    """A repeated section (``key`` None) or key, with the line of its first occurrence."""
    section: str        # canonical section name
    key: str | None     # lower-case key name; None for a repeated section
    first_line: int
    line: int


@dataclass
class IniFile:
    """A read INI file: its sections by canonical name, what was repeated, its findings."""
    path: str
    encoding: str
    sections: dict[str, Section]
    duplicates: list[Duplicate]
    diagnostics: Diagnostics
    line_count: int = 0
    rejected: bool = False     # not CiA 306 text at all (see ``not_text``): nothing was read
    # canonical names of sections whose name is written otherwise ("[1018sub001]", "[1018SUB01]"),
    # so that the model words DCF061 without reading every lazily kept name
    respelled: list[str] = field(default_factory=list)
    # the registry name of the format the sections were read from (dcf2bin.formats): "ini"
    # for CiA 306 text; another format's sections have no CiA 306 lines to look at
    format: str = "ini"
    # repeats after the first diagnostics.LIMIT in ``duplicates``: how many, and the first
    # (the model reports them as one DCF010 finding, issue 26)
    more_duplicates: int = 0
    first_left_out: Duplicate | None = None

    def section(self, name: str) -> Section | None:
        return self.sections.get(name)

    def where(self, line: int | None) -> Where:
        return Where(self.path, line)


def decode_bytes(data: bytes) -> tuple[str, str]:
    """UTF-8 (BOM skipped) if it decodes, else Latin-1 (SPEC §1)."""
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    try:
        return data.decode("utf-8"), "utf-8"
    except UnicodeDecodeError:
        return data.decode("latin-1"), "latin-1"


# Bytes that never stand in a text file: C0 controls but tab, LF, VT, FF, CR and the
# DOS end-of-file mark ^Z (old EDS files end with one).
_CONTROLS = bytes(b for b in range(32) if b not in b"\t\n\v\f\r\x1a")
_CONTROL_RE = re.compile(b"[" + re.escape(_CONTROLS) + b"]")
_SNIFF = 8192      # how much of the file the UTF-16/binary check looks at
_REJECT_HINT = ("an EDS/DCF is text in UTF-8 or Latin-1; a binary DCF segment container "
                "is read by 'dcf2bin dump'")


def not_text(data: bytes) -> tuple[str, int, str] | None:
    """(message, line, hint) when ``data`` is not CiA 306 text at all -- UTF-16 text, a
    binary file -- else None. Such a file is reported once instead of as thousands of
    malformed lines. Only the first 8 KiB are looked at."""
    head = data[:_SNIFF]
    if head[:2] in (b"\xff\xfe", b"\xfe\xff"):
        return ("the file looks like UTF-16 text (it starts with a UTF-16 byte order mark); "
                "an EDS/DCF is UTF-8 or Latin-1", 1, "save it as UTF-8 and try again")
    half = len(head) // 2
    if half >= 2:
        even, odd = head[0::2].count(0), head[1::2].count(0)
        if max(even, odd) * 4 >= half * 3 and min(even, odd) * 10 <= half:
            return ("the file looks like UTF-16 text (every other byte is 0); an EDS/DCF is "
                    "UTF-8 or Latin-1", 1, "save it as UTF-8 and try again")
    controls = len(head) - len(head.translate(None, _CONTROLS))
    if controls and (head.count(0) >= 8 or controls * 10 > len(head)):
        m = _CONTROL_RE.search(head)
        at = m.start() if m else 0
        return (f"the file looks binary, not like EDS/DCF text ({controls} control bytes "
                f"in its first {len(head)}, the first at byte 0x{at:X})",
                data.count(b"\n", 0, at) + 1, _REJECT_HINT)
    return None


def parse_bytes(data: bytes, path: str) -> IniFile:
    problem = not_text(data)
    if problem is not None:
        message, line, hint = problem
        return _rejected(path, message, line, hint)
    text, encoding = decode_bytes(data)
    # When the text has as many characters as the file has bytes, each byte is one
    # character (ASCII read as UTF-8, or Latin-1), and Latin-1 decodes any slice of the
    # bytes to the same characters: the sections point into the bytes (which the caller
    # holds anyway) for the lines they look up on demand, and the decoded copy is freed
    # after parsing.
    return parse_text(text, path, encoding, data if len(text) == len(data) else None)


def _rejected(path: str, message: str, line: int, hint: str,
              encoding: str = "utf-8") -> IniFile:
    diags = Diagnostics()
    diags.error(message, Where(path, line), rule="DCF008", hint=hint)
    return IniFile(path, encoding, {}, [], diags, 0, rejected=True)


def read(path: str) -> IniFile:
    """Parse the file at ``path``, read through the one bounded reader (``fileio``: a
    regular file of at most 64 MiB); OSError when it cannot be read."""
    from dcf2bin.fileio.reading import read_file
    return parse_bytes(read_file(path), path)


def parse_text(text: str, path: str, encoding: str = "utf-8",
               source: bytes | None = None) -> IniFile:
    """Parse INI text. A fast path handles clean files; anything unusual (a bad line,
    a duplicate, a comment after a header) goes through the exact line-by-line
    reader, which reports every problem with its line. ``source``: the bytes ``text``
    was decoded from, when Latin-1 decodes them to ``text`` (ASCII, or a Latin-1 file)."""
    fast = _parse_fast(text, path, encoding, source)
    if fast is not None:
        parsed = fast
    else:
        if "\r" in text:
            # SPEC §1: only LF and CRLF end lines. A file whose lines end in a lone CR
            # (classic Mac OS) would be one huge line: say so once instead.
            lone = text.count("\r") - text.count("\r\n")
            if lone > text.count("\n"):
                return _rejected(path, "the lines end in CR alone (classic Mac OS); only LF "
                                 "and CRLF end lines in an EDS/DCF", 1,
                                 "convert the line ends to LF or CRLF", encoding)
        parsed = _parse_exact(text, path, encoding)
    if not parsed.sections:
        what = "is empty" if not text.strip() else "has no sections"
        parsed.diagnostics.error(f"the file {what}", Where(path, None), rule="DCF056",
                                 hint="an EDS/DCF has [FileInfo], [DeviceInfo] and object "
                                      "sections")
    return parsed


def _parse_fast(text: str, path: str, encoding: str,
                source: bytes | None = None) -> IniFile | None:
    """The common case, a clean file, one section at a time instead of one line at a time
    (``_read_sections``). Anything the exact reader would comment on (a bad line, an
    indented line, a duplicate, text after a header, a lone CR) makes this return None,
    and the exact reader takes the file.

    The text is cut at its own line ends (no converted copy of a CRLF text). A file
    with a CR is read as CRLF text; the reader declines a CR or LF that is not in a
    CRLF, wherever it stands, and only then are the line ends counted: a file that mixes
    CRLF with LF line ends is read again, converted to LF.
    """
    if "\r" in text:
        parsed = _read_sections(text, "\r\n", path, encoding, source)
        if parsed is not None:
            return parsed                      # every line ends in CRLF
        # a lone CR (the exact reader says so), or a CRLF file the fast path declined
        crlfs = text.count("\r\n")
        if text.count("\r") != crlfs or text.count("\n") == crlfs:
            return None
        text, source = text.replace("\r\n", "\n"), None   # mixed line ends
    return _read_sections(text, "\n", path, encoding, source)


def _read_sections(text: str, nl: str, path: str, encoding: str,
                   source: bytes | None) -> IniFile | None:
    """The fast path's reading of ``text`` whose lines end in ``nl`` (None: a line the
    exact reader has to see, a lone CR or LF among them).

    The text is cut at every line that starts with '[' (a header: INI has no other use
    for it); a section keeps only its line, its names and its template (see
    ``Section``). A section's lines after its header are very often the same text as
    another section's but for the values of ``ParameterName=`` and ``Denotation=``, so
    that text is parsed once, into a ``_Template`` shared by those sections. When
    ``ParameterName=`` is the first line, as configurators write it, the text after
    that line is the template's key, compared first with the section before's (an
    array's next sub-object), and the template tells how many lines the section spans:
    no copy of the text with the name cut out, no counting of lines per section (with
    a Denotation= line among them, that text with its value cut out is the key). Other
    sections go through ``_Templates.other``.
    """
    # each a section, from just after its '[', cut a block at a time (``_Chunks``): a list
    # of every section's text at once was one and a half times the file for sections of
    # a hundred bytes, and the rest of a file of more than MAX_SECTIONS was one more copy
    if text[:1] == "[":                        # no lines before the first header
        start = 1
        line = 1
    else:                                      # blank and comment lines only
        at = text.find(nl + "[")
        end = len(text) if at < 0 else at      # the text before the first header, looked
        if _lone(text, nl, end) or not _comments_only(text, nl, end):   # at in place
            return None
        line = text.count(nl, 0, end) + 2
        # where the first section's name starts (past the end: the text has no section)
        start = len(text) + 1 if at < 0 else at + len(nl) + 1
    chunks = _Chunks(text, nl, start, MAX_SECTIONS)
    sections: dict[str, Section] = {}
    respelled: list[str] = []
    templates = _Templates(_Source(text if source is None else source, nl), nl)
    by_tail: dict[str, _Template] = {}         # lines after a first ParameterName= line
    by_tail_get = by_tail.get
    last = last_tail = None                    # the last template found by_tail, and its key
    by_denoted: dict[str, _Template] = {}      # the same lines with Denotation= cut out
    close_name, name_key, den_key = "]" + nl + _NAME_KEY, _NAME_KEY, _DENOTATION_KEY
    shared, denoted, new = _SharedSection, _DenotedSection, _SharedSection.__new__
    too_many: list[tuple] = []                 # sections of more than MAX_KEYS keys
    # str.partition, `in` and == only: find and startswith with a start index parse their
    # arguments at a cost that shows at 60,000 sections. A section of more than _BIG
    # characters comes as a _Big naming where it is in ``text`` (``_Templates.big`` reads it
    # there: no copy of it), which the loop hands to _Templates.other as it does any
    # section it does not read itself (so that the loop spends nothing on them).
    for chunk in chain.from_iterable(chunks.blocks()):
        name, hit, rest = chunk.partition(close_name)
        canon = name.lower()
        pname, more, tail = rest.partition(nl)
        if hit and more and canon.isalnum():   # "[A040sub1]", "ParameterName=..." and more
            pname, denotation = pname.strip(" \t"), None
            if not pname.isprintable() and _lone(pname, nl):
                return None                    # a lone CR or LF
            if tail == last_tail:
                template = last
            else:
                template = by_tail_get(tail)
                if template is None and den_key in tail:
                    denotation, key = _cut(tail, den_key, nl)     # its own line's value
                    if denotation is not None:
                        template = by_denoted.get(key)
                        if template is None:
                            found = templates.cut(name_key + rest)
                            if found is None:
                                return None
                            template = by_denoted[key] = found[2]
                        elif _lone(denotation, nl):
                            return None        # a lone CR or LF
                if template is None:
                    found = templates.cut(name_key + rest)
                    if found is None:
                        return None
                    pname, denotation, template = found
                    if denotation is None:
                        by_tail[tail] = template
                if denotation is None:
                    last, last_tail = template, tail
            step = template.step
        else:
            found = templates.other(chunk)
            if found is None:
                return None
            canon, pname, denotation, template, step = found
            if templates.over is not None:     # more than MAX_KEYS keys (_Templates.big)
                over, templates.over = templates.over, None
                too_many.append((canon, line, line + over[0], over[1]))
        if len(canon) > 8 and canon[7] == "0":     # "1018sub01", or a name like it
            spelled, canon = canon, canonical_section(canon)
            if not canon or "[" in canon or "]" in canon:
                return None
            if canon != spelled:
                respelled.append(canon)
        sec = new(shared if denotation is None else denoted)    # 60,000: no __init__
        sec.line = line
        sec.param_name = pname
        sec.rest = template
        sec._values = None                     # worked out when asked for
        if denotation is not None:
            sec.denotation = denotation
        sections[canon] = sec
        line += step
    if len(sections) != chunks.count:
        return None                            # a repeated section
    unread = chunks.unread
    templates.source.stop = chunks.stop
    diags = Diagnostics()
    for canon, header, at, n in too_many:
        _too_many_keys(diags, path, sections[canon], at, n)
    if unread is not None:
        _too_many_sections(diags, path, line, MAX_SECTIONS + unread, unread)
    parsed = IniFile(path, encoding, sections, [], diags, line - 1, respelled=respelled)
    templates.source.file = weakref.ref(parsed)
    return parsed


class _Chunks:
    """The sections of ``text`` from ``start`` (just after the first one's '['), each from
    just after its '[' -- what ``text[start:].split(nl + "[")`` gives -- a block of at most
    ``_BIG`` characters at a time (``blocks``); a section of more than ``_BIG`` characters
    as a ``_Big`` (not copied). The first ``limit`` sections only: ``stop`` is where the
    first section not read starts (its '['), ``unread`` how many are not read (both None
    when every section is read), ``count`` how many were given."""
    __slots__ = ("text", "sep", "start", "limit", "count", "stop", "unread")

    def __init__(self, text: str, nl: str, start: int, limit: int):
        self.text, self.sep, self.start, self.limit = text, nl + "[", start, limit
        self.count = 0
        self.stop = self.unread = None

    def blocks(self):
        text, sep, pos, limit = self.text, self.sep, self.start, self.limit
        find, rfind, n, n_sep = text.find, text.rfind, len(text), len(sep)
        # the first section's '[' counts into its length (as one piece of the text cut at
        # each "<nl>[", the first starting at the file's '[')
        extra = 1 if pos == 1 else 0
        while pos <= n:
            if self.count == limit:            # the rest is not read (DCF015)
                self.stop, self.unread = pos - 1, 1 + text.count(sep, pos)
                return
            nxt = find(sep, pos)
            end = n if nxt < 0 else nxt
            if end - pos + extra > _BIG:       # one section of more than _BIG characters
                self.count += 1
                yield (_Big(text, pos, end),)
                pos, extra = end + n_sep, 0
                continue
            extra = 0
            if nxt < 0:
                self.count += 1
                yield (text[pos:],)
                return
            # whole sections up to the last "<nl>[" that starts within _BIG of ``pos``, or
            # to the end of the text when that is as near
            cut = n if n - pos <= _BIG else rfind(sep, pos, pos + _BIG + n_sep)
            parts = text[pos:cut].split(sep)
            if self.count + len(parts) > limit:
                parts = parts[:limit - self.count]
                cut = pos + sum(map(len, parts)) + n_sep * len(parts) - n_sep
            self.count += len(parts)
            yield parts
            pos = cut + n_sep


def _comments_only(text: str, nl: str, end: int | None = None) -> bool:
    """Whether every line of ``text[:end]`` is blank or a comment, looked at where each
    starts, in ``text`` (the text before the first header: a file can begin with 60 MB
    of comments, which a copy would hold twice)."""
    n = len(text) if end is None else end
    if n <= _BIG:
        return _body_values(text[:n], nl) == {}
    find, pos = text.find, 0
    while pos <= n:
        j = find(nl, pos, n)
        stop = n if j < 0 else j
        first = text[pos:pos + 1] if pos < n else ""
        if first != ";" and first != "#" and _line(text[pos:stop]) != ():
            return False
        pos = stop + len(nl)
    return True


def _lone(text: str, nl: str, end: int | None = None, start: int = 0) -> bool:
    """Whether ``text`` (``text[start:end]``) has a CR or LF that is not part of a line
    end ``nl`` (counted, not copied: ``text`` can be most of a 60 MB file)."""
    if end is None:
        end = len(text)
    if nl == "\n":
        return text.find("\r", start, end) >= 0
    n = text.count("\r\n", start, end)
    return text.count("\r", start, end) != n or text.count("\n", start, end) != n


class _Big(str):
    """A section of more than ``_BIG`` characters, in the loop of ``_read_sections`` in
    place of its text: where it is in the file's text (``_Templates.big`` reads it there).
    Empty, so that the loop hands it to ``_Templates.other``."""

    def __new__(cls, text: str, start: int, end: int):
        self = super().__new__(cls, "")
        self.text, self.start, self.end = text, start, end
        return self


class _Templates:
    """The templates of one file's sections, by their text with the names cut out, and
    the reading of the sections that ``_read_sections`` does not take in its loop."""

    def __init__(self, source: _Source, nl: str):
        self.source, self.nl = source, nl
        self.by_text: dict[str, _Template] = {}
        self.lines: dict[str, tuple] = {}      # see _body_values
        # (lines from its header to its first key not read, keys not read) of the section
        # ``big`` just read, when it has more than MAX_KEYS keys (DCF014), else None
        self.over: tuple[int, int] | None = None

    def other(self, chunk: str) -> tuple[str, str | None, str | None, _Template, int] | None:
        """(canonical name, ParameterName's value, Denotation's value, template, lines
        to the next header) of a section (its text after its '['), or None."""
        if type(chunk) is _Big:
            return self.big(chunk.text, chunk.start, chunk.end)
        name, closed, body = chunk.partition("]" + self.nl)
        step = 0
        if not closed:
            if chunk[-1:] != "]":
                return None                    # text after a header, or a broken header
            name, step = chunk[:-1], -1        # a header right before the next: no line end
        if "\n" in name or "\r" in name or "[" in name or "]" in name:
            return None                        # text after a header, or a broken header
        if name.strip() != name.strip(" \t"):
            return None                        # other blanks: canonical_section's business
        name = name.strip(" \t")
        if not name:
            return None
        found = self.cut(body)
        if found is None:
            return None
        pname, denotation, template = found
        return name.lower(), pname, denotation, template, template.step + step

    def big(self, text: str, start: int,
            n: int) -> tuple[str, None, None, _Template, int] | None:
        """What ``other`` gives, for a section of more than ``_BIG`` characters (a
        megabyte of comments, a value of 60 MB), ``text[start:n]`` (from just after its
        '['), read line by line in the file's text: no copy of the section, no template
        text (no other section has that text: there is nothing to share). Its names stay
        among its values (nothing is cut out), and its ``text`` is None: its keys are
        found in the file when a message asks (``_Source.keys_at``). None: a line the
        exact reader has to see."""
        nl = self.nl
        end = text.find("]" + nl, start, n)
        if end < 0 and text[n - 1:n] == "]":   # a header right before the next one
            end = n - 1
        name = text[start:end]
        if end <= start or "\n" in name or "\r" in name or "[" in name or "]" in name:
            return None                        # a broken header
        if (_lone(text, nl, n, start) or name.strip() != name.strip(" \t")
                or not name.strip(" \t")):
            return None                        # a lone CR or LF; blanks in the name
        values = _Template()
        find, n_nl = text.find, len(nl)
        pos, step = end + 1 + n_nl, 2          # the header's line and the next header's
        if end == n - 1:                       # (no line: as _Templates.other counts it)
            values.text, values.source, values.step = None, self.source, 1
            return name.strip(" \t").lower(), None, None, values, 1
        keys, over = 0, None                   # key lines; [at, count] beyond MAX_KEYS
        while True:
            j = find(nl, pos, n)
            stop = n if j < 0 else j
            first = text[pos:pos + 1] if pos < n else ""
            if first != ";" and first != "#":  # (a comment: nothing to copy)
                eq = find("=", pos, stop)
                if eq > pos and first not in " \t[":
                    keys += 1
                    if keys > MAX_KEYS:        # counted, not read (as the exact reader)
                        if over is None:
                            over = [step - 1, 0]
                        over[1] += 1
                    else:
                        # as _line reads it, the value copied once (it can be 60 MB)
                        low = text[pos:eq].rstrip(" \t").lower()
                        if low in values:
                            return None        # a repeated key
                        values[low] = text[eq + 1:stop].strip(" \t")
                else:
                    kv = _line(text[pos:stop])
                    if kv is None:
                        return None
            if j < 0:
                break
            pos, step = j + n_nl, step + 1
        values.text, values.source, values.step = None, self.source, step
        self.over = None if over is None else tuple(over)
        return name.strip(" \t").lower(), None, None, values, step

    def cut(self, body: str) -> tuple[str | None, str | None, _Template] | None:
        """(ParameterName's value, Denotation's value, the template) of a section's
        lines, or None when a line is one the exact reader has to see."""
        nl = self.nl
        pname, rest = _cut(body, _NAME_KEY, nl)
        denotation = None
        if _DENOTATION_KEY in rest:            # a name too (SPEC §1), cut out the same way
            denotation, rest = _cut(rest, _DENOTATION_KEY, nl)
        if (pname is not None and _lone(pname, nl)
                or denotation is not None and _lone(denotation, nl)):
            return None                        # a lone CR or LF
        template = self.by_text.get(rest)
        if template is None:
            template = None if _lone(rest, nl) else _body_values(rest, nl, self.lines)
            if template is None:
                return None
            self.by_text[rest] = template
            template.text, template.source = rest, self.source
            template.step = rest.count(nl) + 2   # the header's line and the next header's
        return pname, denotation, template


# A section longer than this is read by ``_Templates.big``: the fast path's copies of a
# section (its text, with the names cut out, as a template and as a dictionary key) cost
# nothing for a section of a few hundred bytes and six times the file for one that is
# most of it (60,000 comment lines of 1 KiB: 546 MB for a 60 MB file, issue 26).
_BIG = 1 << 16

# The two keys whose values are names, cut out of a section's template, as configurators
# spell them (other spellings are ordinary keys: correct, only not shared).
_NAME_KEY = "ParameterName="
_DENOTATION_KEY = "Denotation="


def _cut(body: str, key: str, nl: str) -> tuple[str | None, str]:
    """(the value of ``key``'s line, ``body`` with that value left empty), or (None,
    body) when no line starts with ``key``."""
    i = body.find(key)
    while i > 0 and body[i - 1] != "\n":
        i = body.find(key, i + 1)
    if i < 0:
        return None, body
    i += len(key)
    j = body.find(nl, i)
    if j < 0:
        return body[i:].strip(" \t"), body[:i]
    return body[i:j].strip(" \t"), body[:i] + body[j:]


def _body_values(body: str, nl: str = "\n",
                 lines: dict[str, tuple] | None = None) -> _Template | None:
    """The keys of a section's lines (no header among them), or None when a line is
    one the exact reader has to see (not key=value, comment or blank; indented; a
    repeated key). ``lines`` remembers each line's reading for the next section
    (a file repeats "ObjectType=0x7" and "AccessType=rw" thousands of times)."""
    values = _Template()
    if lines is None:
        lines = {}
    for raw in body.split(nl):
        kv = lines.get(raw)
        if kv is None:
            kv = _line(raw)
            if kv is None:
                return None
            if len(raw) < 256:          # a long line (a comment, a value) seldom repeats
                lines[raw] = kv
        if kv:
            low, v = kv
            if low in values:
                return None                      # a repeated key
            values[low] = v
    return values


def _line(raw: str) -> tuple | None:
    """(lower-case key, value) of a key line, () for a blank or comment line, None for
    a line the exact reader has to see (bad, or indented)."""
    k, eq, v = raw.partition("=")
    if eq and k and k[0] not in " \t;#[":
        return (k.rstrip(" \t").lower(), v.strip(" \t"))
    c = raw.strip(" \t")[:1]
    if c == ";" or c == "#" or not c:
        return ()
    return None


def _parse_exact(text: str, path: str, encoding: str = "utf-8") -> IniFile:
    diags = Capped()       # 5 million bad lines: the first LIMIT of a rule, then a count
    sections: dict[str, Section] = {}
    respelled: list[str] = []
    duplicates = _Duplicates()
    current: Section | None = None
    skipping = False  # inside a repeated section: its keys are not merged into the first
    headers = keys = 0     # the header lines so far; the key lines of the current section
    over: list = []        # the current section's keys beyond MAX_KEYS: [first line, count]
    lines = _split_lines(text)
    lineno = 0
    for raw in lines:
        lineno += 1
        if raw.endswith("\r"):
            raw = raw[:-1]
        s = raw.strip(" \t")
        if not s:
            continue
        c = s[0]
        if c == ";" or c == "#":
            continue
        if c == "[":
            if over:
                _too_many_keys(diags, path, current, *over)
                over = []
            headers += 1
            keys = 0
            if headers > MAX_SECTIONS:
                # the rest is not read: its sections counted as the fast path counts them,
                # the lines that start with '['
                n = 1 + sum(1 for r in lines if r[:1] == "[")
                _too_many_sections(diags, path, lineno, MAX_SECTIONS + n, n)
                lineno -= 1            # (the lines read)
                break
            end = s.find("]")
            if end < 0:
                diags.error(f"malformed section header '{_clip(s)}': missing ']'",
                            Where(path, lineno), rule="DCF003")
                current, skipping = None, True
                continue
            rest = s[end + 1:].strip(" \t")
            if rest:
                if rest[0] in ";#":
                    diags.warning(f"comment after section header ignored: '{_clip(rest)}'",
                                  Where(path, lineno), rule="DCF004")
                else:
                    diags.error(f"text after section header: '{_clip(rest)}'", Where(path, lineno),
                                rule="DCF003")
            name = s[1:end].strip(" \t")
            if not name:
                diags.error("empty section name", Where(path, lineno), rule="DCF003")
                current, skipping = None, True
                continue
            canon = canonical_section(name)
            first = sections.get(canon)
            if first is not None:
                duplicates.add(Duplicate(canon, None, first.line, lineno))
                current, skipping = first, True
            else:
                current = _WrittenSection(name, lineno)
                sections[canon] = current
                skipping = False
                if canon != name.lower():
                    respelled.append(canon)
            continue
        eq = s.find("=")
        if eq <= 0:
            what = "line without '='" if eq < 0 else "key missing before '='"
            diags.error(f"{what}: '{_clip(s)}'", Where(path, lineno), rule="DCF002")
            continue
        if current is None:
            if not skipping:
                diags.error(f"key outside any section: '{_clip(s)}'", Where(path, lineno),
                            rule="DCF001")
            continue
        if skipping:
            continue  # keys of a repeated section: the Duplicate record reports it
        keys += 1
        if keys > MAX_KEYS:          # counted, not read (repeats included: they are kept too)
            if over:
                over[1] += 1
            else:
                over = [lineno, 1]
            continue
        kname = s[:eq].rstrip(" \t")
        klow = kname.lower()
        prev = current.keys.get(klow)
        if prev is not None:
            duplicates.add(Duplicate(canonical_section(current.name), klow, prev.line, lineno))
            continue
        current.add(Key(kname, s[eq + 1:].lstrip(" \t"), lineno))
    if over:
        _too_many_keys(diags, path, current, *over)
    return IniFile(path, encoding, sections, duplicates.kept, diags, lineno, respelled=respelled,
                   more_duplicates=duplicates.more, first_left_out=duplicates.first)


class _Duplicates:
    """The exact reader's repeated sections and keys: the first ``LIMIT``, then a count
    and the first left out (a file can repeat one key on millions of lines)."""
    __slots__ = ("kept", "more", "first")

    def __init__(self):
        self.kept: list[Duplicate] = []
        self.more = 0
        self.first: Duplicate | None = None

    def add(self, dup: Duplicate) -> None:
        if len(self.kept) < LIMIT:
            self.kept.append(dup)
        else:
            self.more += 1
            if self.first is None:
                self.first = dup


def _split_lines(text: str, block: int = 1 << 20):
    """``text.split("\n")``, one block of about ``block`` characters at a time: a list of
    every line of a 60 MB file of short lines would hold 5 million strings at once."""
    find, pos = text.find, 0
    while True:
        end = find("\n", pos + block)
        if end < 0:
            yield from text[pos:].split("\n")
            return
        yield from text[pos:end].split("\n")
        pos = end + 1


def _too_many_keys(diags: Diagnostics, path: str, sec: Section, line: int, n: int) -> None:
    """DCF014 at the first key line not read, of the section ``sec``."""
    diags.error(f"[{shorten(sec.name)}] (line {sec.line}) has {MAX_KEYS + n:,} keys, more "
                f"than the {MAX_KEYS:,} a section may have: the {n:,} from this line on "
                "are not read", Where(path, line), rule="DCF014",
                hint="no CiA 306 section has that many: an object list names each of the "
                     "65,536 indexes at most once")


def _too_many_sections(diags: Diagnostics, path: str, line: int, total: int,
                       n: int) -> None:
    """DCF015 at the first section not read."""
    diags.error(f"the file has {total:,} sections, more than the {MAX_SECTIONS:,} a file may "
                f"have: the {n:,} from this line on are not read", Where(path, line),
                rule="DCF015",
                hint="every network variable of CiA 405 (A000-A8FF) is 589,824 sections: "
                     "is this the file you meant?")


def _clip(s: str, n: int = 60) -> str:
    """A line quoted in a diagnostic: control characters escaped, long lines cut."""
    if not s.isprintable():
        s = "".join(c if c.isprintable() or c == "\t" else f"\\x{ord(c):02x}" for c in s)
    return s if len(s) <= n else s[:n] + "..."

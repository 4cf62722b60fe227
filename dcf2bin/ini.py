"""A line-tracking reader for CiA 306 INI text (SPEC.md §1).

Not configparser: names are case-insensitive, every section and key keeps its
line number, duplicates are reported with both lines, nothing is dropped
silently, and it is fast (one pass, no regex on the common path).
"""
from __future__ import annotations

import re
from dataclasses import dataclass

from dcf2bin.diagnostics import Diagnostics, Where

# "[1018sub01]" and "[1018sub1]" are the same section (SPEC §1): canonical form
# is lower case with the subindex in hex without leading zeros.
_SUB_RE = re.compile(r"([0-9a-f]{4})sub([0-9a-f]{1,2})")


def canonical_section(name: str) -> str:
    low = name.strip().lower()
    m = _SUB_RE.fullmatch(low)
    if m:
        return f"{m.group(1)}sub{int(m.group(2), 16):x}"
    return low


@dataclass(slots=True)
class Key:
    name: str   # as written
    value: str  # trimmed
    line: int


class Section:
    """One section: its values by lower-case key, and (lazily) each key's name and line.

    The fast reader keeps where the section's text is and the parts it has parsed;
    ``values`` and ``keys`` (name, value and line of every key) are worked out on
    first use, so the common case, which never prints a diagnostic, pays little.

    From the fast reader, ``head_key``/``head_value`` are the lower-case key and the
    value of the section's first line when that is a key, and ``rest`` the values of
    its other lines: one dict shared by every section whose lines after the first are
    the same text (the 254 sub-objects of a network-variable array differ only in
    their ParameterName), so the model can build such entries once. The exact reader
    leaves them None.
    """
    __slots__ = ("name", "line", "_values", "_keys", "_text", "_at", "head_key",
                 "head_value", "rest")

    def __init__(self, name: str, line: int, values: dict[str, str] | None = None,
                 keys: dict[str, Key] | None = None, text: str | None = None, at: int = 0,
                 head_key: str | None = None, head_value: str | None = None,
                 rest: dict[str, str] | None = None):
        self.name = name            # as written
        self.line = line
        self._values = values if values is not None or rest is not None else {}
        self._keys = keys
        self._text = text           # the file's text; the section's header line starts at _at
        self._at = at
        self.head_key = head_key
        self.head_value = head_value
        self.rest = rest

    @property
    def values(self) -> dict[str, str]:
        """lower-case key name -> value (blanks trimmed)."""
        if self._values is None:
            if self.head_key is None:
                self._values = dict(self.rest)
            else:
                self._values = {self.head_key: self.head_value}
                self._values.update(self.rest)
        return self._values

    @property
    def keys(self) -> dict[str, Key]:
        """lower-case key name -> Key(name as written, value, line)."""
        if self._keys is None:
            keys: dict[str, Key] = {}
            text = self._text or ""
            end = text.find("\n[", self._at)
            lines = text[self._at:end if end >= 0 else len(text)].split("\n")
            for i, raw in enumerate(lines[1:], self.line + 1):   # after the header line
                k, eq, v = raw.partition("=")
                k = k.strip(" \t\r")
                if eq and k and k[0] not in ";#":
                    keys.setdefault(k.lower(), Key(k, v.strip(" \t\r"), i))
            self._keys = keys
        return self._keys

    def has(self, key: str) -> bool:
        return key in self.values

    def get(self, key: str) -> str | None:
        """The value of ``key`` (lower case), or None when absent or empty."""
        return self.values.get(key) or None

    def line_of(self, key: str) -> int:
        if key not in self.values:
            return self.line
        return self.keys[key].line

    def add(self, key: Key) -> None:
        low = key.name.lower()
        self.values[low] = key.value
        if self._keys is None:
            self._keys = {}
        self._keys[low] = key


@dataclass(slots=True)
class Duplicate:
    section: str        # canonical section name
    key: str | None     # lower-case key name; None for a repeated section
    first_line: int
    line: int


@dataclass
class IniFile:
    path: str
    encoding: str
    sections: dict[str, Section]
    duplicates: list[Duplicate]
    diagnostics: Diagnostics
    line_count: int = 0

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


def parse_bytes(data: bytes, path: str) -> IniFile:
    text, encoding = decode_bytes(data)
    return parse_text(text, path, encoding)


def read(path: str) -> IniFile:
    with open(path, "rb") as f:
        return parse_bytes(f.read(), path)


def parse_text(text: str, path: str, encoding: str = "utf-8") -> IniFile:
    """Parse INI text. A fast path handles clean files; anything unusual (a bad line,
    a duplicate, a comment after a header) goes through the exact line-by-line
    reader, which reports every problem with its line."""
    fast = _parse_fast(text, path, encoding)
    if fast is not None:
        return fast
    return _parse_exact(text, path, encoding)


def _parse_fast(text: str, path: str, encoding: str) -> IniFile | None:
    """The common case, a clean file, one section at a time instead of one line at a time.

    The text is cut at every line that starts with '[' (a header: INI has no other
    use for it), at the file's own line ends (no converted copy of a CRLF text); a
    section keeps only where it starts in the text. A section's lines after its first
    are very often the same text as another section's (see ``Section``), so that text
    is parsed once and its values shared. Anything the exact reader would comment on
    (a bad line, an indented line, a duplicate, text after a header, a lone CR) makes
    this return None, and the exact reader takes the file.
    """
    nl = "\n"
    if "\r" in text:
        crlf = text.count("\r\n")
        if text.count("\r") != crlf:
            return None                        # a lone CR: let the exact reader deal with it
        if crlf == text.count("\n"):
            nl = "\r\n"                        # every line ends in CRLF
        else:
            text = text.replace("\r\n", "\n")   # mixed line ends
    sep, close = nl + "[", "]" + nl
    n_sep = len(sep)
    chunks = text.split(sep)                   # each a section, from just after its '['
    if text[:1] == "[":                        # no lines before the first header
        chunks[0] = chunks[0][1:]
        line, at = 1, 1
    else:                                      # blank and comment lines only
        head = chunks.pop(0)
        if _body_values(head, nl) != {}:
            return None
        line, at = head.count(nl) + 2, len(head) + n_sep
    sections: dict[str, Section] = {}
    shapes: dict[str, dict[str, str] | None] = {}
    shapes_get = shapes.get
    lower = _LOWER.get
    for chunk in chunks:
        name, sep_found, body = chunk.partition(close)
        if not sep_found:                      # the last line of the file is a header
            if chunk[-1:] != "]":
                return None
            name = chunk[:-1]
        if "\n" in name or "[" in name or "]" in name:
            return None                        # text after a header, or a broken header
        first, _, rest = body.partition(nl)
        shape = shapes_get(rest)
        if shape is None:
            shape = shapes[rest] = _body_values(rest, nl)
            if shape is None:
                return None
        k, eq, v = first.partition("=")
        if eq and k and k[0] not in " \t;#[":
            low = lower(k) or _lower(k)
            if low in shape:
                return None                    # a repeated key
            v = v.strip(" \t")
        elif _body_values(first, nl) == {}:    # a blank or comment line
            low = v = None
        else:
            return None
        name = name.strip(" \t")
        canon = name.lower()
        if (len(canon) > 8 and canon[7] == "0") or not canon:
            canon = canonical_section(name)
            if not canon or "[" in canon or "]" in canon:
                return None
        if canon in sections:
            return None                        # a repeated section
        sections[canon] = Section(name, line, None, None, text, at - 1, low, v, shape)
        line += chunk.count(nl) + 1
        at += len(chunk) + n_sep
    return IniFile(path, encoding, sections, [], Diagnostics(), text.count("\n") + 1)


# Key names as written -> lower case without the blanks before '=': a file uses few
# spellings ("ParameterName"), so each is lowered once, not once per section.
_LOWER: dict[str, str] = {}


def _lower(key: str) -> str:
    low = key.rstrip(" \t").lower()
    if len(_LOWER) < 4096:
        _LOWER[key] = low
    return low


def _body_values(body: str, nl: str = "\n") -> dict[str, str] | None:
    """The keys of a section's lines (no header among them), or None when a line is
    one the exact reader has to see (not key=value, comment or blank; indented; a
    repeated key)."""
    values: dict[str, str] = {}
    for raw in body.split(nl):
        k, eq, v = raw.partition("=")
        if eq and k and k[0] not in " \t;#[":
            low = _LOWER.get(k) or _lower(k)
            if low in values:
                return None
            values[low] = v.strip(" \t")
            continue
        c = raw.strip(" \t")[:1]
        if c == ";" or c == "#" or not c:
            continue
        return None                              # bad line, or indented
    return values


def _parse_exact(text: str, path: str, encoding: str = "utf-8") -> IniFile:
    diags = Diagnostics()
    sections: dict[str, Section] = {}
    duplicates: list[Duplicate] = []
    current: Section | None = None
    skipping = False  # inside a repeated section: its keys are not merged into the first
    lines = text.split("\n")
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
            end = s.find("]")
            if end < 0:
                diags.error(f"malformed section header '{s}': missing ']'", Where(path, lineno),
                            rule="DCF003")
                current, skipping = None, True
                continue
            rest = s[end + 1:].strip(" \t")
            if rest:
                if rest[0] in ";#":
                    diags.warning(f"comment after section header ignored: '{rest}'",
                                  Where(path, lineno), rule="DCF004")
                else:
                    diags.error(f"text after section header: '{rest}'", Where(path, lineno),
                                rule="DCF003")
            name = s[1:end].strip(" \t")
            if not name:
                diags.error("empty section name", Where(path, lineno), rule="DCF003")
                current, skipping = None, True
                continue
            canon = canonical_section(name)
            first = sections.get(canon)
            if first is not None:
                duplicates.append(Duplicate(canon, None, first.line, lineno))
                current, skipping = first, True
            else:
                current = Section(name, lineno, keys={})
                sections[canon] = current
                skipping = False
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
        kname = s[:eq].rstrip(" \t")
        value = s[eq + 1:].lstrip(" \t")
        klow = kname.lower()
        if skipping:
            continue  # keys of a repeated section: the Duplicate record reports it
        prev = current.keys.get(klow)
        if prev is not None:
            duplicates.append(Duplicate(canonical_section(current.name), klow, prev.line, lineno))
            continue
        current.add(Key(kname, value, lineno))
    return IniFile(path, encoding, sections, duplicates, diags, lineno)


def _clip(s: str, n: int = 60) -> str:
    """A line quoted in a diagnostic: control characters escaped, long lines cut."""
    if not s.isprintable():
        s = "".join(c if c.isprintable() or c == "\t" else f"\\x{ord(c):02x}" for c in s)
    return s if len(s) <= n else s[:n] + "..."

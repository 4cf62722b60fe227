"""A line-tracking reader for CiA 306 INI text (SPEC.md §1).

Not configparser: names are case-insensitive, every section and key keeps its
line number, duplicates are reported with both lines, nothing is dropped
silently, and it is fast (one pass, no regex on the common path).
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field

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


@dataclass(slots=True)
class Section:
    name: str   # as written
    line: int
    keys: dict[str, Key] = field(default_factory=dict)  # lower-case key name -> Key

    def get(self, key: str) -> str | None:
        """The value of ``key`` (lower case), or None when absent or empty."""
        k = self.keys.get(key)
        if k is None or k.value == "":
            return None
        return k.value

    def line_of(self, key: str) -> int:
        k = self.keys.get(key)
        return k.line if k is not None else self.line


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
                current = Section(name, lineno)
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
        current.keys[klow] = Key(kname, value, lineno)
    return IniFile(path, encoding, sections, duplicates, diags, lineno)


def _clip(s: str, n: int = 60) -> str:
    return s if len(s) <= n else s[:n] + "..."

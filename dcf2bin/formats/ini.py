"""CiA 306 INI text (EDS, DCF): the format dcf2bin has always read.

The reader is ``dcf2bin.ini`` (line-tracking, fast) and the model's builder
(``dcf2bin.model``); this module registers them and writes sections back as text
(``text``: what a reader of another format hands to code that edits CiA 306 text, such
as the network configurator's configured DCF).
"""
from __future__ import annotations

import re

from dcf2bin import ini as ini_mod

_SECTION = re.compile(rb"(?m)^[ \t]*\[[^\]\r\n]+\]")


def sniff(data: bytes) -> bool:
    """CiA 306 text: a ``[section]`` line in the first 64 KiB, and text by the DCF
    reader's own test (``ini.not_text``)."""
    return bool(_SECTION.search(data[:65536])) and ini_mod.not_text(data) is None


def read(data: bytes, path: str) -> ini_mod.IniFile:
    return ini_mod.parse_bytes(data, path)


def text(parsed: ini_mod.IniFile) -> str:
    """The sections of ``parsed`` as CiA 306 text, in their order, each key as written
    (``Name=value``), a blank line after each section, LF line ends. A value is one line:
    a line end in a value is written as a blank (CiA 306 has no way to say it)."""
    out: list[str] = []
    for sec in parsed.sections.values():
        out.append(f"[{sec.name}]")
        for k in sec.keys.values():
            value = k.value
            if "\n" in value or "\r" in value:
                value = " ".join(value.split())
            out.append(f"{k.name}={value}")
        out.append("")
    return "\n".join(out) + ("\n" if out else "")


def dump(dev, kind: str = "eds", *, name: str | None = None, node_id: int | None = None):
    """``dev`` as CiA 306 text: an EDS or (``kind`` "dcf") a DCF; a ``written.Written``
    (the bytes and the warnings about what the text cannot say). See ``ini_writer``."""
    from dcf2bin.formats.ini_writer import dump as write
    return write(dev, kind, name=name, node_id=node_id)

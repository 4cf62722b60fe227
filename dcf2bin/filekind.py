"""What kind of file an input is: a device description (DCF/EDS text, CiA 311 XML), a binary
container, or the lossless JSON form.

One rule for every command (issue 19): the content decides where it is clear -- the JSON
form starts with ``{`` and names its format, a container's first DWORD is its own size, a
description format passes its own content test (the registry of formats,
``dcf2bin.formats.registry``: XML starts with ``<``, CiA 306 text has ``[section]`` lines
and passes the DCF reader's text test ``ini.not_text``) -- and the file name only where the
content is not (an empty file, a damaged container, binary junk): such a file is then read
as its name says, and the reader of that kind reports what is wrong.

No click here: ``dcf2bin.cli`` and the lint runner both use it, and they word a mismatch
with ``mismatch``.
"""
from __future__ import annotations

import os

from dcf2bin.formats import registry

DCF = "dcf"
XDD = "xdd"
CONTAINER = "bin"
JSON = "json"

#: what each kind is called in a sentence
NAMES = {DCF: "DCF/EDS text", XDD: "CiA 311 XML (XDD/XDC)", CONTAINER: "a binary container",
         JSON: "the JSON form of a container"}

# the description formats' suffixes come from their registry (dcf2bin.formats.registry)
_BY_SUFFIX = {".bin": CONTAINER, ".json": JSON, **registry.kinds_by_suffix()}


def by_name(path: str) -> str | None:
    """The kind a file's suffix promises (None for '-', no suffix or another one)."""
    return _BY_SUFFIX.get(os.path.splitext(path)[1].lower())


def detect(data: bytes, path: str = "") -> str:
    """The kind of ``data``: by content where the content is clear, else by ``path``'s
    suffix, else by the content's best guess.

    Clear: a ``{`` first and the JSON form's ``"dcf2bin-container"`` mark; a complete
    container header (its first DWORD is the file's size, 40 bytes or more); CiA 306 text
    (the DCF reader's own text test) with at least one ``[section]`` line. Anything else --
    an empty file, a truncated or damaged container, a text without sections, UTF-16 -- is
    decided by the name, and without a known suffix a binary file is a container and text
    is DCF."""
    kind = _clear(data)
    if kind is not None:
        return kind
    named = by_name(path)
    if named is not None:
        return named
    from dcf2bin.ini import not_text
    if _body(data)[:1] == b"{":
        return JSON
    problem = not_text(data)
    return DCF if problem is None or "UTF-16" in problem[0] else CONTAINER


def _body(data: bytes) -> bytes:
    body = data[:8192].lstrip(b" \t\r\n\x0b\x0c")
    if body.startswith(b"\xef\xbb\xbf"):
        body = body[3:].lstrip(b" \t\r\n\x0b\x0c")
    return body


def _clear(data: bytes) -> str | None:
    if _body(data)[:1] == b"{" and b'"dcf2bin-container"' in data[:65536]:
        return JSON
    if len(data) >= 40 and int.from_bytes(data[:4], "little") == len(data):
        return CONTAINER
    fmt = registry.sniff(data)          # a description format's own content test
    return fmt.kind if fmt is not None else None


def contradicts_name(kind: str, path: str) -> bool:
    """True when the content's kind is not the one the file's suffix promises."""
    named = by_name(path)
    return named is not None and named != kind


def what_it_is(path: str, kind: str) -> str:
    """'fake.bin is DCF/EDS text' (the name as given)."""
    return f"{path} is {NAMES[kind]}"


# The command that takes each kind, for the sentence that names it.
_USE = {
    DCF: "use dcf2bin compile to make a container of it (dcf2bin validate checks it)",
    XDD: "use dcf2bin compile to make a container of it (dcf2bin validate checks it)",
    CONTAINER: "use dcf2bin dump to read it (dcf2bin bin2dcf turns it into a DCF)",
    JSON: "use dcf2bin compile to turn it back into the container",
}


def advice(kind: str) -> str:
    """'use dcf2bin dump to read it ...': the command that takes a file of this kind."""
    return _USE[kind]


def mismatch(path: str, kind: str, wanted: str | tuple[str, ...], *,
             use: str | dict[str, str] | None = None) -> str | None:
    """The sentence for a file of the wrong kind: None when ``kind`` is one of ``wanted``.

    ``fake.bin is DCF/EDS text, not a binary container; use dcf2bin compile ...``
    ``use`` replaces the standard advice (an option that takes the file, say): one text
    for every kind, or a text per kind (the others keep the standard one)."""
    wanted = (wanted,) if isinstance(wanted, str) else tuple(wanted)
    if kind in wanted:
        return None
    # a command that takes DCF/EDS text takes CiA 311 XML too: "DCF/EDS text" names both
    want = " or ".join(NAMES[w].replace("the JSON form of a container", "its JSON form")
                       for w in wanted if not (w == XDD and DCF in wanted))
    if isinstance(use, dict):
        use = use.get(kind)
    return f"{what_it_is(path, kind)}, not {want}; {use or _USE[kind]}"


def misnamed(path: str, kind: str) -> str | None:
    """The note for a file whose content contradicts its suffix, read by its content:
    'fake.dcf is a binary container, not DCF/EDS text as its name says; read as a binary
    container'. None when the name fits (or says nothing)."""
    if not contradicts_name(kind, path):
        return None
    named = NAMES[by_name(path)]
    return f"{what_it_is(path, kind)}, not {named} as its name says; read as {NAMES[kind]}"

"""What kind of file an input is: a device description (DCF/EDS text, CiA 311 XML), a binary
container, a CiA 302-3 concise DCF (what ``network build`` writes for a slave), the lossless
JSON form of either -- or one of the other files dcf2bin reads or writes, given where it
does not belong.

One rule for every command (issue 19): the content decides where it is clear -- the JSON
form starts with ``{`` and names its format, a container's first DWORD is its own size, a
concise DCF's is the number of the entries that fill it to its last byte, a
description format passes its own content test (the registry of formats,
``dcf2bin.formats.registry``: XML starts with ``<``, CiA 306 text has ``[section]`` lines
and passes the DCF reader's text test ``ini.not_text``) -- and the file name only where the
content is not (an empty file, a damaged container, binary junk): such a file is then read
as its name says, and the reader of that kind reports what is wrong.

The other kinds (issue 26 item 15) are a table, ``KINDS``: each one's name, what it is
called in a sentence, the command that reads it (or that dcf2bin writes it and reads it
nowhere), a test of the content and the name suffixes that promise it. A CSV list given to
``simulate`` is then one sentence -- "vars.csv is not DCF/EDS text (it looks like CSV:
dcf2bin allocate reads it)" -- instead of one DCF002 per line. Their tests run before the
description formats' (an SVG or HTML file starts with ``<`` too, a ``.cpj`` has
``[section]`` lines); ``register`` adds a kind.

No click here: ``dcf2bin.cli`` and the lint runner both use it, and they word a mismatch
with ``mismatch``.
"""
from __future__ import annotations

import os
import re
from collections.abc import Callable
from dataclasses import dataclass

from dcf2bin.formats import registry

DCF = "dcf"
XDD = "xdd"
CONTAINER = "bin"
JSON = "json"
CONCISE = "concise"
CONCISE_JSON = "concise-json"

#: what each kind dcf2bin compiles, or reads as a container or a concise DCF, is called in a
#: sentence
NAMES = {DCF: "DCF/EDS text", XDD: "CiA 311 XML (XDD/XDC)", CONTAINER: "a binary container",
         JSON: "the JSON form of a container", CONCISE: "a concise DCF (CiA 302-3)",
         CONCISE_JSON: "the JSON form of a concise DCF"}

# the description formats' suffixes come from their registry (dcf2bin.formats.registry)
_BY_SUFFIX = {".bin": CONTAINER, ".json": JSON, **registry.kinds_by_suffix()}


@dataclass(frozen=True)
class Kind:
    """Another kind of file: ``name`` (the kind's key), ``called`` ('CSV': "it looks like
    CSV"), ``words`` (who reads it: 'dcf2bin allocate reads it', or 'dcf2bin writes this;
    it is not an input'), ``detect`` (True for content of this kind: the first 64 KiB,
    never decoded as a whole), ``suffixes`` (the names that promise it, lower case)."""
    name: str
    called: str
    words: str
    detect: Callable[[bytes], bool]
    suffixes: tuple[str, ...] = ()


_OUTPUT = "dcf2bin writes this; it is not an input"


# -- content tests: each cheap, on the start of the file -----------------------------------------

def _text_head(data: bytes) -> str | None:
    """The first 8 KiB as text (BOM and leading blank lines dropped), None for binary."""
    head = data[:8192]
    if b"\0" in head:
        return None
    if head.startswith(b"\xef\xbb\xbf"):
        head = head[3:]
    return head.decode("latin-1").lstrip(" \t\r\n\x0b\x0c")


def _first_line(data: bytes, comments: str = "") -> str | None:
    """The first line that is not blank (nor a comment starting with one of ``comments``)."""
    text = _text_head(data)
    if text is None:
        return None
    for line in text.splitlines():
        s = line.strip()
        if s and not (comments and s[0] in comments):
            return s
    return None


_CPJ = re.compile(r"(?im)^[ \t]*\[topology\d*\][ \t]*$")
_YAML_KEY = re.compile(r"[A-Za-z_][\w.\- ]*:(\s.*)?")
_CSV_FIELD = re.compile(r"\s*[A-Za-z_][\w .()/-]*\s*")
_IEC = re.compile(r"(?im)^\s*(VAR_GLOBAL|VAR_EXTERNAL|VAR|TYPE|PROGRAM|FUNCTION_BLOCK)\b")
_IEC_END = re.compile(r"(?i)\bEND_(VAR|TYPE|PROGRAM|FUNCTION_BLOCK)\b")
_C = re.compile(r"(?m)^[ \t]*#[ \t]*(include|define|ifndef|ifdef|pragma)\b")
_JSON_OUT = re.compile(rb'"format"\s*:\s*"dcf2bin-(?!container"|concise")[a-z-]+"')


def _is_cpj(data: bytes) -> bool:
    text = _text_head(data)
    return text is not None and _CPJ.search(text) is not None


def _is_yaml(data: bytes) -> bool:
    line = _first_line(data, "#")
    if line is None:
        return False
    if line == "---" or line.startswith("%YAML"):
        return True
    return _YAML_KEY.fullmatch(line) is not None and "=" not in line.partition(":")[0]


def _csv_header(data: bytes) -> list[str] | None:
    line = _first_line(data)
    if line is None or "," not in line or "=" in line or line[0] in "[;#{<":
        return None
    fields = line.split(",")
    if all(_CSV_FIELD.fullmatch(f) for f in fields):
        return [f.strip().lower() for f in fields]
    return None


def _is_vars_csv(data: bytes) -> bool:
    header = _csv_header(data)
    return header is not None and "name" in header and "index" not in header


def _is_map_csv(data: bytes) -> bool:
    header = _csv_header(data)
    return header is not None and header[:3] == ["name", "index", "subindex"]


def _is_iec(data: bytes) -> bool:
    text = _text_head(data)
    return text is not None and (text.startswith("(*") or _IEC.search(text) is not None) \
        and _IEC_END.search(text) is not None


def _is_c(data: bytes) -> bool:
    text = _text_head(data)
    if text is None:
        return False
    return text.startswith(("/*", "//")) or _C.search(text) is not None


def _is_json_output(data: bytes) -> bool:
    return _body(data)[:1] == b"{" and _JSON_OUT.search(data[:4096]) is not None


def _is_svg(data: bytes) -> bool:
    text = _text_head(data)
    return text is not None and "<svg" in text[:1024].lower()


def _is_html(data: bytes) -> bool:
    text = _text_head(data)
    return text is not None and text[:256].lower().startswith(("<!doctype html", "<html"))


def _is_lenze_bin(data: bytes) -> bool:
    """export -f lenze-bin: 12-byte records, flags 0x41 (0x01 on the last), wLen 4."""
    n = len(data)
    if n < 12 or n % 12:
        return False
    records = range(0, n, 12) if n <= 12 * 256 else [*range(0, 12 * 255, 12), n - 12]
    for at in records:
        last = at == n - 12
        if data[at] != (0x01 if last else 0x41) or data[at + 8:at + 10] != b"\x04\x00":
            return False
    return True


#: The other kinds, tested in this order after the clear ones (the JSON forms, a container,
#: a whole concise DCF) and before the description formats, so that a .cpj's [Topology]
#: sections, a YAML flow list or an SVG picture are not taken for a DCF or an XDD.
KINDS: list[Kind] = [
    Kind("json-output", "a JSON report of dcf2bin", _OUTPUT, _is_json_output),
    Kind("cpj", "a CiA 306-3 network project",
         "dcf2bin network check and network show read it", _is_cpj, (".cpj",)),
    Kind("html", "an HTML page", "dcf2bin map and network show write this; it is not an input",
         _is_html, (".html", ".htm")),
    Kind("svg", "an SVG picture", "dcf2bin map and network show write this; it is not an input",
         _is_svg, (".svg",)),
    Kind("c", "C source", "dcf2bin compile, map and export write this; it is not an input",
         _is_c, (".c", ".h")),
    Kind("iec", "IEC 61131-3 text", "dcf2bin map and export write this; it is not an input",
         _is_iec, (".st", ".iecst")),
    Kind("map-csv", "the CSV map of dcf2bin map", _OUTPUT, _is_map_csv),
    Kind("csv", "CSV", "dcf2bin allocate reads it", _is_vars_csv, (".csv",)),
    Kind("yaml", "a YAML network file",
         "dcf2bin network check, show, build, download and scan read it", _is_yaml,
         (".yml", ".yaml")),
    Kind("lenze-bin", "Lenze PLC Designer records",
         "dcf2bin export --format lenze-bin writes this; it is not an input", _is_lenze_bin),
]


def register(kind: Kind, *, first: bool = False) -> None:
    """Add a kind to the table (``first``: tested before the others; a kind with the same
    name is replaced)."""
    KINDS[:] = [k for k in KINDS if k.name != kind.name]
    KINDS.insert(0, kind) if first else KINDS.append(kind)


def kind_of(name: str) -> Kind | None:
    """The table's entry of a kind (None for the kinds of NAMES)."""
    return next((k for k in KINDS if k.name == name), None)


def called(kind: str) -> str:
    """What a kind is called in a sentence."""
    if kind in NAMES:
        return NAMES[kind]
    k = kind_of(kind)
    return k.called if k is not None else kind


# -- the rule -------------------------------------------------------------------------------------

def by_name(path: str) -> str | None:
    """The kind a file's suffix promises (None for '-', no suffix or another one)."""
    suffix = os.path.splitext(path)[1].lower()
    if suffix in _BY_SUFFIX:
        return _BY_SUFFIX[suffix]
    return next((k.name for k in KINDS if suffix and suffix in k.suffixes), None)


def detect(data: bytes, path: str = "") -> str:
    """The kind of ``data``: by content where the content is clear, else by ``path``'s
    suffix, else by the content's best guess.

    Clear: a ``{`` first and a JSON form's ``"dcf2bin-container"`` or ``"dcf2bin-concise"``
    mark; a complete container header (its first DWORD is the file's size, 40 bytes or
    more); a whole concise DCF (a DWORD count, then exactly that many entries up to the
    file's last byte: ``concise.fills``); a kind of ``KINDS`` whose test the content
    passes; a damaged concise DCF (``concise.damaged``: a first DWORD smaller than the file
    and a first entry whole inside it that writes an object, 0x1000 or above); a description
    format's own content test (CiA 306 text: the DCF reader's text test and a ``[section]``
    line). Anything else -- an empty file, a truncated or damaged container, a text without
    sections, UTF-16 -- is decided by the name, and without a known suffix a binary file is
    a container and text is DCF.

    A file cannot be both a whole container and a whole concise DCF: a container's first
    DWORD is its own size, a concise DCF's the number of its entries, each 7 bytes or more
    (SPEC §3.2), so it is always less than the file's size. ``00 00 00 00`` is an empty
    concise DCF; a file shorter than a container's header whose first DWORD is its size
    (a container cut short) is read as its name says."""
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
    from dcf2bin import concise
    if _body(data)[:1] == b"{":
        if b'"dcf2bin-container"' in data[:65536]:
            return JSON
        if b'"dcf2bin-concise"' in data[:65536]:
            return CONCISE_JSON
    if len(data) >= 40 and int.from_bytes(data[:4], "little") == len(data):
        return CONTAINER
    if concise.fills(data):             # walks the entries' heads: the whole file
        return CONCISE
    head = data[:65536]
    for k in KINDS:
        if k.detect(head):
            return k.name
    if concise.damaged(data):
        return CONCISE
    fmt = registry.sniff(data)          # a description format's own content test
    return fmt.kind if fmt is not None else None


# a name that promises one kind promises these too: a concise DCF is a .bin as a container is
_SAME_NAME = {CONTAINER: (CONCISE,), JSON: (CONCISE_JSON,)}


def contradicts_name(kind: str, path: str) -> bool:
    """True when the content's kind is not the one the file's suffix promises (``.bin``
    promises a container or a concise DCF, ``.json`` the JSON form of either)."""
    named = by_name(path)
    return named is not None and named != kind and kind not in _SAME_NAME.get(named, ())


def what_it_is(path: str, kind: str) -> str:
    """'fake.bin is DCF/EDS text' (the name as given)."""
    return f"{path} is {called(kind)}"


# The command that takes each kind, for the sentence that names it.
_USE = {
    DCF: "use dcf2bin compile to make a container of it (dcf2bin validate checks it)",
    XDD: "use dcf2bin compile to make a container of it (dcf2bin validate checks it)",
    CONTAINER: "use dcf2bin dump to read it (dcf2bin bin2dcf turns it into a DCF)",
    JSON: "use dcf2bin compile to turn it back into the container",
    CONCISE: "use dcf2bin dump to read it (dcf2bin validate checks it, download writes it "
             "to a node, bin2dcf turns it into a DCF)",
    CONCISE_JSON: "use dcf2bin compile to turn it back into the concise DCF",
}


def advice(kind: str) -> str:
    """'use dcf2bin dump to read it ...': the command that takes a file of this kind (for
    another kind: who reads it, or that dcf2bin writes it)."""
    if kind in _USE:
        return _USE[kind]
    k = kind_of(kind)
    return k.words if k is not None else ""


def mismatch(path: str, kind: str, wanted: str | tuple[str, ...], *,
             use: str | dict[str, str] | None = None) -> str | None:
    """The sentence for a file of the wrong kind: None when ``kind`` is one of ``wanted``.

    ``fake.bin is DCF/EDS text, not a binary container; use dcf2bin compile ...``;
    another kind: ``vars.csv is not DCF/EDS text (it looks like CSV: dcf2bin allocate
    reads it)``. ``use`` replaces the standard advice (an option that takes the file, say):
    one text for every kind, or a text per kind (the others keep the standard one)."""
    wanted = (wanted,) if isinstance(wanted, str) else tuple(wanted)
    if kind in wanted:
        return None
    if isinstance(use, dict):
        use = use.get(kind)
    if kind not in NAMES:
        # what the file was most likely meant to be: DCF/EDS text where that is read
        first = next((k for k in (DCF, XDD, CONTAINER, CONCISE, JSON) if k in wanted),
                     wanted[0])
        return f"{path} is not {called(first)} (it looks like {called(kind)}: " \
            f"{advice(kind)})" + (f"; {use}" if use else "")
    # a command that takes DCF/EDS text takes CiA 311 XML too: "DCF/EDS text" names both;
    # "its JSON form" names the JSON forms of the kinds named before it
    named = _named(wanted)
    # both binaries and both JSON forms: the JSON form follows them, "of either"
    either = {CONTAINER, CONCISE, JSON, CONCISE_JSON} <= set(wanted)
    if either:
        named = [w for w in named if w != JSON] + [JSON]
    form = "the JSON form of either" if either else "its JSON form"
    want = " or ".join(called(w).replace("the JSON form of a container", form)
                       .replace("the JSON form of a concise DCF", form)
                       for w in named)
    return f"{what_it_is(path, kind)}, not {want}; {use or _USE[kind]}"


def _named(wanted: tuple[str, ...]) -> list[str]:
    """The kinds a mismatch names: XDD goes with DCF, one JSON form for both."""
    out = [w for w in wanted if not (w == XDD and DCF in wanted)]
    if JSON in out and CONCISE_JSON in out:
        out.remove(CONCISE_JSON)
    return out


def misnamed(path: str, kind: str) -> str | None:
    """The note for a file whose content contradicts its suffix, read by its content:
    'fake.dcf is a binary container, not DCF/EDS text as its name says; read as a binary
    container'. None when the name fits (or says nothing)."""
    if not contradicts_name(kind, path):
        return None
    named = called(by_name(path))
    return f"{what_it_is(path, kind)}, not {named} as its name says; read as {called(kind)}"


__all__ = ["CONCISE", "CONCISE_JSON", "CONTAINER", "DCF", "JSON", "XDD", "KINDS", "Kind", "NAMES",
           "advice", "by_name", "called", "contradicts_name", "detect", "kind_of", "misnamed",
           "mismatch", "register", "what_it_is"]

"""Reading a node's file for a network: through the one bounded reader of every input
(:mod:`dcf2bin.fileio`): only a regular file, never more than 64 MiB; and only a device
description, CiA 306 text (EDS, DCF) or CiA 311 XML (XDD, XDC), read through the registry
of formats (issue 28) as every command reads one (issue 26: a binary container, its JSON
form, is refused by its content as every command tells it; binary junk is the INI
reader's DCF008, as ``validate`` says it).

A configured DCF is CiA 306 text, edited line by line (``dcfedit``, ``allocate --into``):
:func:`cia306` gives the text a node's DCF is made of -- the file itself for CiA 306 text,
its sections written as CiA 306 text for CiA 311 XML -- and the INI reading of exactly
that text.
"""
from __future__ import annotations

from dcf2bin.fileio import read_file

#: what a network reads as a node's file, for the sentence that refuses another kind
READS = "a network reads each node's EDS, DCF, XDD or XDC"

# the network's words for the kinds it refuses (filekind's advice names the commands that
# take them, such as compile: the network takes none of them)
_ADVICE = {
    "bin": f"{READS} (dcf2bin bin2dcf turns a container into a DCF)",
    "json": READS,
    "concise": f"{READS} (network build writes a slave's concise DCF, and its DCF beside it)",
    "concise-json": READS,
}


def read_node_file(path: str) -> bytes:
    """The bytes of the file at ``path``, a name written in the network file; OSError
    (with ``strerror``) when it is missing, not a regular file, or larger than fileio.MAX_INPUT.
    ``/dev/stdin`` and its kin are paths like any other there (a device, refused): a
    network file never reads this process's input."""
    return read_file(path, descriptors=False)


def wrong_kind(path: str, data: bytes) -> str | None:
    """Why ``data`` cannot be a node's file (NET011): it is a container, the JSON form of
    one, a concise DCF, or another kind dcf2bin knows, by its content; None for a device
    description (CiA 306 text or CiA 311 XML, and what only looks like none of them: its
    reader words that)."""
    from dcf2bin import filekind
    return filekind.mismatch(path, filekind.detect(data, path), (filekind.DCF, filekind.XDD),
                             use=_ADVICE)


def cia306(net, dev) -> tuple[bytes, object]:
    """(the CiA 306 text ``dev``'s configured DCF is made of, its ``ini.IniFile``): for
    CiA 306 text the file's own bytes (``net.files``) and the reading the Device was built
    from; for another format (CiA 311 XML) its sections written as CiA 306 text, UTF-8
    (``formats.ini.text``, what ``formats.load_with_text`` gives), read once per file and
    kept in ``net.texts``. The Device keeps the file's own lines for every finding."""
    parsed = dev.ini
    if parsed is None or parsed.format == "ini":
        data = net.files.get(dev.path)
        return (data if data is not None else read_file(dev.path)), parsed
    made = net.texts.get(dev.path)
    if made is None or made[2] is not parsed:
        from dcf2bin import ini as ini_mod
        from dcf2bin.formats import ini as ini_format
        text = ini_format.text(parsed).encode("utf-8")
        made = net.texts[dev.path] = (text, ini_mod.parse_bytes(text, dev.path), parsed)
    return made[0], made[1]

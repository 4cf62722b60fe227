"""Device descriptions in every format, read into the one neutral model.

``registry`` is the table of formats (name, suffixes, content test, module); each format
is one module here: ``ini`` (CiA 306 text: EDS, DCF), ``xdd`` (CiA 311 XML: XDD, XDC,
XPD). A reader turns a file into the per-object key/value sections CiA 306 defines, with
the file's own line numbers (``read``), and the model's builder makes the ``Device`` of
them (``build``), so that every command, rule and check reads every format alike.

    >>> from dcf2bin import formats
    >>> dev = formats.load("motor.xdc")                          # doctest: +SKIP
    >>> dev, text = formats.load_with_text("motor.xdc")          # doctest: +SKIP

Nothing here imports the model, lxml or click when this package is imported: the
functions import what their format needs when they run (``dcf2bin --help`` stays light).
"""
from __future__ import annotations

from dcf2bin.formats.registry import FORMATS, Format, by_name, by_suffix, sniff

__all__ = ["FORMATS", "TARGETS", "Format", "build", "by_name", "by_suffix", "convert", "dump",
           "format_of", "load", "load_with_text", "read", "sniff", "target_of"]

#: what ``dump`` writes: target name -> (format, kind of file)
TARGETS = {"eds": ("ini", "eds"), "dcf": ("ini", "dcf"), "xdd": ("xdd", "xdd"),
           "xdc": ("xdd", "xdc")}
_TARGET_SUFFIXES = {".eds": "eds", ".dcf": "dcf", ".xdd": "xdd", ".xpd": "xdd", ".xdc": "xdc"}


def format_of(data: bytes, path: str = "") -> Format:
    """The format ``data`` is read with: its content's, else the one its name's suffix
    says, else CiA 306 text (whose reader says what is wrong with an empty or binary file)."""
    import os
    from dcf2bin.formats import registry
    fmt = registry.sniff(data)
    if fmt is None:
        fmt = registry.by_suffix(os.path.splitext(path)[1])
    return fmt if fmt is not None and fmt.reads else registry.DEFAULT


def read(data: bytes, path: str):
    """The file's sections (``dcf2bin.ini.IniFile``), whatever its format; problems are
    collected in it, never raised."""
    return format_of(data, path).code().read(data, path)


def build(parsed, *, node_id: int | None = None, allow_external_files: bool = False):
    """The ``Device`` of sections ``read`` made: ``model.build``, plus what a format
    reader found beyond the sections (its problems tied to an object, its specifics)."""
    from dcf2bin import model
    dev = model.build(parsed, node_id=node_id, allow_external_files=allow_external_files)
    finish = getattr(parsed, "finish", None)
    if finish is not None:
        finish(dev)
    return dev


def load(path: str, *, node_id: int | None = None, allow_external_files: bool = False,
         data: bytes | None = None):
    """Read a device description in any format into a ``Device`` (``data``: its bytes,
    when the caller has them; else the file is read through ``fileio.read_file``, the
    bounded reader). Problems are collected in ``dev.problems``, never raised."""
    if data is None:
        from dcf2bin.fileio import read_file
        data = read_file(path)
    return build(read(data, path), node_id=node_id,
                 allow_external_files=allow_external_files)


def load_with_text(path: str, *, node_id: int | None = None, data: bytes | None = None):
    """(Device, CiA 306 text) of a description in any format: for code that edits a
    DCF's text (the network configurator writes a slave's configured DCF from it). The
    text of a DCF/EDS is the file itself (decoded); that of another format is its
    sections written as CiA 306 text, so its line numbers are not the file's: the
    Device's diagnostics point at the file."""
    from dcf2bin import ini as ini_mod
    from dcf2bin.formats import ini as ini_format
    if data is None:
        from dcf2bin.fileio import read_file
        data = read_file(path)
    parsed = read(data, path)
    dev = build(parsed, node_id=node_id)
    if parsed.format == "ini":
        return dev, ini_mod.decode_bytes(data)[0]
    return dev, ini_format.text(parsed)


def target_of(path: str) -> str | None:
    """The target a file name's suffix names ("eds", "dcf", "xdd", "xdc"), or None."""
    import os
    return _TARGET_SUFFIXES.get(os.path.splitext(path)[1].lower())


def dump(dev, target: str, *, name: str | None = None, node_id: int | None = None):
    """``dev`` written as ``target`` (a name of ``TARGETS``): a ``written.Written``, the
    bytes and a warning for each thing the target cannot say. ``name``: the written file's
    name (its [FileInfo] FileName, fileName); ``node_id``: the NodeID of a DCF/XDC."""
    fmt, kind = TARGETS[target]
    return by_name(fmt).code().dump(dev, kind, name=name, node_id=node_id)


def convert(data: bytes, path: str, target: str, *, name: str | None = None,
            node_id: int | None = None):
    """Read a description (``data``, named ``path``) and write it as ``target``: a
    ``written.Written`` whose diagnostics are the reader's findings, then the writer's
    warnings; ``ok`` is False (and nothing is written) when the reader found an error.
    ``node_id`` is the written NodeID, and it stands in for the file's own as compile's
    does (the builder's node_id): a NodeID the file gets wrong does not stop it."""
    from dcf2bin.diagnostics import Severity
    from dcf2bin.formats.written import Written, comment_lines
    dev = load(path, data=data, node_id=node_id)
    # The reader's note that the objects marked CO_disabled are left out of the model
    # (XDD020) is not what becomes of them in the output: a CiA 311 writer writes them
    # back with their property, and CiA 306 text leaves them out with its own warning
    # (CNV004). The writer says it, for its target.
    found = [p.diagnostic for p in dev.problems if p.diagnostic.rule != "XDD020"]
    if any(d.severity is Severity.ERROR for d in found):
        return Written(b"", found, ok=False)
    out = dump(dev, target, name=name, node_id=node_id)
    if dev.ini is not None and dev.ini.format == "ini":
        out.diagnostics[:0] = comment_lines(data, path)
    out.diagnostics[:0] = found
    return out

"""Exports of a device's object dictionary for other systems (SPEC §7), one module each:

* ``lenze``: Lenze PLC Designer master OD (``CanOpenODEntry`` records), as IEC 61131-3
  structured text or packed little-endian binary;
* ``port``: a C source for the port CANopen Library (``LIST_ELEMENT_T`` / ``VALUE_DESC_T``);
* ``markdown`` and ``html``: the documentation of the object dictionary (one page, two
  renderings);
* ``canopennode``: ``OD.h`` and ``OD.c`` for CANopenNode v4's object dictionary interface.

All export every object from 0x1000 up (objects below 0x1000 are data type definitions).
Model errors that touch an exported object stop the export; values that cannot be encoded
are one-line ``file:line`` errors.
"""
from __future__ import annotations

from dcf2bin.diagnostics import shorten
# re-exported: the names every format module and test used from here before common.py
from dcf2bin.export.common import (FIRST_INDEX, FORMATS, ExportResult, ascii_text,  # noqa: F401
                                   encode, error, exported_objects, model_diagnostics,
                                   warning)


def run(fmt: str, path: str, *, data: bytes | None = None, node_id: int | None = None,
        allow_external_files: bool = False, **options) -> ExportResult:
    """Load ``path`` (or ``data``) and export it in ``fmt`` (one of FORMATS)."""
    from dcf2bin import formats
    if data is None:
        from dcf2bin.fileio import read_file
        data = read_file(path)
    dev = formats.load(path, node_id=node_id, allow_external_files=allow_external_files,
                       data=data)
    return export_device(fmt, dev, source=data, **options)


def export_device(fmt: str, dev, *, source: bytes | None = None, **options) -> ExportResult:
    """Export ``dev`` in ``fmt``; ``source`` (the file's bytes) gives the CANopenNode
    settings an EDS states in comment lines, which the model does not keep."""
    if fmt in ("lenze-st", "lenze-bin"):
        from dcf2bin.export import lenze
        return lenze.export(dev, binary=(fmt == "lenze-bin"), **options)
    if fmt == "port-c":
        from dcf2bin.export import port
        return port.export(dev, **options)
    if fmt == "markdown":
        from dcf2bin.export import markdown
        return markdown.export(dev, source=source, **options)
    if fmt == "html":
        from dcf2bin.export import html
        return html.export(dev, source=source, **options)
    if fmt == "canopennode":
        from dcf2bin.export import canopennode
        return canopennode.export(dev, source=source, **options)
    raise ValueError(f"unknown export format '{shorten(fmt)}' (known: {', '.join(FORMATS)})")

"""Exports of a device's object dictionary for other systems (SPEC §7).

* ``lenze``: Lenze PLC Designer master OD (``CanOpenODEntry`` records), as IEC 61131-3
  structured text or packed little-endian binary;
* ``port``: a C source for the port CANopen Library (``LIST_ELEMENT_T`` / ``VALUE_DESC_T``).

Both export every entry of every object from 0x1000 up (objects below 0x1000 are data
type definitions), with the entry's value as SPEC §1 defines it (ParameterValue, else
DownloadFile, else DefaultValue, else the type's zero). Model errors that touch an exported
object stop the export; values that cannot be encoded are one-line ``file:line`` errors.
"""
from __future__ import annotations
# re-exported: the names every format module and test used from here before common.py
from dcf2bin.export.common import (FIRST_INDEX, FORMATS, ExportResult, ascii_text,  # noqa: F401
                                   encode, error, exported_objects, model_diagnostics,
                                   warning)


def run(fmt: str, path: str, *, data: bytes | None = None, node_id: int | None = None,
        allow_external_files: bool = False, **options) -> ExportResult:
    """Load ``path`` (or ``data``) and export it in ``fmt`` (one of FORMATS)."""
    from dcf2bin import formats
    dev = formats.load(path, node_id=node_id, allow_external_files=allow_external_files,
                       data=data)
    return export_device(fmt, dev, **options)


def export_device(fmt: str, dev, **options) -> ExportResult:
    if fmt in ("lenze-st", "lenze-bin"):
        from dcf2bin.export import lenze
        return lenze.export(dev, binary=(fmt == "lenze-bin"), **options)
    if fmt == "port-c":
        from dcf2bin.export import port
        return port.export(dev, **options)
    raise ValueError(f"unknown export format '{fmt}' (known: {', '.join(FORMATS)})")

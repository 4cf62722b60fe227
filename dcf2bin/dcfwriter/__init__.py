"""Container -> DCF text: ``bin2dcf`` (SPEC.md §4).

One object section per index; ``ParameterValue`` is the last value written to each
(index, subindex) and comments list the earlier writes (PDO reconfiguration
sequences). DataType: from the CiA 405 range for network variables; else from the
attribute bits and the size (BOOLEAN, VISIBLE_STRING, NUMERIC 1..8 bytes ->
UNSIGNED8..64, no type bit -> DOMAIN); AccessType and PDOMapping from the attribute.
With an EDS (``--eds``) types, access and names come from it where they agree with
what the container stores.

The output is chosen so that ``compile`` with default options gives the same bytes
for every container compiled with default options from a DCF: network-variable
objects are ARRAYs (creation group, sub 0 first), other written entries keep their
access so the configuration group selects them again, PDO objects carry the final
COB-ID and mapping so compile regenerates the CiA 301 block, and a
``[DynamicChannels]`` section is reconstructed from the PI addresses when the
variables do not sit where the CiA 405 table puts them.

The work is done in three steps, one module each:

* ``reader`` reads the container into per-index facts (a ``spec.DcfSpec``), with
  ``entries`` typing each entry from its range, its attribute byte or the EDS;
* ``text`` writes those objects as DCF text;
* ``roundtrip`` replays the rules of SPEC §3 on them and warns where compile would
  not give the container's bytes back.

A CiA 302-3 concise DCF (what ``network build`` writes for a slave) is turned into a DCF by
``convert_concise`` the same way: its entries have no attribute, so their types come from
the EDS, CiA 301 or the size (``dump.entry_type``), and no round trip is promised (a DCF
holds one value per entry, not the order of the writes).

    >>> from dcf2bin import dump, dcfwriter
    >>> c, _ = dump.read_bytes(open("samples/plc.bin", "rb").read(), "plc.bin")
    >>> res = dcfwriter.convert(c, "plc.bin", dcf_name="plc.dcf")
    >>> res.roundtrip, res.diagnostics
    (True, [])
"""
from __future__ import annotations

from dataclasses import dataclass

from dcf2bin.container import BinContainer
from dcf2bin.dcfwriter.roundtrip import mark_old_cob_ids, predict
from dcf2bin.dcfwriter.reader import read_spec
from dcf2bin.dcfwriter.spec import (R_ATTR, R_EDS, R_HEADER, R_PDO, R_PI, R_REPEAT, R_SELECT,
                                    R_SUMMARY, R_VALUE, table_type)
from dcf2bin.dcfwriter.text import render
from dcf2bin.diagnostics import Diagnostic
from dcf2bin.dump import EdsInfo


@dataclass
class Result:
    text: str
    diagnostics: list[Diagnostic]
    roundtrip: bool        # compile(text) with default options == the container
    options: list[str]     # compile options that would give the same bytes, when not default
    encoding: str = "utf-8"

    def to_bytes(self) -> bytes:
        """The DCF in its encoding (Latin-1 only when a string needs it; SPEC §1)."""
        return self.text.encode(self.encoding, errors="replace")


def convert_concise(entries, name: str, *, dcf_name: str, eds: EdsInfo | None = None,
                    eds_device=None) -> Result:
    """A concise DCF's entries as DCF text: ``ParameterValue`` the last value written to
    each entry, earlier writes as comments; the types from the EDS, CiA 301 or the size
    (``dump.entry_type``). A DCF holds no order of writes, so it is not meant to give the
    concise DCF's bytes back (``roundtrip`` is False)."""
    spec = read_spec(BinContainer(entries=list(entries)), name, eds, what="concise DCF")
    text = render(spec, dcf_name, eds_device)
    return Result(text, spec.issues.diagnostics(), False, [], spec.encoding)


def convert(c: BinContainer, name: str, *, dcf_name: str, eds: EdsInfo | None = None,
            eds_device=None) -> Result:
    """A container as DCF text, with warnings where compile would not give the same bytes.

    ``name`` names the container in the warnings, ``dcf_name`` goes into
    ``[FileInfo] FileName``; ``eds``/``eds_device`` come from ``dump.load_eds``.
    """
    spec = read_spec(c, name, eds)
    marked = mark_old_cob_ids(spec)
    roundtrip, options = predict(spec)
    if "--profile dis2" not in options:
        for s in marked:   # not a DIS-2 block after all: no DefaultValue of our making
            s.default = ""
    text = render(spec, dcf_name, eds_device, options)
    return Result(text, spec.issues.diagnostics(), roundtrip, options, spec.encoding)


__all__ = ["Result", "convert", "convert_concise", "table_type", "R_HEADER", "R_ATTR",
           "R_REPEAT", "R_SELECT", "R_PDO", "R_PI", "R_VALUE", "R_EDS", "R_SUMMARY"]

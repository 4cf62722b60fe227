"""The identity a description states beside its identity object 0x1018: [DeviceInfo]
VendorNumber, ProductNumber and RevisionNumber (0x1018 sub 1-3) and [DeviceComissioning]
LSS_SerialNumber (sub 4).

A device holds its identity whether or not its EDS gives 0x1018 a value, and an EDS often
gives it in [DeviceInfo] only. Where the file gives such an entry no value, this is the
value the device holds: the software node answers it (``bus.node``) and ``diff`` compares
it (``compare.readers``) -- one rule, so that a file and the node made of it agree (issue
29: a build's DCF against the DCF uploaded from the node).

Only what reads as an UNSIGNED32 counts: a key that is no integer, or out of range, is not
an identity (never guessed, never cut to 32 bits). Data only: it reads an ``ini.IniFile``.
"""
from __future__ import annotations

from dataclasses import dataclass

from dcf2bin import values

# 0x1018 sub -> (section, key as the file writes it)
SOURCES = {1: ("DeviceInfo", "VendorNumber"),
           2: ("DeviceInfo", "ProductNumber"),
           3: ("DeviceInfo", "RevisionNumber"),
           4: ("DeviceComissioning", "LSS_SerialNumber")}


@dataclass(frozen=True, slots=True)
class Stated:
    """One identity value the file states outside 0x1018: the number, the key that gives
    it (``[DeviceInfo] ProductNumber``) and that key's line."""
    value: int
    key: str
    line: int | None = None


def stated_identity(ini) -> dict[int, Stated]:
    """0x1018 sub -> what ``ini`` (an ``ini.IniFile``, or None) states of it outside the
    object, for the subs whose key reads as an UNSIGNED32. [DeviceComissioning] is also
    read as [DeviceCommissioning] (the spelling CiA 306 does not use), the first winning
    as for NodeID."""
    out: dict[int, Stated] = {}
    if ini is None:
        return out
    for sub, (section, key) in SOURCES.items():
        sec = ini.section(section.lower())
        if sec is None and section == "DeviceComissioning":
            sec = ini.section("devicecommissioning")
        text = sec.get(key.lower()) if sec is not None else None
        if text is None:
            continue
        try:
            number = values.parse_int(values.split_numeric_comment(text)[0])
        except values.ValueProblem:
            continue
        if 0 <= number <= 0xFFFFFFFF:
            out[sub] = Stated(number, f"[{section}] {key}", sec.line_of(key.lower()))
    return out

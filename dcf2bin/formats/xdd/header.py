"""The sections about the file and the device, from a CiA 311 file's header elements:
[FileInfo] from the device profile's ``ProfileBody`` attributes, [DeviceInfo] from
``DeviceIdentity``, the supported baud rates and the network management features,
[DummyUsage] from ``dummyUsage``, and [DeviceComissioning] from an XDC's
``deviceCommissioning`` (what a DCF's section of that name says).
"""
from __future__ import annotations

import re

from dcf2bin.formats.xdd.document import add, section
from dcf2bin.formats.xdd.vocabulary import BAUD_RATES

_FILE_INFO = (("fileName", "FileName"), ("fileVersion", "FileVersion"),
              ("fileCreator", "CreatedBy"), ("fileCreationDate", "CreationDate"),
              ("fileCreationTime", "CreationTime"), ("fileModifiedBy", "ModifiedBy"),
              ("fileModificationDate", "ModificationDate"),
              ("fileModificationTime", "ModificationTime"))
_IDENTITY = (("vendorName", "VendorName", False), ("vendorID", "VendorNumber", True),
             ("productName", "ProductName", False), ("productID", "ProductNumber", True),
             ("revisionNumber", "RevisionNumber", True), ("orderNumber", "OrderCode", False))
_GENERAL = (("bootUpSlave", "SimpleBootUpSlave"), ("granularity", "Granularity"),
            ("dynamicChannels", "DynamicChannelsSupported"),
            ("groupMessaging", "GroupMessaging"), ("nrOfRxPDO", "NrOfRXPDO"),
            ("nrOfTxPDO", "NrOfTXPDO"), ("layerSettingServiceSlave", "LSS_Supported"),
            ("ngSlave", "NG_Slave"), ("ngMaster", "NG_Master"),
            ("NrOfNG_MonitoredNodes", "NrOfNG_MonitoredNodes"))
_MASTER = (("bootUpMaster", "SimpleBootUpMaster"),)
_COMMISSIONING = (("nodeID", "NodeID"), ("nodeName", "NodeName"),
                  ("actualBaudRate", "Baudrate"), ("networkNumber", "NetNumber"),
                  ("networkName", "NetworkName"), ("CANopenManager", "CANopenManager"),
                  ("LSS_SerialNumber", "LSS_SerialNumber"))
_DATE = re.compile(r"(\d{4})-(\d{2})-(\d{2})")
_TIME = re.compile(r"(\d{2}):(\d{2})")
_KBPS = re.compile(r"(\d+)\s*[Kk]bps")


def file_info(body):
    """[FileInfo] from a ProfileBody's attributes (dates and times in CiA 306's forms)."""
    sec = section("FileInfo", body.sourceline)
    for attr, key in _FILE_INFO:
        value = body.get(attr)
        if value is None:
            continue
        if key.endswith("Date") and (m := _DATE.fullmatch(value.strip())):
            value = f"{m.group(2)}-{m.group(3)}-{m.group(1)}"          # MM-DD-YYYY
        elif key.endswith("Time") and (m := _TIME.match(value.strip())):
            hour, minute = int(m.group(1)), m.group(2)
            value = f"{(hour + 11) % 12 + 1:02d}:{minute}{'AM' if hour < 12 else 'PM'}"
        add(sec, key, value, body.sourceline)
    return sec


def device_info(identity, bauds, general, master):
    """[DeviceInfo]; None when the file has none of its elements."""
    line = next((e.sourceline for e in (identity, general, master) if e is not None),
                bauds[0].sourceline if bauds else None)
    if line is None:
        return None
    sec = section("DeviceInfo", line)
    for child in identity if identity is not None else ():
        for name, key, number in _IDENTITY:
            if child.tag.__class__ is str and child.tag.rpartition("}")[2] == name:
                text = (child.text or "").strip()
                add(sec, key, _number(text) if number else text, child.sourceline)
    if bauds:
        rates = {b.get("value", "").strip(): b.sourceline for b in bauds}
        for value, key in BAUD_RATES.items():
            add(sec, key, "1" if value in rates else "0", rates.get(value, bauds[0].sourceline))
    for el, attrs in ((general, _GENERAL), (master, _MASTER)):
        if el is None:
            continue
        for attr, key in attrs:
            value = el.get(attr)
            if value is not None:
                add(sec, key, _flag(value), el.sourceline)
    return sec


def dummy_usage(dummies):
    """[DummyUsage] from ``<dummy entry="Dummy0001=0"/>``; None without them."""
    if not dummies:
        return None
    sec = section("DummyUsage", dummies[0].getparent().sourceline)
    for d in dummies:
        key, eq, value = d.get("entry", "").partition("=")
        if eq and key.strip():
            add(sec, key.strip(), value.strip(), d.sourceline)
    return sec


def commissioning(el):
    """[DeviceComissioning] (CiA 306's spelling) from an XDC's deviceCommissioning."""
    if el is None:
        return None
    sec = section("DeviceComissioning", el.sourceline)
    for attr, key in _COMMISSIONING:
        value = el.get(attr)
        if value is None:
            continue
        if key == "Baudrate" and (m := _KBPS.fullmatch(value.strip())):
            value = m.group(1)                         # "500 Kbps" -> 500 (kbit/s)
        add(sec, key, _flag(value), el.sourceline)
    return sec


def _flag(value: str) -> str:
    """XML Schema's booleans as CiA 306's 0/1; other values as written."""
    return {"true": "1", "false": "0"}.get(value.strip(), value.strip())


def _number(text: str) -> str:
    """A vendor or product ID as CiA 306 reads it: CiA 311 writes them as decimal
    ("327") or as 8 hex digits ("00000147"), which CiA 306 would read as octal."""
    if len(text) == 8 and text[0] == "0" and all(c in "0123456789abcdefABCDEF" for c in text):
        return "0x" + text
    return text


def object_lists(sections: dict, line: int) -> dict:
    """[MandatoryObjects], [OptionalObjects] and [ManufacturerObjects], worked out from the
    objects read (a CiA 311 file has no such lists; CiA 306 has them): canonical name ->
    section, each key at its object's line, the sections at the object list's."""
    groups: dict[str, list] = {"MandatoryObjects": [], "OptionalObjects": [],
                               "ManufacturerObjects": []}
    for canon, sec in sections.items():
        if len(canon) != 4 or canon.strip("0123456789abcdef"):
            continue
        idx = int(canon, 16)
        kind = ("MandatoryObjects" if idx in (0x1000, 0x1001, 0x1018) else
                "ManufacturerObjects" if 0x2000 <= idx <= 0x5FFF else "OptionalObjects")
        groups[kind].append((idx, sec.line))
    out = {}
    for name, objects in groups.items():
        sec = section(name, line)
        add(sec, "SupportedObjects", str(len(objects)), line)
        for n, (idx, at) in enumerate(sorted(objects), 1):
            add(sec, str(n), f"0x{idx:04X}", at)
        out[name.lower()] = sec
    return out

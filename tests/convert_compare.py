"""One comparison of two device models, field by field (issue 28's round trips): every
object, every entry and every attribute, the header values the model uses, and the
format specifics both sides can hold. Returns the differences as readable lines, so a
failing test says what differs and where."""
from __future__ import annotations

import re

from dcf2bin import values

OBJECT_FIELDS = ("name", "object_type", "sub_number", "compact", "complex")
ENTRY_FIELDS = ("name", "dtype", "access", "pdo_mapping", "obj_flags", "default", "param",
                "download_file", "low", "high", "denotation", "implicit")
# [DeviceInfo]/[DeviceComissioning] keys compared as numbers; a missing flag is 0
NUMBERS = {"vendornumber", "productnumber", "revisionnumber", "granularity", "nrofrxpdo",
           "nroftxpdo", "nrofng_monitorednodes", "dynamicchannelssupported", "nodeid",
           "baudrate", "netnumber", "lss_serialnumber"}
FLAGS = {"simplebootupmaster", "simplebootupslave", "groupmessaging", "lss_supported",
         "ng_slave", "ng_master", "compactpdo", "canopenmanager"} | {
    f"baudrate_{r}" for r in (10, 20, 50, 125, 250, 500, 800, 1000)}


def differences(a, b, *, skip_objects=(), skip_fields=(), headers=("deviceinfo",
                "dummyusage", "devicecomissioning", "fileinfo"), specifics=True) -> list[str]:
    """What differs between Devices ``a`` and ``b``: [] when they are the same model.
    ``skip_fields``: (object or entry field) names not compared (what a conversion warned
    it cannot keep, as "compact")."""
    out: list[str] = []
    ia, ib = set(a.objects) - set(skip_objects), set(b.objects) - set(skip_objects)
    for idx in sorted(ia ^ ib):
        out.append(f"0x{idx:04X}: only in {'the first' if idx in ia else 'the second'}")
    for idx in sorted(ia & ib):
        oa, ob = a.objects[idx], b.objects[idx]
        for f in OBJECT_FIELDS:
            if f not in skip_fields and getattr(oa, f) != getattr(ob, f):
                out.append(f"0x{idx:04X} {f}: {getattr(oa, f)!r} != {getattr(ob, f)!r}")
        for sub in sorted(set(oa.entries) ^ set(ob.entries)):
            out.append(f"0x{idx:04X}sub{sub:X}: only in "
                       f"{'the first' if sub in oa.entries else 'the second'}")
        for sub in sorted(set(oa.entries) & set(ob.entries)):
            ea, eb = oa.entries[sub], ob.entries[sub]
            for f in ENTRY_FIELDS:
                if f not in skip_fields and getattr(ea, f) != getattr(eb, f):
                    out.append(f"0x{idx:04X}sub{sub:X} {f}: {getattr(ea, f)!r} != "
                               f"{getattr(eb, f)!r}")
    for f in ("node_id", "dummy_usage"):
        if f not in skip_fields and getattr(a, f) != getattr(b, f):
            out.append(f"{f}: {getattr(a, f)!r} != {getattr(b, f)!r}")
    for name in headers:
        ha, hb = _header(a, name), _header(b, name)
        for key in sorted(set(ha) | set(hb)):
            if (name, key) in skip_fields or key in skip_fields:
                continue
            va, vb = ha.get(key), hb.get(key)
            if not _same(key, va, vb):
                out.append(f"[{name}] {key}: {va!r} != {vb!r}")
    if specifics:
        sa, sb = _specifics(a), _specifics(b)
        for key in sorted(set(sa) | set(sb), key=lambda k: (k[0], -1 if k[1] is None else k[1])):
            if key[0] in skip_objects:
                continue
            if sa.get(key, {}) != sb.get(key, {}):
                out.append(f"specifics {key}: {sa.get(key)!r} != {sb.get(key)!r}")
    return out


def _header(dev, name: str) -> dict:
    sec = dev.ini.section(name) if dev.ini is not None else None
    if sec is None and name == "devicecomissioning":
        sec = dev.ini.section("devicecommissioning") if dev.ini is not None else None
    return dict(sec.values) if sec is not None else {}


def _same(key: str, a, b) -> bool:
    a, b = a or None, b or None         # an empty value says nothing
    if key in FLAGS:
        a, b = a or "0", b or "0"
    if a == b:
        return True
    if a is None or b is None:
        return False
    if key.endswith("time"):        # 2:07AM, 02:07PM, 14:07, 14:07:00: times of day
        return _minutes(a) is not None and _minutes(a) == _minutes(b)
    if key.endswith("date"):        # 03-11-2024 and 2024-03-11
        return _date(a) is not None and _date(a) == _date(b)
    if key in NUMBERS or key in FLAGS or key.startswith("dummy"):
        try:
            return values.parse_int(a.strip()) == values.parse_int(b.strip())
        except values.ValueProblem:
            return False
    return False


def _minutes(text: str):
    m = re.fullmatch(r"\s*(\d{1,2}):(\d{2})(?::\d{2}(?:\.\d+)?)?\s*(?:([AaPp])[Mm])?\s*", text)
    if m is None:
        return None
    hour = int(m.group(1))
    if m.group(3):
        hour = hour % 12 + (12 if m.group(3) in "Pp" else 0)
    return hour * 60 + int(m.group(2))


def _date(text: str):
    m = re.fullmatch(r"\s*(\d{2})-(\d{2})-(\d{4})\s*", text)
    if m is not None:
        return m.group(3), m.group(1), m.group(2)
    m = re.fullmatch(r"\s*(\d{4})-(\d{2})-(\d{2})\s*", text)
    return m.groups() if m is not None else None


def _specifics(dev) -> dict:
    """The specifics, without a description that is only the entry's name (a CiA 311
    label, which the reader takes as the description when there is no other)."""
    out = {}
    for (idx, sub), spec in dev.specifics.items():
        e = dev.entry(idx, 0 if sub is None else sub)
        kept = {k: v for k, v in spec.items()
                if not (k == "description" and e is not None and v == e.name)}
        if kept:
            out[(idx, sub)] = kept
    return out

"""DCF1xx: the object dictionary as a whole (CiA 301 / CiA 306)."""
from __future__ import annotations

from dcf2bin import datatypes as dt
from dcf2bin import values
from dcf2bin.diagnostics import shorten
from dcf2bin.lint import tables
from dcf2bin.lint.registry import ERROR, WARNING, Finding, rule
from dcf2bin.model import is_pdo_mapping

MANDATORY = {0x1000: "Device type", 0x1001: "Error register", 0x1018: "Identity object"}
_LISTS = (("mandatoryobjects", "MandatoryObjects"), ("optionalobjects", "OptionalObjects"),
          ("manufacturerobjects", "ManufacturerObjects"))


def _is_manufacturer(index: int) -> bool:
    return 0x2000 <= index <= 0x5FFF


def _int(text: str | None) -> int | None:
    if text is None:
        return None
    try:
        return values.parse_int(values.split_numeric_comment(text)[0])
    except values.ValueProblem:
        return None


class _Lists:
    """The three object lists, parsed once per file."""

    def __init__(self, ctx):
        self.sections = {}          # canon -> Section
        self.entries = []           # (list canon, number, index or None, line)
        self.first: dict[int, tuple[str, int]] = {}   # index -> (list canon, line)
        for canon, _ in _LISTS:
            sec = ctx.section(canon)
            if sec is None:
                continue
            self.sections[canon] = sec
            numbered = sorted((int(k), k) for k in ctx.key_names(sec)
                              if k.isdigit() and k.isascii() and len(k) < 20)
            for number, key in numbered:
                line = sec.line_of(key)
                idx = _int(sec.get(key))
                self.entries.append((canon, number, idx, line))
                if idx is not None and idx not in self.first:
                    self.first[idx] = (canon, line)


def _lists(ctx) -> _Lists:
    lists = ctx.cache.get("lists")
    if lists is None:
        lists = ctx.cache["lists"] = _Lists(ctx)
    return lists


def _n(count: int, noun: str) -> str:
    if count == 1:
        return f"1 {noun}"
    return f"{count} {noun[:-1] + 'ies' if noun.endswith('y') else noun + 's'}"


def _shown(canon: str) -> str:
    return dict(_LISTS)[canon]


@rule("DCF101", "mandatory-object-missing", ERROR,
      "Object 0x1000, 0x1001 or 0x1018, mandatory for every CANopen device (CiA 301), "
      "is missing.",
      hint="add the object section")
def mandatory_missing(ctx):
    if not ctx.ini.sections:
        return  # DCF056
    lists = _lists(ctx)
    for idx, name in MANDATORY.items():
        if idx not in ctx.dev.objects:
            listed = lists.first.get(idx)
            if listed:
                yield Finding(f"mandatory object 0x{idx:04X} ({name}) is listed in "
                              f"[{_shown(listed[0])}] but has no section [{idx:04X}]", listed[1])
            else:
                yield Finding(f"mandatory object 0x{idx:04X} ({name}) is missing", None)


@rule("DCF102", "listed-object-missing", ERROR,
      "An object list ([MandatoryObjects], [OptionalObjects], [ManufacturerObjects]) names "
      "an object that has no section.",
      hint="add the object's section or remove it from the list")
def listed_missing(ctx):
    for canon, number, idx, line in _lists(ctx).entries:
        if idx is None or idx in ctx.dev.objects or idx in MANDATORY:
            continue
        yield Finding(f"[{_shown(canon)}] {number}=0x{idx:04X} has no section [{idx:04X}]",
                      line, ctx.value_column(line))


@rule("DCF103", "object-not-listed", WARNING,
      "An object section is not named in any object list.",
      hint="add it to [OptionalObjects] (or [ManufacturerObjects] for 0x2000-0x5FFF)")
def not_listed(ctx):
    lists = _lists(ctx)
    have_std = "mandatoryobjects" in lists.sections or "optionalobjects" in lists.sections
    have_mfr = "manufacturerobjects" in lists.sections
    for idx in sorted(ctx.dev.objects):
        obj = ctx.dev.objects[idx]
        if idx < 0x1000 or obj.implicit or idx in lists.first:
            continue
        if not (have_mfr if _is_manufacturer(idx) else have_std):
            continue  # DCF108 names the missing list once
        yield Finding(f"object 0x{idx:04X} is not listed in any object list",
                      obj.where.line if obj.where else None)


@rule("DCF104", "object-list-count", WARNING,
      "SupportedObjects of an object list differs from the number of its entries.",
      hint="SupportedObjects= counts the numbered entries 1..N")
def list_count(ctx):
    lists = _lists(ctx)
    for canon, sec in lists.sections.items():
        n = sum(1 for e in lists.entries if e[0] == canon)
        text = sec.get("supportedobjects")
        if text is None:
            yield Finding(f"[{shorten(sec.name)}] has no SupportedObjects (it has "
                          f"{_n(n, 'entry')})",
                          sec.line)
            continue
        count = _int(text)
        if count is not None and count != n:
            line = sec.line_of("supportedobjects")
            yield Finding(f"[{shorten(sec.name)}] SupportedObjects={count} but it has "
                          f"{_n(n, 'entry')}",
                          line, ctx.value_column(line))


@rule("DCF105", "object-list-gap", WARNING,
      "The entries of an object list are not numbered 1, 2, 3, ... without gaps.",
      hint="number the entries 1..N; tools stop reading at the first gap")
def list_gap(ctx):
    lists = _lists(ctx)
    for canon, sec in lists.sections.items():
        numbers = [e[1] for e in lists.entries if e[0] == canon]
        if numbers != list(range(1, len(numbers) + 1)):
            expected = set(range(1, len(numbers) + 1))
            missing = sorted(expected - set(numbers))
            shown = ", ".join(str(m) for m in missing[:5]) + (", ..." if len(missing) > 5 else "")
            yield Finding(f"[{shorten(sec.name)}] entries are not numbered 1..{len(numbers)} "
                          f"(missing {shown})", sec.line)


@rule("DCF106", "object-in-wrong-list", WARNING,
      "A manufacturer object (0x2000-0x5FFF) is listed outside [ManufacturerObjects], or "
      "another object inside it.",
      hint="0x2000-0x5FFF belong in [ManufacturerObjects], all others in "
           "[MandatoryObjects]/[OptionalObjects]")
def wrong_list(ctx):
    for canon, number, idx, line in _lists(ctx).entries:
        if idx is None:
            continue
        mfr = canon == "manufacturerobjects"
        if mfr != _is_manufacturer(idx):
            where = "only 0x2000-0x5FFF belong there" if mfr else \
                "manufacturer objects belong in [ManufacturerObjects]"
            yield Finding(f"0x{idx:04X} is listed in [{_shown(canon)}]; {where}", line,
                          ctx.value_column(line))


@rule("DCF107", "object-listed-twice", WARNING,
      "An object is named twice in the object lists.",
      hint="list every object once")
def listed_twice(ctx):
    lists = _lists(ctx)
    for canon, number, idx, line in lists.entries:
        if idx is None:
            continue
        first_canon, first_line = lists.first[idx]
        if first_line != line or first_canon != canon:
            yield Finding(f"0x{idx:04X} is listed again (first in [{_shown(first_canon)}] at "
                          f"line {first_line})", line, ctx.value_column(line))


@rule("DCF108", "object-list-missing", WARNING,
      "[MandatoryObjects] is missing, or objects exist whose list section "
      "([OptionalObjects]/[ManufacturerObjects]) is missing.",
      hint="CiA 306 tools read the object lists to find the objects")
def list_missing(ctx):
    lists = _lists(ctx)
    objs = [i for i, o in ctx.dev.objects.items() if i >= 0x1000 and not o.implicit]
    if not ctx.ini.sections:
        return
    if "mandatoryobjects" not in lists.sections:
        yield Finding("[MandatoryObjects] is missing", None)
    std = [i for i in objs if not _is_manufacturer(i) and i not in lists.first]
    if std and "optionalobjects" not in lists.sections and any(i not in MANDATORY for i in std):
        yield Finding(f"[OptionalObjects] is missing, {_n(len(std), 'object')} not listed", None)
    mfr = [i for i in objs if _is_manufacturer(i) and i not in lists.first]
    if mfr and "manufacturerobjects" not in lists.sections:
        yield Finding(f"[ManufacturerObjects] is missing, {_n(len(mfr), 'object')} not listed",
                      None)


@rule("DCF110", "subnumber-mismatch", WARNING,
      "SubNumber differs from the number of [<index>subN] sections of the object.",
      hint="SubNumber counts the sub-sections, sub 0 included")
def subnumber_mismatch(ctx):
    counts = tables.sub_counts(ctx)
    for idx, obj in ctx.dev.objects.items():
        sec = obj.section
        if sec is None or obj.implicit or obj.compact:
            continue
        n = counts.get(idx, 0)
        text = sec.get("subnumber")
        if text is None:
            if n:
                yield Finding(f"[{shorten(sec.name)}] has {n} sub-sections but no "
                              "SubNumber", sec.line)
            continue
        count = _int(text)
        if count is not None and count != n:
            line = sec.line_of("subnumber")
            yield Finding(f"[{shorten(sec.name)}] SubNumber={count} but {n} sub-sections are "
                          "present",
                          line, ctx.value_column(line))


@rule("DCF111", "compact-with-subnumber", WARNING,
      "An object gives both CompactSubObj and SubNumber.",
      hint="a CompactSubObj object has no SubNumber (its sub-objects are implied)")
def compact_with_subnumber(ctx):
    for obj in ctx.dev.objects.values():
        sec = obj.section
        if sec is None or not obj.compact:
            continue
        n = _int(sec.get("subnumber"))
        if n:
            line = sec.line_of("subnumber")
            yield Finding(f"[{shorten(sec.name)}] has CompactSubObj={obj.compact} and "
                          f"SubNumber={n}",
                          line, ctx.value_column(line))


@rule("DCF112", "sub0-not-unsigned8", ERROR,
      "Sub 0 of an ARRAY/RECORD (the number of sub-entries) is not UNSIGNED8.",
      hint="set DataType=0x0005 for sub 0")
def sub0_type(ctx):
    for obj in ctx.dev.objects.values():
        if not obj.complex:
            continue
        e = obj.entries.get(0)
        if e is None or e.implicit or e.dtype is None or e.dtype.code == dt.UNSIGNED8.code:
            continue
        line = e.key_where("datatype").line
        yield Finding(f"{e.label} has DataType {e.dtype.name}; sub 0 is UNSIGNED8", line,
                      ctx.value_column(line))


@rule("DCF113", "sub0-not-highest", WARNING,
      "The value of a read-only sub 0 differs from the highest subindex present.",
      hint="sub 0 holds the highest subindex supported; the given value is used as is")
def sub0_highest(ctx):
    for idx, obj in ctx.dev.objects.items():
        if not obj.complex or is_pdo_mapping(idx):
            continue
        e = obj.entries.get(0)
        if e is None or e.implicit or e.access not in ("ro", "const"):
            continue
        value, nodeid = ctx.int_value(e)
        if value is None or nodeid:
            continue
        highest = max(obj.entries)
        if value != highest:
            line = e.value_where.line
            yield Finding(f"{e.label} is {value} but the highest subindex present is {highest}",
                          line, ctx.value_column(line))


@rule("DCF114", "missing-parameter-name", WARNING,
      "An object or sub-object section has no ParameterName.",
      hint="every object and sub-object section names itself with ParameterName=")
def missing_name(ctx):
    nameless = tables.nameless(ctx)     # kind -> ids of the sections without one
    every = set().union(*nameless.values())
    subs = nameless.get("sub")          # usually none: then the sub-sections are not walked
    for idx, obj in ctx.dev.objects.items():
        if obj.section is not None and id(obj.section) in every:
            yield Finding(f"[{shorten(obj.section.name)}] has no ParameterName", obj.section.line)
        for sub, sec in sorted(ctx.sub_sections.get(idx, {}).items()) if subs else ():
            if id(sec) in subs:
                yield Finding(f"[{shorten(sec.name)}] has no ParameterName", sec.line)


_IDENTITY = (("vendornumber", 1, "VendorNumber"), ("productnumber", 2, "ProductNumber"),
             ("revisionnumber", 3, "RevisionNumber"))


@rule("DCF120", "identity-mismatch", WARNING,
      "[DeviceInfo] VendorNumber/ProductNumber/RevisionNumber differs from 0x1018 sub 1/2/3.",
      hint="the identity object and [DeviceInfo] must describe the same device")
def identity_mismatch(ctx):
    info = ctx.section("deviceinfo")
    if info is None:
        return
    for key, sub, shown in _IDENTITY:
        expected = _int(info.get(key))
        e = ctx.dev.entry(0x1018, sub)
        if expected is None or e is None or e.implicit:
            continue
        value, nodeid = ctx.int_value(e)
        if value is None or nodeid or value == expected:
            continue
        line = e.value_where.line
        yield Finding(f"{e.label} is 0x{value:08X} but [DeviceInfo] {shown}=0x{expected:08X} "
                      f"(line {info.line_of(key)})", line, ctx.value_column(line))


@rule("DCF121", "pdo-count-mismatch", WARNING,
      "[DeviceInfo] NrOfRXPDO/NrOfTXPDO differs from the PDO communication objects present.",
      hint="NrOfRXPDO counts 0x1400.., NrOfTXPDO counts 0x1800..")
def pdo_count(ctx):
    info = ctx.section("deviceinfo")
    if info is None:
        return
    for key, shown, base in (("nrofrxpdo", "NrOfRXPDO", 0x1400), ("nroftxpdo", "NrOfTXPDO",
                                                                   0x1800)):
        n = _int(info.get(key))
        if n is None:
            continue
        present = sum(1 for i in ctx.dev.objects if base <= i < base + 0x200)
        if n != present:
            kind = "RPDO" if base == 0x1400 else "TPDO"
            line = info.line_of(key)
            yield Finding(f"[DeviceInfo] {shown}={n} but {_n(present, kind)} (communication "
                          f"objects 0x{base:04X}-0x{base + 0x1FF:04X}) present", line,
                          ctx.value_column(line))


@rule("DCF122", "granularity", WARNING,
      "[DeviceInfo] Granularity is outside 0..64, or a PDO mapping does not follow it "
      "(configured although 0, or a length that is not a multiple of it).",
      hint="Granularity 0: mapping fixed; 8: byte-wise; 1: bit-wise")
def granularity(ctx):
    info = ctx.section("deviceinfo")
    if info is None:
        return
    g = _int(info.get("granularity"))
    if g is None:
        return
    gline = info.line_of("granularity")
    if not 0 <= g <= 64:
        yield Finding(f"[DeviceInfo] Granularity={g} is outside 0..64", gline,
                      ctx.value_column(gline))
        return
    for idx in sorted(ctx.dev.objects):
        if not is_pdo_mapping(idx):
            continue
        obj = ctx.dev.objects[idx]
        if g == 0:
            configured = [e for e in obj.entries.values() if e.configured]
            if configured:
                line = configured[0].value_where.line
                yield Finding(f"PDO mapping 0x{idx:04X} is configured but [DeviceInfo] "
                              f"Granularity=0 (line {gline}) says the mapping cannot change",
                              line, ctx.value_column(line))
            continue
        if g == 1:
            continue
        for sub, e in obj.entries.items():
            if sub == 0 or e.implicit:
                continue
            value, _ = ctx.int_value(e)
            if not value:
                continue
            bits = value & 0xFF
            if bits % g:
                line = e.value_where.line
                yield Finding(f"{e.label} maps {bits} bits, not a multiple of Granularity={g} "
                              f"(line {gline})", line, ctx.value_column(line))


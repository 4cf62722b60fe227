"""What a DCF that dcf2bin writes from partial knowledge must still describe to be a valid one.

bin2dcf writes a DCF from a container, ``simulate --emit-od`` from the object dictionary
it simulated. Neither knows the whole device, and a DCF of only what they know fails
validate (issue 26 item 16):

* the objects every CANopen device has, 0x1000, 0x1001, 0x1018 (CiA 301; DCF101): a
  container seldom writes these read-only objects;
* the entries its PDOs map (DCF404): a container maps the device's own objects (0x6040,
  0x2000sub1) without writing them;
* the dummy types its PDOs map, in ``[DummyUsage]`` (DCF410).

This module describes them from what is known, never a guessed value: CiA 301's names and
types for the mandatory objects; for a mapped entry the device's EDS where it describes
the entry as the mapping uses it, else the mapping itself -- its length in bits gives the
size (BOOLEAN for 1 bit, UNSIGNEDn for n bits), with AccessType rw, which any PDO may map,
and a comment that says these stand in for the device's. No such entry has a value (a
mandatory object only the EDS's), and the writers add ``ObjFlags=0x1`` (do not write on
download), so that ``compile`` of the DCF -- ``--entries all`` included -- writes none of
them and gives the container's bytes back (SPEC §4).

A leaf (it imports ``datatypes`` and ``values`` only), so that both writers can use it.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from dcf2bin import datatypes as dt
from dcf2bin import values

# -- the objects every device has (CiA 301) ----------------------------------------------------

#: index -> (name, ObjectType, ((sub, name, DataType), ...)); every entry read-only.
#: 0x1018 lists what CiA 301 defines: sub 1 is mandatory, 2..4 optional.
MANDATORY = {
    0x1000: ("Device type", dt.OT_VAR, ((0, "Device type", dt.UNSIGNED32),)),
    0x1001: ("Error register", dt.OT_VAR, ((0, "Error register", dt.UNSIGNED8),)),
    0x1018: ("Identity object", dt.OT_RECORD, (
        (0, "Highest sub-index supported", dt.UNSIGNED8), (1, "Vendor-ID", dt.UNSIGNED32),
        (2, "Product code", dt.UNSIGNED32), (3, "Revision number", dt.UNSIGNED32),
        (4, "Serial number", dt.UNSIGNED32))),
}

#: the subs described when nothing says which the device has: sub 0 and the mandatory sub 1
LEAST = {0x1000: (0,), 0x1001: (0,), 0x1018: (0, 1)}


def mandatory_sections(index: int, *, subs=None, values_: dict[int, str] | None = None,
                       mappable=(), comment: str = "", obj_flags: int = 0) -> list[str]:
    """The DCF lines of mandatory object ``index``: ``subs`` (default ``LEAST``) with
    ``values_`` (sub -> DefaultValue text; the others get none), PDOMapping=1 for the subs
    in ``mappable`` (a PDO maps them), ``comment`` (a ``;`` line after the object's
    header), ``ObjFlags`` when ``obj_flags`` is not 0. Ends with a blank line."""
    name, kind, entries = MANDATORY[index]
    subs = LEAST[index] if subs is None else tuple(subs)
    known = values_ or {}
    head = _head(index, comment, name, kind, obj_flags)
    if kind == dt.OT_VAR:
        return head + entry_keys(entries[0][2], "ro", 0 in mappable, known.get(0)) + [""]
    out = head + [f"SubNumber={len(subs)}", ""]
    for sub, sub_name, dtype in entries:
        if sub in subs:
            out += [f"[{index:04X}sub{sub:X}]", f"ParameterName={sub_name}", "ObjectType=0x7"]
            out += entry_keys(dtype, "ro", sub in mappable, known.get(sub)) + [""]
    return out


def mandatory_type(index: int, sub: int) -> dt.DataType | None:
    """The CiA 301 data type of a sub of a mandatory object (None for another one)."""
    for s, _, dtype in MANDATORY[index][2] if index in MANDATORY else ():
        if s == sub:
            return dtype
    return None


def known_value(text: str | None, dtype: dt.DataType) -> str | None:
    """An EDS's DefaultValue as a value of ``dtype`` (0x-hex, the type's width), or None:
    no value, one with $NODEID, or one that is no value of the type (never copied to fail
    elsewhere)."""
    if text is None or values.uses_nodeid(text):
        return None
    try:
        number = values.as_number(dtype, text, None)
    except values.ValueProblem:
        return None
    return None if number is None else f"0x{number:0{2 * dtype.size}X}"


# -- what the PDOs map ----------------------------------------------------------------------------

@dataclass(slots=True)
class Mapped:
    """An entry PDOs map: its length in bits, the directions, the first mapping entry."""
    bits: int
    by: str                          # '0x1600sub1'
    rx: bool = False
    tx: bool = False
    lengths: set = field(default_factory=set)


def mapped_entries(mappings) -> tuple[dict[tuple[int, int], Mapped], set[int]]:
    """What PDO mapping objects map: ``mappings`` gives (mapping index, {sub: data bytes})
    for each 0x1600-0x17FF/0x1A00-0x1BFF object; the values up to sub 0's count (all when
    sub 0 has no 1-byte value) count. Returns the mapped entries (network variables left
    out: they are created, never the device's) and the dummy data types mapped (1..7)."""
    out: dict[tuple[int, int], Mapped] = {}
    dummies: set[int] = set()
    for mapping, subs in mappings:
        s0 = subs.get(0)
        count = s0[0] if s0 is not None and len(s0) == 1 else None
        for sub, data in subs.items():
            if sub == 0 or (count is not None and sub > count) or len(data) != 4:
                continue
            v = int.from_bytes(data, "little")
            index, target, bits = v >> 16, (v >> 8) & 0xFF, v & 0xFF
            if 1 <= index <= 7:
                dummies.add(index)
                continue
            if index == 0 or 0xA000 <= index <= 0xAFFF or not bits:
                continue
            m = out.get((index, target))
            if m is None:
                m = out[(index, target)] = Mapped(bits, f"0x{mapping:04X}sub{sub:X}")
            m.lengths.add(bits)
            if mapping < 0x1A00:
                m.rx = True
            else:
                m.tx = True
    return out, dummies


@dataclass(slots=True)
class Stub:
    """How a mapped entry absent from the DCF is described."""
    name: str
    dtype: dt.DataType
    access: str
    comment: str


def stub(index: int, sub: int, m: Mapped, where: str, eds_entry=None) -> Stub | None:
    """A mapped entry as the EDS has it (``eds_entry``) where that fits the mapping
    (length, direction, mappable), else from the mapping; None when no type has its
    length, or the mappings disagree on it. ``where`` starts the comment ('not in the
    container')."""
    if len(m.lengths) != 1:
        return None
    e = eds_entry
    if e is not None and _fits(e, m):
        return Stub(e.name or _name(index, sub), e.dtype, e.access,
                    f"; {where}: mapped by {m.by}, as the EDS describes it (ObjFlags=0x1: "
                    "compile skips it)")
    dtype = dt.BOOLEAN if m.bits == 1 else \
        dt.UNSIGNED_BY_SIZE.get(m.bits // 8) if m.bits % 8 == 0 else None
    if dtype is None:
        return None
    return Stub(e.name if e is not None and e.name else _name(index, sub), dtype, "rw",
                f"; {where}: mapped by {m.by} ({m.bits} bits); DataType and AccessType "
                "stand in for the device's (ObjFlags=0x1: compile skips it)")


def _fits(e, m: Mapped) -> bool:
    t = e.dtype
    if t is None or t.size is None or e.access is None or not e.pdo_mapping:
        return False
    size_ok = m.bits == 1 if t.kind == dt.BOOL else t.size * 8 == m.bits
    return size_ok and (not m.rx or e.access in dt.WRITABLE) and \
        (not m.tx or e.access in dt.READABLE)


def _name(index: int, sub: int) -> str:
    return f"Object {index:04X}" if sub == 0 else f"Sub-index {sub}"


def stub_object(index: int, stubs: dict[int, Stub], name: str | None, where: str
                ) -> list[str]:
    """A whole object the DCF lacks, with ObjFlags=0x1: a VAR when only its sub 0 is
    mapped, else a RECORD with an explicit sub 0 (no value) and the mapped subs."""
    name = name or f"Object {index:04X}"
    if list(stubs) == [0]:
        s = stubs[0]
        return (_head(index, s.comment, name, dt.OT_VAR, 1)
                + entry_keys(s.dtype, s.access, True) + [""])
    out = _head(index, f"; {where}: an object its PDOs map (ObjFlags=0x1: compile skips it)",
                name, dt.OT_RECORD, 1)
    out += [f"SubNumber={len(stubs) + (0 not in stubs)}", ""]
    if 0 not in stubs:
        out += [f"[{index:04X}sub0]", "ParameterName=Highest sub-index supported",
                "ObjectType=0x7"] + entry_keys(dt.UNSIGNED8, "ro", False) + [""]
    for sub, s in stubs.items():
        out += stub_sub(index, sub, s, obj_flags=False)
    return out


def stub_sub(index: int, sub: int, s: Stub, *, obj_flags: bool) -> list[str]:
    """The section of one mapped sub (``obj_flags``: its own ObjFlags=0x1, for an object
    that has other, written, subs)."""
    out = [f"[{index:04X}sub{sub:X}]", s.comment, f"ParameterName={s.name}", "ObjectType=0x7"]
    if obj_flags:
        out.append("ObjFlags=0x1")
    return out + entry_keys(s.dtype, s.access, True) + [""]


# -- lines ----------------------------------------------------------------------------------------

def _head(index: int, comment: str, name: str, kind: int, obj_flags: int) -> list[str]:
    head = [f"[{index:04X}]"]
    if comment:
        head.append(comment)
    head += [f"ParameterName={name}", f"ObjectType=0x{kind:X}"]
    if obj_flags:
        head.append(f"ObjFlags=0x{obj_flags:X}")
    return head


def entry_keys(dtype: dt.DataType, access: str, pdo: bool, value: str | None = None
               ) -> list[str]:
    """DataType, AccessType, DefaultValue (when given) and PDOMapping lines of an entry."""
    keys = [f"DataType=0x{dtype.code:04X}", f"AccessType={access}"]
    if value is not None:
        keys.append(f"DefaultValue={value}")
    return keys + [f"PDOMapping={1 if pdo else 0}"]


__all__ = ["LEAST", "MANDATORY", "Mapped", "Stub", "entry_keys", "known_value",
           "mandatory_sections", "mandatory_type", "mapped_entries", "stub", "stub_object",
           "stub_sub"]

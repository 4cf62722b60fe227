"""What bin2dcf's DCF describes beside what the container writes (issue 26 item 16): the
objects every device has and the entries its PDOs map, where the container does not
write them, so that the DCF validates and still compiles to the container's bytes
(``dcf2bin.dcfparts`` says how each is described; SPEC §4); and the other object of a PDO
whose communication or mapping object alone is written (a concise DCF that only disables a
PDO writes its COB-ID), as every PDO has both (SPEC §3.2).
"""
from __future__ import annotations

from dataclasses import dataclass, field

from dcf2bin import datatypes as dt
from dcf2bin import dcfparts
from dcf2bin.dcfwriter.spec import DcfSpec
from dcf2bin.model import is_pdo_comm as is_comm
from dcf2bin.model import is_pdo_mapping as is_mapping

WHERE = "not in the container"
NOT_WRITTEN = f"; {WHERE}: an object every CANopen device has (ObjFlags=0x1: compile skips it)"


def _where(spec: DcfSpec) -> str:
    return f"not in the {spec.what}"


@dataclass
class Described:
    """The sections to add: whole objects by index, and sub sections of objects the
    container writes (their count raises the object's SubNumber). (The dummy types the
    PDOs map are in ``[DummyUsage]`` already: text.py.)"""
    objects: dict[int, list[str]] = field(default_factory=dict)
    subs: dict[int, list[str]] = field(default_factory=dict)
    sub_count: dict[int, int] = field(default_factory=dict)


def describe(spec: DcfSpec, eds_device=None) -> Described:
    """The objects and entries to add to the DCF of ``spec``."""
    objects = spec.objects
    where = _where(spec)
    mapped, _ = dcfparts.mapped_entries(
        (obj.index, {sub: s.value_bytes for sub, s in obj.subs.items()})
        for obj in objects.values() if is_mapping(obj.index))
    out = Described()
    for index in dcfparts.MANDATORY:
        if index not in objects:
            pdo = {sub for (i, sub) in mapped if i == index}
            out.objects[index] = _mandatory(index, eds_device, pdo, where)
    wanted: dict[int, dict[int, dcfparts.Mapped]] = {}
    for (index, sub), m in mapped.items():
        if index in dcfparts.MANDATORY and index not in objects:
            continue                                 # described above
        obj = objects.get(index)
        if obj is not None and (sub in obj.subs or obj.object_type == dt.OT_VAR):
            continue                                 # written (or a VAR: no sub to add)
        wanted.setdefault(index, {})[sub] = m
    _pdo_partners(objects, out, where)
    for index, subs in sorted(wanted.items()):
        stubs = {}
        for sub, m in sorted(subs.items()):
            e = eds_device.entry(index, sub) if eds_device is not None else None
            s = dcfparts.stub(index, sub, m, where, e)
            if s is not None:
                stubs[sub] = s
        if not stubs:
            continue
        if index in objects:
            out.subs[index] = [line for sub, s in stubs.items()
                               for line in dcfparts.stub_sub(index, sub, s, obj_flags=True)]
            out.sub_count[index] = len(stubs)
        else:
            eds_obj = eds_device.objects.get(index) if eds_device is not None else None
            out.objects[index] = dcfparts.stub_object(
                index, stubs, eds_obj.name if eds_obj is not None else None, where)
    return out


def _pdo_partners(objects, out: Described, where: str) -> None:
    """The mapping object of a written communication object, or the other way round, where
    the bytes do not write it: its sub 0 (and a communication object's COB-ID) without a
    value, ObjFlags=0x1."""
    for index in sorted(objects):
        if is_comm(index):
            partner, subs = index + 0x200, ((0, "Number of mapped objects", "rw"),)
        elif is_mapping(index):
            partner, subs = index - 0x200, ((0, "Highest sub-index supported", "ro"),
                                            (1, "COB-ID", "rw"))
        else:
            continue
        if partner in objects or partner in out.objects:
            continue
        kind, number = ("RPDO", (partner & 0x1FF) + 1) if partner < 0x1800 else \
            ("TPDO", (partner & 0x1FF) + 1)
        what = "mapping" if is_mapping(partner) else "communication"
        lines = [f"[{partner:04X}]", f"; {where}: the {what} object of the PDO that "
                 f"0x{index:04X} configures (ObjFlags=0x1: compile skips it)",
                 f"ParameterName={kind}{number} {what} parameter", "ObjectType=0x9",
                 "ObjFlags=0x1", f"SubNumber={len(subs)}", ""]
        for sub, name, access in subs:
            dtype = dt.UNSIGNED8 if sub == 0 else dt.UNSIGNED32
            lines += [f"[{partner:04X}sub{sub}]", f"ParameterName={name}", "ObjectType=0x7",
                      *dcfparts.entry_keys(dtype, access, False), ""]
        out.objects[partner] = lines


def _mandatory(index: int, eds_device, pdo: set[int], where: str = WHERE) -> list[str]:
    """A mandatory object the container does not write: CiA 301's subs (0x1018: sub 1,
    those of 2..4 the EDS has, and any a PDO maps), values only from the EDS."""
    not_written = NOT_WRITTEN.replace(WHERE, where)
    defined = {s for s, _, _ in dcfparts.MANDATORY[index][2]}
    obj = eds_device.objects.get(index) if eds_device is not None else None
    subs = set(dcfparts.LEAST[index]) | (pdo & defined)
    if obj is None:
        return dcfparts.mandatory_sections(index, subs=sorted(subs), mappable=pdo,
                                           comment=not_written, obj_flags=1)
    subs = sorted(subs | (defined & set(obj.entries)))
    known = {}
    for sub in subs:
        e = obj.entries.get(sub)
        text = dcfparts.known_value(e.default, dcfparts.mandatory_type(index, sub)) \
            if e is not None else None
        if text is not None:
            known[sub] = text
    if index == 0x1018:
        known[0] = str(subs[-1])    # the subs described here, as validate counts them
    return dcfparts.mandatory_sections(index, subs=subs, values_=known, mappable=pdo,
                                       comment=not_written + "; values from the EDS",
                                       obj_flags=1)


__all__ = ["Described", "NOT_WRITTEN", "WHERE", "describe"]

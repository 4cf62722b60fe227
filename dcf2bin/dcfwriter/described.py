"""What bin2dcf's DCF describes beside what the container writes (issue 26 item 16): the
objects every device has and the entries its PDOs map, where the container does not
write them, so that the DCF validates and still compiles to the container's bytes
(``dcf2bin.dcfparts`` says how each is described; SPEC §4).
"""
from __future__ import annotations

from dataclasses import dataclass, field

from dcf2bin import datatypes as dt
from dcf2bin import dcfparts
from dcf2bin.dcfwriter.spec import DcfSpec
from dcf2bin.model import is_pdo_mapping as is_mapping

WHERE = "not in the container"
NOT_WRITTEN = f"; {WHERE}: an object every CANopen device has (ObjFlags=0x1: compile skips it)"


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
    mapped, _ = dcfparts.mapped_entries(
        (obj.index, {sub: s.value_bytes for sub, s in obj.subs.items()})
        for obj in objects.values() if is_mapping(obj.index))
    out = Described()
    for index in dcfparts.MANDATORY:
        if index not in objects:
            pdo = {sub for (i, sub) in mapped if i == index}
            out.objects[index] = _mandatory(index, eds_device, pdo)
    wanted: dict[int, dict[int, dcfparts.Mapped]] = {}
    for (index, sub), m in mapped.items():
        if index in dcfparts.MANDATORY and index not in objects:
            continue                                 # described above
        obj = objects.get(index)
        if obj is not None and (sub in obj.subs or obj.object_type == dt.OT_VAR):
            continue                                 # written (or a VAR: no sub to add)
        wanted.setdefault(index, {})[sub] = m
    for index, subs in sorted(wanted.items()):
        stubs = {}
        for sub, m in sorted(subs.items()):
            e = eds_device.entry(index, sub) if eds_device is not None else None
            s = dcfparts.stub(index, sub, m, WHERE, e)
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
                index, stubs, eds_obj.name if eds_obj is not None else None, WHERE)
    return out


def _mandatory(index: int, eds_device, pdo: set[int]) -> list[str]:
    """A mandatory object the container does not write: CiA 301's subs (0x1018: sub 1,
    those of 2..4 the EDS has, and any a PDO maps), values only from the EDS."""
    defined = {s for s, _, _ in dcfparts.MANDATORY[index][2]}
    obj = eds_device.objects.get(index) if eds_device is not None else None
    subs = set(dcfparts.LEAST[index]) | (pdo & defined)
    if obj is None:
        return dcfparts.mandatory_sections(index, subs=sorted(subs), mappable=pdo,
                                           comment=NOT_WRITTEN, obj_flags=1)
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
                                       comment=NOT_WRITTEN + "; values from the EDS",
                                       obj_flags=1)


__all__ = ["Described", "NOT_WRITTEN", "WHERE", "describe"]

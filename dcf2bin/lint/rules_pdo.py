"""DCF4xx: PDO communication and mapping parameters (CiA 301, SPEC §3.2, §5, §6)."""
from __future__ import annotations

from dataclasses import dataclass, field

from dcf2bin import datatypes as dt
from dcf2bin.lint.registry import ERROR, INFO, WARNING, Finding, rule
from dcf2bin.model import (NV_FIRST, NV_LAST, is_pdo_comm, is_pdo_mapping,
                           unstated_mapping_count)

COB_INVALID, COB_NO_RTR, COB_29BIT = 0x80000000, 0x40000000, 0x20000000
MAX_MAPPED = 64
# CiA 301 §7.3.5: CAN-IDs reserved for NMT, SYNC/EMCY, TIME, SDO, NMT error control, LSS
RESTRICTED = [(0x000, 0x000), (0x001, 0x07F), (0x101, 0x180), (0x581, 0x5FF), (0x601, 0x67F),
              (0x6E0, 0x6FF), (0x701, 0x77F), (0x780, 0x7FF)]
_COMM_TYPES = {1: dt.UNSIGNED32, 2: dt.UNSIGNED8, 3: dt.UNSIGNED16, 5: dt.UNSIGNED16,
               6: dt.UNSIGNED8}


@dataclass
class Mapped:
    sub: int
    entry: object                  # the mapping Entry
    index: int
    subindex: int
    bits: int


@dataclass
class Pdo:
    comm_index: int
    comm: object                   # Obj
    mapping: object | None         # Obj
    rx: bool
    cob: int | None = None         # COB-ID with node-ID (0 if $NODEID and unknown)
    cob_nodeid: bool = False
    count: int | None = None       # mapping sub 0
    mapped: list[Mapped] = field(default_factory=list)

    @property
    def label(self) -> str:
        return f"{'RPDO' if self.rx else 'TPDO'} 0x{self.comm_index:04X}"

    @property
    def valid(self) -> bool:
        return self.cob is not None and not self.cob & COB_INVALID


def pdos(ctx) -> list[Pdo]:
    out = ctx.cache.get("pdos")
    if out is not None:
        return out
    out = []
    dev = ctx.dev
    for idx in sorted(dev.objects):
        if not is_pdo_comm(idx):
            continue
        comm = dev.objects[idx]
        p = Pdo(idx, comm, dev.objects.get(idx + 0x200), idx < 0x1800)
        e1 = comm.entries.get(1)
        if e1 is not None and e1.dtype is not None and e1.dtype.code == dt.UNSIGNED32.code:
            p.cob, p.cob_nodeid = ctx.int_value(e1)
        if p.mapping is not None:
            e0 = p.mapping.entries.get(0)
            if e0 is not None:
                p.count = ctx.int_value(e0)[0]
            if p.count is not None:
                for k in range(1, min(p.count, MAX_MAPPED) + 1):
                    e = p.mapping.entries.get(k)
                    if e is None or e.dtype is None or e.dtype.code != dt.UNSIGNED32.code:
                        continue
                    v = ctx.int_value(e)[0]
                    if v is None:
                        continue
                    p.mapped.append(Mapped(k, e, v >> 16, (v >> 8) & 0xFF, v & 0xFF))
        out.append(p)
    ctx.cache["pdos"] = out
    return out


def _at(ctx, entry, key: str | None = None):
    line = entry.key_where(key).line if key else entry.value_where.line
    return line, ctx.value_column(line)


@rule("DCF401", "pdo-comm-without-mapping", ERROR,
      "A PDO communication object (0x1400.., 0x1800..) has no mapping object (+0x200).",
      hint="add the mapping object 0x16xx/0x1Axx")
def comm_without_mapping(ctx):
    for p in pdos(ctx):
        if p.mapping is None:
            yield Finding(f"PDO communication object 0x{p.comm_index:04X} has no mapping object "
                          f"0x{p.comm_index + 0x200:04X}",
                          p.comm.where.line if p.comm.where else None)


@rule("DCF402", "pdo-mapping-without-comm", ERROR,
      "A PDO mapping object (0x1600.., 0x1A00..) has no communication object (-0x200).",
      hint="add the communication object 0x14xx/0x18xx")
def mapping_without_comm(ctx):
    for idx in sorted(ctx.dev.objects):
        if is_pdo_mapping(idx) and idx - 0x200 not in ctx.dev.objects:
            obj = ctx.dev.objects[idx]
            yield Finding(f"PDO mapping object 0x{idx:04X} has no communication object "
                          f"0x{idx - 0x200:04X}", obj.where.line if obj.where else None)


@rule("DCF403", "pdo-cob-id-missing", ERROR,
      "A PDO communication object has no sub 1 (COB-ID), or it is not UNSIGNED32.",
      hint="sub 1 of a PDO communication object is the UNSIGNED32 COB-ID")
def cob_missing(ctx):
    for p in pdos(ctx):
        e1 = p.comm.entries.get(1)
        if e1 is None:
            yield Finding(f"{p.label} has no COB-ID (sub 1)",
                          p.comm.where.line if p.comm.where else None)
        elif e1.dtype is not None and e1.dtype.code != dt.UNSIGNED32.code:
            yield Finding(f"{e1.label} (COB-ID) is {e1.dtype.name}, not UNSIGNED32",
                          *_at(ctx, e1, "datatype"))


@rule("DCF404", "mapped-object-missing", ERROR,
      "A PDO mapping entry names an object/subindex that does not exist (or is 0).",
      hint="map an existing entry, or lower mapping sub 0")
def mapped_missing(ctx):
    for p in pdos(ctx):
        for m in p.mapped:
            if 1 <= m.index <= 7:
                continue  # dummy: DCF410
            if m.index == 0 and m.subindex == 0:
                yield Finding(f"{m.entry.label} is 0 but sub 0 counts {p.count} mapped objects",
                              *_at(ctx, m.entry))
            elif ctx.dev.entry(m.index, m.subindex) is None:
                yield Finding(f"{m.entry.label} maps 0x{m.index:04X}sub{m.subindex:X}, which does "
                              "not exist", *_at(ctx, m.entry))


@rule("DCF405", "mapped-object-not-mappable", ERROR,
      "A PDO maps an entry whose PDOMapping is not 1.",
      hint="set PDOMapping=1 on the mapped entry, or map another one")
def not_mappable(ctx):
    for p in pdos(ctx):
        for m in p.mapped:
            t = ctx.dev.entry(m.index, m.subindex)
            if t is None or t.pdo_mapping or NV_FIRST <= m.index <= NV_LAST:
                continue  # network variables are always created mappable (SPEC §3.3)
            yield Finding(f"{m.entry.label} maps {t.label}, which is not PDO-mappable",
                          *_at(ctx, m.entry))


@rule("DCF406", "mapped-object-wrong-direction", ERROR,
      "An RPDO maps an entry that is not writable, or a TPDO one that is not readable.",
      hint="RPDO targets are wo/rw/rww, TPDO sources ro/rw/rwr/const")
def wrong_direction(ctx):
    for p in pdos(ctx):
        for m in p.mapped:
            t = ctx.dev.entry(m.index, m.subindex)
            if t is None or t.access is None or NV_FIRST <= m.index <= NV_LAST:
                continue
            ok = dt.WRITABLE if p.rx else dt.READABLE
            if t.access not in ok:
                need = "writable" if p.rx else "readable"
                yield Finding(f"{p.label} maps {t.label} ({t.access}), which is not {need}",
                              *_at(ctx, m.entry))


@rule("DCF407", "mapped-length-mismatch", ERROR,
      "A PDO mapping entry's bit length differs from the mapped entry's type size.",
      hint="the low byte of a mapping entry is the length in bits of the mapped type")
def length_mismatch(ctx):
    for p in pdos(ctx):
        for m in p.mapped:
            if 1 <= m.index <= 7:
                t_type = dt.BY_CODE.get(m.index)
            else:
                t = ctx.dev.entry(m.index, m.subindex)
                t_type = t.dtype if t is not None else None
            if t_type is None or t_type.bits is None:
                if t_type is not None and m.bits == 0:
                    yield Finding(f"{m.entry.label} maps {t_type.name} with length 0",
                                  *_at(ctx, m.entry))
                continue
            ok = {t_type.bits} | ({1} if t_type.kind == dt.BOOL else set())
            if m.bits not in ok:
                yield Finding(f"{m.entry.label} maps 0x{m.index:04X}sub{m.subindex:X} with "
                              f"{m.bits} bits; {t_type.name} has {t_type.bits}",
                              *_at(ctx, m.entry))


@rule("DCF408", "pdo-too-long", ERROR,
      "The objects mapped into one PDO exceed 64 bits (8 bytes, classic CAN; the profile's "
      "limit with --profile).",
      hint="split the mapping over two PDOs")
def too_long(ctx):
    limit = ctx.profile.max_bits
    for p in pdos(ctx):
        total = sum(m.bits for m in p.mapped)
        if total > limit:
            e0 = p.mapping.entries[0]
            yield Finding(f"{p.label} maps {total} bits, more than {limit}", *_at(ctx, e0))


@rule("DCF409", "pdo-too-many-mapped", ERROR,
      "Mapping sub 0 counts more than 64 mapped objects.",
      hint="a PDO maps at most 64 objects")
def too_many(ctx):
    for p in pdos(ctx):
        if p.count is not None and p.count > MAX_MAPPED:
            e0 = p.mapping.entries[0]
            yield Finding(f"{e0.label} counts {p.count} mapped objects, more than {MAX_MAPPED}",
                          *_at(ctx, e0))


@rule("DCF410", "dummy-mapping-not-enabled", ERROR,
      "A PDO maps a dummy entry (0x0001-0x0007) whose type [DummyUsage] does not enable, "
      "or with a subindex other than 0.",
      hint="set Dummy<type>=1 in [DummyUsage]")
def dummy_not_enabled(ctx):
    for p in pdos(ctx):
        for m in p.mapped:
            if not 1 <= m.index <= 7:
                continue
            if m.subindex != 0:
                yield Finding(f"{m.entry.label} maps dummy 0x{m.index:04X} with subindex "
                              f"{m.subindex}; dummies use subindex 0", *_at(ctx, m.entry))
            elif m.index not in ctx.dev.dummy_usage:
                yield Finding(f"{m.entry.label} maps dummy 0x{m.index:04X} but [DummyUsage] "
                              f"Dummy{m.index:04X} is not 1", *_at(ctx, m.entry))


@rule("DCF411", "cob-id-reserved-bits", ERROR,
      "A PDO COB-ID with an 11-bit CAN-ID (bit 29 clear) sets bits 11-28.",
      hint="11-bit CAN-IDs are 0x001..0x7FF; set bit 29 for a 29-bit identifier")
def cob_reserved_bits(ctx):
    for p in pdos(ctx):
        if p.cob is None or p.cob & COB_29BIT or not p.cob & 0x1FFFF800:
            continue
        yield Finding(f"{p.label}: COB-ID 0x{p.cob:08X} sets bits 11-28 for an 11-bit CAN-ID",
                      *_at(ctx, p.comm.entries[1]))


@rule("DCF412", "cob-id-restricted", WARNING,
      "A valid PDO uses a CAN-ID that CiA 301 reserves (NMT, SYNC/EMCY, TIME, SDO, "
      "heartbeat, LSS).",
      hint="use a PDO CAN-ID from 0x181..0x57F or 0x680..0x6DF")
def cob_restricted(ctx):
    for p in pdos(ctx):
        if not p.valid or p.cob & COB_29BIT:
            continue
        nodes = (1, 127) if p.cob_nodeid and ctx.dev.node_id is None else (0,)
        for n in nodes:
            can_id = (p.cob + n) & 0x7FF
            if any(lo <= can_id <= hi for lo, hi in RESTRICTED):
                extra = f" (with node-ID {n})" if n else ""
                yield Finding(f"{p.label}: CAN-ID 0x{can_id:03X}{extra} is reserved by CiA 301",
                              *_at(ctx, p.comm.entries[1]))
                break


@rule("DCF413", "cob-id-collision", ERROR,
      "Two valid PDOs use the same COB-ID.",
      hint="give every valid PDO its own CAN-ID")
def cob_collision(ctx):
    seen: dict[tuple, Pdo] = {}
    for p in pdos(ctx):
        if not p.valid:
            continue
        key = (p.cob_nodeid and ctx.dev.node_id is None, p.cob & (0x1FFFFFFF | COB_29BIT))
        first = seen.get(key)
        if first is None:
            seen[key] = p
            continue
        e1 = p.comm.entries[1]
        other = first.comm.entries[1]
        yield Finding(f"{p.label}: COB-ID {e1.value_text} collides with {first.label} "
                      f"(line {other.value_where.line})", *_at(ctx, e1))


@rule("DCF414", "transmission-type-reserved", ERROR,
      "A PDO transmission type is reserved (241-251), or RTR-only (252/253) on an RPDO.",
      hint="0-240 synchronous, 252/253 RTR (TPDO only), 254/255 event-driven")
def transmission_type(ctx):
    for p in pdos(ctx):
        e = p.comm.entries.get(2)
        if e is None or e.implicit:
            continue
        v = ctx.int_value(e)[0]
        if v is None:
            continue
        if 241 <= v <= 251:
            yield Finding(f"{e.label}: transmission type {v} is reserved", *_at(ctx, e))
        elif p.rx and v in (252, 253):
            yield Finding(f"{e.label}: transmission type {v} (RTR-only) applies to TPDOs only",
                          *_at(ctx, e))


@rule("DCF415", "pdo-comm-sub-not-written", WARNING,
      "A configured PDO communication sub-entry that the PDO block never writes (sub 0, 4, "
      "7 and above).",
      hint="compile writes comm subs 1, 2, 3, 5 and 6 only")
def comm_sub_not_written(ctx):
    for p in pdos(ctx):
        for s, e in p.comm.entries.items():
            if e.configured and (s in (0, 4) or s >= 7):
                line, col = _at(ctx, e, "parametervalue" if e.param is not None
                                else "downloadfile")
                yield Finding(f"{e.label} is configured but never written", line, col)


@rule("DCF416", "pdo-mapping-above-count", WARNING,
      "A configured, non-zero PDO mapping entry above the count in mapping sub 0; it is not "
      "written.",
      hint="raise mapping sub 0, or remove the entry's ParameterValue")
def mapping_above_count(ctx):
    for p in pdos(ctx):
        if p.mapping is None or p.count is None:
            continue
        for s, e in p.mapping.entries.items():
            if s > p.count and e.configured and ctx.int_value(e)[0] != 0:  # 0 = empty slot
                yield Finding(f"{e.label} is configured but mapping sub 0 is {p.count}; not "
                              "written", *_at(ctx, e))


@rule("DCF417", "pdo-mapping-sub-missing", ERROR,
      "Mapping sub 0 counts n objects but a sub k <= n is missing.",
      hint="add the missing mapping sub-entries, or lower sub 0")
def mapping_sub_missing(ctx):
    for p in pdos(ctx):
        if p.mapping is None or p.count is None or p.count > MAX_MAPPED:
            continue
        missing = [k for k in range(1, p.count + 1) if k not in p.mapping.entries]
        if missing:
            e0 = p.mapping.entries[0]
            shown = ", ".join(str(k) for k in missing[:8]) + (", ..." if len(missing) > 8 else "")
            yield Finding(f"PDO mapping 0x{p.mapping.index:04X} maps {p.count} objects but has no "
                          f"sub {shown}", *_at(ctx, e0))


@rule("DCF418", "pdo-entry-type", ERROR,
      "A PDO parameter has the wrong DataType (mapping entries UNSIGNED32; comm sub 2/6 "
      "UNSIGNED8, sub 3/5 UNSIGNED16).",
      hint="use the CiA 301 types of the PDO parameter records")
def entry_type(ctx):
    for p in pdos(ctx):
        for s, want in _COMM_TYPES.items():
            e = p.comm.entries.get(s)
            if s == 1 or e is None or e.dtype is None or e.dtype.code == want.code:
                continue
            yield Finding(f"{e.label} is {e.dtype.name}; expected {want.name}",
                          *_at(ctx, e, "datatype"))
    for idx in sorted(ctx.dev.objects):
        if not is_pdo_mapping(idx):
            continue
        for s, e in ctx.dev.objects[idx].entries.items():
            if s and e.dtype is not None and e.dtype.code != dt.UNSIGNED32.code:
                yield Finding(f"{e.label} is {e.dtype.name}; mapping entries are UNSIGNED32",
                              *_at(ctx, e, "datatype"))


def _block_written(ctx, comm_index: int) -> bool:
    """Does compile (default selection) write this PDO's block: both objects exist and one
    of them has a configured sub-entry (SPEC §3.2 step 3)?"""
    objs = [ctx.dev.objects.get(comm_index), ctx.dev.objects.get(comm_index + 0x200)]
    return None not in objs and any(e.configured for o in objs for e in o.entries.values())


@rule("DCF419", "pdo-mapping-count-unstated", WARNING,
      "A PDO mapping object lists sub-entries but its sub 0 gives no value (no sub 0, or "
      "no DefaultValue/ParameterValue; e.g. only HighLimit=8): how many objects it maps is "
      "not said. An error where compile writes that PDO's block.",
      hint="give mapping sub 0 a DefaultValue (EDS) or ParameterValue (DCF)")
def mapping_count_unstated(ctx):
    for idx in sorted(ctx.dev.objects):
        if not is_pdo_mapping(idx) or _block_written(ctx, idx - 0x200):
            continue   # a written block: the compile selection reports it as an error
        unstated = unstated_mapping_count(ctx.dev.objects[idx])
        if unstated is not None:
            where, message = unstated
            yield Finding(message, where.line)


# -- device profiles (SPEC §6) ---------------------------------------------------------------

@rule("DCF450", "profile-too-many-mapped", ERROR,
      "With --profile dis2: a PDO maps more objects than the profile allows (4).",
      hint="Metronix DIS-2 maps at most 4 objects per PDO")
def profile_too_many(ctx):
    limit = ctx.profile.max_mapped
    if limit >= MAX_MAPPED:
        return
    for p in pdos(ctx):
        if p.count is not None and limit < p.count <= MAX_MAPPED:
            e0 = p.mapping.entries[0]
            yield Finding(f"{p.label} maps {p.count} objects; profile {ctx.profile.name} allows "
                          f"{limit}", *_at(ctx, e0))


@rule("DCF451", "profile-cob-id-bit30", ERROR,
      "With --profile dis2: a PDO COB-ID lacks bit 30 (no RTR), which the profile requires.",
      hint="set bit 30: e.g. 0x40000000 + the CAN-ID")
def profile_bit30(ctx):
    if not ctx.profile.cob_bit30_required:
        return
    for p in pdos(ctx):
        if p.cob is not None and not p.cob & COB_NO_RTR:
            e1 = p.comm.entries[1]
            yield Finding(f"{p.label}: COB-ID {e1.value_text} lacks bit 30 (no RTR), required by "
                          f"profile {ctx.profile.name}", *_at(ctx, e1))


@rule("DCF452", "profile-old-cob-id-write", INFO,
      "With --profile dis2: a PDO block first writes the COB-ID the drive has (comm sub 1's "
      "DefaultValue) | 0xC0000000, because its CAN-ID differs from the final COB-ID's.",
      hint="the drive changes a COB-ID only while the PDO is disabled under its old one")
def profile_old_cob_id(ctx):
    if not ctx.profile.old_cob_first:
        return
    for p in pdos(ctx):
        e1 = p.comm.entries.get(1)
        if p.cob is None or e1 is None or e1.default is None \
                or not _block_written(ctx, p.comm_index):
            continue
        old, old_nodeid = ctx.int_value(e1, e1.default)
        if old is None:
            continue   # DCF200 reports it (compile: an error with this profile)
        if ctx.dev.node_id is None and old_nodeid != p.cob_nodeid:
            continue   # the answer depends on the node-ID (compile: DCF201)
        if (old ^ p.cob) & 0x1FFFFFFF:
            value = f" = 0x{old | 0xC0000000:08X}" if ctx.dev.node_id is not None \
                or not old_nodeid else ""
            yield Finding(f"{p.label}: the PDO block first writes the old COB-ID "
                          f"{e1.default} | 0xC0000000{value} (DefaultValue of {e1.label}): "
                          f"its CAN-ID differs from the final {e1.value_text}",
                          *_at(ctx, e1, "defaultvalue"))

"""Which entries the index segment writes, in which order (SPEC.md §3.2, D-8).

The result is a ``Selection``: the index segment's entries (index, subindex, data
bytes), already encoded, and their attribute bytes, as two columns. Encoding errors of
written entries are collected, not raised, so one run reports all of them.
"""
from __future__ import annotations

from bisect import bisect_left, bisect_right
from dataclasses import dataclass, field
from itertools import repeat

from dcf2bin import datatypes as dt
from dcf2bin.diagnostics import DcfError, Diagnostic, Severity
from dcf2bin.model import (Device, Entry, NV_FIRST, NV_LAST, is_pdo_comm, is_pdo_mapping,
                           is_pdo_object, unstated_mapping_count)

AUTO, ALL = "auto", "all"
CIA301, NONE = "cia301", "none"
COB_INVALID = 0x80000000
CAN_ID_MASK = 0x1FFFFFFF   # COB-ID bits 0-28: the CAN-ID
MAX_MAPPED = 64


@dataclass(slots=True)
class Write:
    """One entry the container writes: index, subindex, data and attribute byte."""
    index: int
    sub: int
    data: bytes
    attr: int


@dataclass
class PdoRules:
    """How a PDO block disables and enables a PDO (SPEC §3.2 a/f, §6 for DIS-2)."""
    disable_mask: int = COB_INVALID
    enable_mask: int = 0
    max_mapped: int = MAX_MAPPED
    # D-12 (DIS-2): when comm sub 1's DefaultValue (the COB-ID the device has) has another
    # CAN-ID than the final one, the block first writes ``old | disable_mask``
    old_cob_first: bool = False


@dataclass
class Selection:
    """The index segment as columns: ``entries`` (index, subindex, data) and one
    attribute byte per entry in ``attrs`` (a compile writes tens of thousands)."""
    entries: list[tuple[int, int, bytes]] = field(default_factory=list)
    attrs: bytearray = field(default_factory=bytearray)
    errors: list[Diagnostic] = field(default_factory=list)
    emitted: set[tuple[int, int]] = field(default_factory=set)   # outside ``created``
    emitted_objects: set[int] = field(default_factory=set)
    created: set[int] = field(default_factory=set)   # objects written whole (group 1)
    # the network-variable objects, in the order group 1 wrote them (each by subindex):
    # the first occurrence of every variable in the index segment (SPEC §3.4)
    nv_objects: list[int] = field(default_factory=list)

    def wrote(self, index: int, sub: int | None = None) -> bool:
        """Does the index segment write this entry (sub None: any entry of the object)?"""
        if index in self.created:
            return True
        if sub is None:
            return index in self.emitted_objects
        return (index, sub) in self.emitted


# D-9: network variables are created NUMERIC|READ|WRITE|PDO, their sub 0 NUMERIC|READ
NV_ATTR, NV_SUB0_ATTR = 0xF0, 0x30
_NV_ATTR_BYTE = bytes([NV_ATTR])


def attribute_byte(index: int, sub: int, dtype: dt.DataType | None, access: str | None,
                   pdo: bool) -> int:
    """The extended-info attribute byte (SPEC §3.3, D-9); bin2dcf predicts with it too."""
    if NV_FIRST <= index <= NV_LAST:
        return NV_ATTR if sub else NV_SUB0_ATTR
    attr = dtype.type_attr if dtype is not None else 0
    attr |= dt.ACCESS_ATTR.get(access or "", 0)
    return attr | dt.ATTR_PDO if pdo else attr


def attribute(entry: Entry) -> int:
    """The attribute byte of an entry of the model."""
    return attribute_byte(entry.index, entry.sub, entry.dtype, entry.access, entry.pdo_mapping)


class _Selector:
    def __init__(self, dev: Device, policy: str, pdo_sequence: str,
                 static_od: set[int] | None, rules: PdoRules):
        self.dev = dev
        self.policy = policy
        self.pdo_sequence = pdo_sequence
        self.static_od = static_od
        self.rules = rules
        self.sel = Selection()

    def error(self, exc_or_msg, where=None, rule: str = "") -> None:
        if isinstance(exc_or_msg, DcfError):
            self.sel.errors.append(exc_or_msg.diagnostic)
        else:
            self.sel.errors.append(Diagnostic(Severity.ERROR, exc_or_msg,
                                              where.file if where else self.dev.path,
                                              where.line if where else None, rule=rule))

    def write(self, entry: Entry, data: bytes | None = None) -> None:
        if data is None and entry.dtype is None:
            data = b""  # the model already reported the missing/unknown DataType
        elif data is None:
            try:
                data = self.dev.encode(entry)
            except DcfError as exc:
                self.error(exc)
                data = b""
        sel, index, sub = self.sel, entry.index, entry.sub
        sel.entries.append((index, sub, data))
        sel.attrs.append(attribute_byte(index, sub, entry.dtype, entry.access,
                                        entry.pdo_mapping))
        sel.emitted.add((index, sub))
        sel.emitted_objects.add(index)

    def counts(self, entry: Entry) -> bool:
        """Configured (auto) or has any value (all)."""
        return entry.configured if self.policy == AUTO else entry.has_value

    def run(self) -> Selection:
        dev = self.dev
        objs = [o for o in dev.sorted_objects() if o.index >= 0x1000]
        created = set()
        # 1. creation: every sub-entry of the object -- the bulk of a PLC file
        entries, attrs = self.sel.entries, self.sel.attrs
        for obj in objs:
            idx = obj.index
            nv = NV_FIRST <= idx <= NV_LAST
            if not nv and (self.static_od is None or idx in self.static_od):
                continue
            created.add(idx)
            # the object column by column: its data bytes (one value shared by runs of
            # variables), then (index, sub, data) and the attribute bytes (D-9)
            es = obj.entries
            entries.extend(zip(repeat(idx), es, self._data_column(es.values())))
            if nv:
                self.sel.nv_objects.append(idx)
                at = len(attrs)
                attrs += _NV_ATTR_BYTE * len(es)
                for k, sub in enumerate(es):     # sub 0: first, but for a file's order
                    if not sub:
                        attrs[at + k] = NV_SUB0_ATTR
                        break
            else:
                attrs.extend(map(attribute, es.values()))
        self.sel.created = created
        # 2. configuration
        auto = self.policy == AUTO
        for obj in objs:
            if obj.index in created or is_pdo_object(obj.index):
                continue
            for e in obj.entries.values():
                if e.obj_flags & 1:
                    continue
                if auto:
                    if e.configured and e.access not in ("ro", "const"):
                        self.write(e)
                elif e.has_value:
                    self.write(e)
        # 3. PDOs: the communication objects present, RPDOs (0x1400-0x15FF) then TPDOs
        # (0x1800-0x19FF), each by ascending index (``objs`` is sorted)
        self.check_pairs()
        keys = [obj.index for obj in objs]
        for lo, hi in ((0x1400, 0x15FF), (0x1800, 0x19FF)):
            for obj in objs[bisect_left(keys, lo):bisect_right(keys, hi)]:
                comm = obj.index
                if comm in created:
                    continue
                if self.pdo_is_configured(comm) and (comm + 0x200) not in created:
                    self.pdo_block(comm)
        return self.sel

    def _data_column(self, es) -> list[bytes]:
        """The data bytes of the entries ``es``, as group 1 writes them: an entry's value
        is looked up in the device's cache of encodings (``Device.encode`` fills it, and
        leaves out a value that warns, so that each entry warns); the same type and value
        text as the entry before (the same objects: a run of variables built from one
        template) is the same bytes, without a lookup."""
        dev = self.dev
        encoded = dev.encoded.get
        out = []
        append = out.append
        last_dtype = last_text = last_data = None
        for e in es:
            dtype = e.dtype
            if dtype is None:
                append(b"")     # the model already reported the DataType
                continue
            text = e.param
            if text is None and e.download_file is None:
                text = e.default
            if text is last_text and dtype is last_dtype and text is not None:
                append(last_data)
                continue
            data = encoded((dtype.code, text)) if text is not None else None
            if data is None:
                try:
                    data = dev.encode(e)
                except DcfError as exc:
                    self.error(exc)
                    data = b""
            else:
                last_dtype, last_text, last_data = dtype, text, data
            append(data)
        return out

    def pdo_is_configured(self, comm: int) -> bool:
        for idx in (comm, comm + 0x200):
            obj = self.dev.objects.get(idx)
            if obj is not None and any(self.counts(e) for e in obj.entries.values()):
                return True
        return False

    def check_pairs(self) -> None:
        """Every comm object needs its mapping object; a configured mapping its comm."""
        dev = self.dev
        for idx, obj in sorted(dev.objects.items()):
            if is_pdo_comm(idx) and (idx + 0x200) not in dev.objects:
                self.error(f"PDO communication object 0x{idx:04X} has no mapping object "
                           f"0x{idx + 0x200:04X}", obj.where, "DCF401")
            elif is_pdo_mapping(idx) and (idx - 0x200) not in dev.objects and any(
                    self.counts(e) for e in obj.entries.values()):
                self.error(f"configured PDO mapping object 0x{idx:04X} has no communication "
                           f"object 0x{idx - 0x200:04X}", obj.where, "DCF402")

    def pdo_block(self, comm_idx: int) -> None:
        dev = self.dev
        comm = dev.objects[comm_idx]
        mapping = dev.objects.get(comm_idx + 0x200)
        if mapping is None:
            return  # reported by check_pairs
        if self.pdo_sequence == NONE:
            for obj in (comm, mapping):
                for e in obj.entries.values():
                    if self.counts(e):
                        self.write(e)
            return
        cob = comm.entries.get(1)
        if cob is None:
            self.error(f"PDO 0x{comm_idx:04X} has no COB-ID (sub 1)", comm.where, "DCF403")
            return
        if cob.dtype is None or cob.dtype.code != dt.UNSIGNED32.code:
            self.error(f"{cob.label}: the COB-ID must be UNSIGNED32", cob.key_where("datatype"),
                       "DCF403")
            return
        try:
            final = dev.effective_int(cob)
        except DcfError as exc:
            self.error(exc)
            return
        # a) disable (D-12: under the old COB-ID first when the CAN-ID changes)
        if self.rules.old_cob_first:
            try:
                old = dev.default_int(cob)
            except DcfError as exc:
                self.error(exc)
                return
            if old is not None and (old ^ final) & CAN_ID_MASK:
                self.write(cob, (old | self.rules.disable_mask).to_bytes(4, "little"))
        self.write(cob, (final | self.rules.disable_mask).to_bytes(4, "little"))
        # b) transmission type, inhibit time, event timer, SYNC start
        for s in (2, 3, 5, 6):
            e = comm.entries.get(s)
            if e is not None and self.counts(e) and not e.obj_flags & 1:
                self.write(e)
        # c) d) e) mapping
        unstated = unstated_mapping_count(mapping)
        if unstated is not None:   # a guess (docs/compile.md, choice 9)
            self.error(unstated[1], unstated[0], "DCF419")
            return
        sub0 = mapping.entries.get(0)
        try:
            n = dev.effective_int(sub0) if sub0 is not None else 0
        except DcfError as exc:
            self.error(exc)
            return
        if n < 0:  # a signed sub 0 type (lint reports the type itself)
            self.error(f"{sub0.label}: {n} mapped objects is negative", sub0.value_where,
                       "DCF417")
            return
        if n > self.rules.max_mapped:
            self.error(f"{sub0.label}: {n} mapped objects, more than {self.rules.max_mapped}",
                       sub0.value_where,
                       "DCF409" if self.rules.max_mapped == MAX_MAPPED else "DCF450")
            return
        size0 = sub0.dtype.size if sub0.dtype and sub0.dtype.size else 1
        self.write(sub0, (0).to_bytes(size0, "little"))
        for k in range(1, n + 1):
            e = mapping.entries.get(k)
            if e is None:
                self.error(f"PDO mapping 0x{mapping.index:04X} maps {n} objects but has no "
                           f"sub {k}", sub0.value_where, "DCF417")
                continue
            self.write(e)
        self.write(sub0, n.to_bytes(size0, "little"))
        # f) enable
        if not final & COB_INVALID:
            self.write(cob, (final | self.rules.enable_mask).to_bytes(4, "little"))


def select(dev: Device, *, policy: str = AUTO, pdo_sequence: str = CIA301,
           static_od: set[int] | None = None, rules: PdoRules | None = None) -> Selection:
    return _Selector(dev, policy, pdo_sequence, static_od, rules or PdoRules()).run()

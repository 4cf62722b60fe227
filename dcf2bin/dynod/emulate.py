"""A deterministic model of the target's ``DynBuildOd()`` (SPEC §8, D-11).

``emulate(container, options, static, sources)`` runs the steps of SPEC §8.2 in order
and stops at the first failure, like the target: structure (0xA1), PI memory (0xA0),
then the index entries one by one with create/write and the CiA 301 PDO semantics.

Speed: a PLC container creates tens of thousands of network variables. The engine
keeps one small tuple per written entry, ``(attr, data, static entry)``, in a dict per
index; the public ``TargetEntry`` objects of ``Outcome.od`` are built only when asked for.
"""
from __future__ import annotations

import gc
from dataclasses import dataclass, field

from dcf2bin import datatypes as dt
from dcf2bin.indexes import NV_FIRST, NV_LAST
from dcf2bin.dynod import codes as C

RX, TX = "rx", "tx"
_NUMERIC_OR_BOOL = dt.ATTR_NUMERIC | dt.ATTR_BOOLEAN
_OUTPUT_FIRST = 0xA480      # CiA 405: A000-A47F inputs, A480-A8FF outputs


@dataclass
class TargetOptions:
    """What the firmware was built with (seed 000 §4) and what it gives (SPEC §8.1)."""
    pi_size: int | None = None        # m_dwProcessImageSize; None = unlimited
    tx_cobs: int | None = None        # PDO entries of the TX COB table; None = unlimited
    rx_cobs: int | None = None
    granularity: int = 64             # PDO_GRANULARITY (8 or 64)
    bit_mapping: bool = True          # PDO_USE_BIT_MAPPING
    address_base: str = "image"       # D-10: "image" or "area"


@dataclass(slots=True)
class TargetEntry:
    index: int
    sub: int
    data: bytes
    dtype: dt.DataType | None
    kind: str                 # "bool", "numeric", "vstring" or "domain"
    readable: bool
    writable: bool
    mappable: bool
    pi_address: int | None = None     # image address of a placed network variable
    created: bool = False             # created by the container (not in the static OD)
    written: bool = False             # written by the container

    @property
    def access(self) -> str:
        """The AccessType this entry has after DynBuildOd: rw, wo, or ro (also for an
        attribute byte with neither READ nor WRITE: such an entry is never written)."""
        if self.readable and self.writable:
            return "rw"
        return "wo" if self.writable else "ro"


@dataclass
class Pdo:
    direction: str            # "rx" or "tx"
    comm_index: int
    cob_id: int               # the COB-ID as last written (bit 31 clear)
    mapped: list[tuple[int, int, int, int | None]]   # (index, sub, bits, PI address)

    @property
    def can_id(self) -> int:
        return self.cob_id & 0x3FFFFFFF

    @property
    def bits(self) -> int:
        return sum(m[2] for m in self.mapped)


@dataclass
class Descriptor:
    """tProcessImageDscrpt: IN the PI memory the caller gives, OUT the five numbers."""
    memory: int | None                                  # IN m_dwProcessImageSize (None: unlimited)
    out: tuple[int, int, int, int, int] | None = None   # size, in off, in size, out off, out size


@dataclass
class Created:
    objects: list[int] = field(default_factory=list)   # indexes the container created
    entries: int = 0
    bytes: int = 0


@dataclass
class Outcome:
    code: int
    reason: str = ""
    entry: int | None = None          # 1-based position in the index segment
    index: int | None = None
    subindex: int | None = None
    offset: int | None = None         # byte offset of the entry in the container
    where: str | None = None          # DCF file:line that produced the entry
    value: bytes | None = None        # the failing entry's data
    step: str = ""                    # "structure", "memory", "entries" or "" (success)
    warnings: list[str] = field(default_factory=list)
    descriptor: Descriptor | None = None
    created: Created = field(default_factory=Created)
    pdos: list[Pdo] = field(default_factory=list)
    entries_applied: int = 0
    _engine: _Engine | None = field(default=None, repr=False)
    _od: dict | None = field(default=None, repr=False)

    @property
    def name(self) -> str:
        return C.name(self.code)

    @property
    def ok(self) -> bool:
        return self.code == C.OK

    @property
    def rule(self) -> str:
        return C.rule_id(self.code)

    @property
    def label(self) -> str | None:
        if self.index is None:
            return None
        return f"0x{self.index:04X}sub{self.subindex:X}"

    @property
    def od(self) -> dict[int, dict[int, TargetEntry]]:
        """The object dictionary after DynBuildOd (up to the failing entry): static,
        created and written entries (built on first use)."""
        if self._od is None:
            self._od = self._engine.build_od() if self._engine is not None else {}
        return self._od


class _Fail(Exception):
    def __init__(self, code: int, reason: str, pos: int | None = None):
        super().__init__(reason)
        self.code, self.reason, self.pos = code, reason, pos


def can_id_problem(cob: int) -> str | None:
    """Why a COB-ID's CAN-ID is not legal for a PDO (CiA 301), or None."""
    if cob & 0x20000000:
        return None                                 # 29-bit frame: any identifier
    if cob & 0x1FFFF800:
        return "an 11-bit COB-ID with bits 11-28 set"
    cid = cob & 0x7FF
    for lo, hi in _RESTRICTED:
        if lo <= cid <= hi:
            return f"CAN-ID 0x{cid:03X} is restricted by CiA 301 (0x{lo:03X}-0x{hi:03X})" \
                if lo != hi else f"CAN-ID 0x{cid:03X} is restricted by CiA 301"
    return None


_RESTRICTED = ((0x000, 0x000), (0x001, 0x07F), (0x101, 0x180), (0x581, 0x5FF), (0x601, 0x67F),
               (0x6E0, 0x6FF), (0x701, 0x77F), (0x780, 0x7FF))


def _le(data: bytes) -> int:
    return int.from_bytes(data, "little")


def _dir(comm: int) -> str:
    return RX if comm < 0x1800 else TX


def _pdo_name(comm: int) -> str:
    base = 0x1400 if comm < 0x1800 else 0x1800
    return f"{'RPDO' if comm < 0x1800 else 'TPDO'}{comm - base + 1} (0x{comm:04X})"


class _Engine:
    def __init__(self, c, opts: TargetOptions, static, sources):
        self.c = c
        self.opts = opts
        self.static = static
        # unknown (no static OD) or partial: what it lacks may still be on the target
        self.partial = static is None or not static.complete
        self.sources = sources
        self.cur: dict[int, dict[int, tuple]] = {}
        self.created_objects: list[int] = []
        self.n_created = 0
        self.created_bytes = 0
        self.valid: dict[int, int] = {}                 # comm index -> CAN-ID
        self.owner: dict[tuple[str, int], int] = {}     # (direction, CAN-ID) -> comm index
        self.counts = {RX: 0, TX: 0}
        self.warned: dict[str, int] = {}
        self.nv_first: list[int] = []                   # positions of first NV occurrences
        self.image: list[int] | None = None             # image address per NV (address order)
        self.applied = 0
        self.creating: int | None = None                # the index the current entry creates

    # -- helpers ---------------------------------------------------------------------------
    def warn(self, key: str) -> None:
        self.warned[key] = self.warned.get(key, 0) + 1

    def exists_index(self, index: int) -> bool | None:
        """True/False, or None when the static OD is unknown and the container never
        wrote the index."""
        if index in self.cur or (self.static is not None and self.static.has(index)):
            return True
        return None if self.partial else False

    def record(self, index: int, sub: int):
        """(attr, data, static entry) of an entry as it stands, or None."""
        subs = self.cur.get(index)
        if subs is not None:
            rec = subs.get(sub)
            if rec is not None:
                return rec
        if self.static is not None:
            st = self.static.entry(index, sub)
            if st is not None:
                return (None, self.static.data(st), st)
        return None

    def int_of(self, index: int, sub: int) -> int | None:
        rec = self.record(index, sub)
        if rec is None or rec[1] is None:
            return None
        return _le(rec[1])

    # -- the steps -------------------------------------------------------------------------
    def run(self) -> Outcome:
        out = Outcome(C.OK, _engine=self)
        c = self.c
        out.descriptor = Descriptor(self.opts.pi_size, c.pi)
        try:
            out.step = "structure"
            self.structure()
            out.step = "memory"
            if c.pi is not None and self.opts.pi_size is not None \
                    and c.pi[0] > self.opts.pi_size:
                raise _Fail(C.NO_MEMORY, f"the process image needs {c.pi[0]} bytes, the target "
                                         f"gives {self.opts.pi_size}")
            out.step = "entries"
            self.entries()
            out.step = ""
        except _Fail as f:
            out.code, out.reason = f.code, f.reason
            if f.pos is not None:
                self.locate(out, f.pos)
                if out.step == "entries":
                    self.applied = f.pos
        out.entries_applied = self.applied
        out.created = Created(sorted(self.created_objects), self.n_created, self.created_bytes)
        out.warnings = self.warning_texts()
        if out.ok:
            out.pdos = self.pdos()
        return out

    def locate(self, out: Outcome, pos: int) -> None:
        index, sub, data = self.c.entries[pos]
        out.entry, out.index, out.subindex, out.value = pos + 1, index, sub, data
        from dcf2bin.dump import header_of
        h = header_of(self.c)
        off = h["index_offset"] + 4
        for _, _, d in self.c.entries[:pos]:
            off += 7 + len(d)
        out.offset = off
        src = self.sources
        if src is not None:
            w = src(pos + 1) if callable(src) else src.get(pos + 1)
            out.where = None if w is None else str(w)

    def structure(self) -> None:
        c = self.c
        entries = c.entries
        n = len(entries)
        if c.attributes is not None and len(c.attributes) != n:
            raise _Fail(C.INVALID_CONFIG, f"the extended info segment has {len(c.attributes)} "
                                          f"attribute bytes for {n} index entries")
        # first occurrence of each network variable (SPEC §3.4): built in C -- a dict from
        # the reversed keys keeps, for every key, the smallest position
        keys = [index << 8 | sub if NV_FIRST <= index <= NV_LAST and sub else -1
                for index, sub, _ in entries]
        firsts = dict(zip(reversed(keys), range(n - 1, -1, -1)))
        firsts.pop(-1, None)
        first = self.nv_first
        first.extend(sorted(firsts.values()))
        addrs = c.addresses or None
        if addrs is not None and len(addrs) != len(first):
            raise _Fail(C.INVALID_CONFIG, f"the PI address segment holds {len(addrs)} "
                                          f"addresses for {len(first)} network variables")
        if c.raw_piparam is not None:
            raise _Fail(C.INVALID_CONFIG, f"the PI parameter segment has {len(c.raw_piparam)} "
                                          "bytes, not 20")
        pi = c.pi
        if pi is not None:
            total, in_off, in_size, out_off, out_size = pi
            if in_off + in_size > total:
                raise _Fail(C.INVALID_CONFIG, f"the input area [{in_off}, {in_off + in_size}) "
                                              f"lies beyond the PI size {total}")
            if out_off + out_size > total:
                raise _Fail(C.INVALID_CONFIG, f"the output area [{out_off}, "
                                              f"{out_off + out_size}) lies beyond the PI size "
                                              f"{total}")
        if addrs is None:
            return
        if self.opts.address_base == "area" and pi is not None:
            image = [a + (pi[1] if entries[p][0] < _OUTPUT_FIRST else pi[3])
                     for a, p in zip(addrs, first)]
        else:
            image = list(addrs)
        self.image = image
        sizes = [len(entries[p][2]) for p in first]
        total = pi[0] if pi is not None else None
        # variable by variable in address order: beyond the image, then overlapping an
        # earlier one; a byte map of the image answers "is any of these bytes taken?" in C
        taken = bytearray(max(a + z for a, z in zip(image, sizes)) if image else 0)
        find = taken.find
        ones = b"\x01" * 16
        for i, a in enumerate(image):
            z = sizes[i]
            e = a + z
            if total is not None and e > total:
                raise _Fail(C.INVALID_CONFIG, f"network variable at PI address {a} with "
                                              f"{z} bytes ends beyond the PI size {total}",
                            first[i])
            if z:
                if find(1, a, e) >= 0:
                    self.overlap(i, image, sizes)
                taken[a:e] = ones[:z] if z <= 16 else b"\x01" * z

    def overlap(self, i: int, image: list[int], sizes: list[int]) -> None:
        a, e = image[i], image[i] + sizes[i]
        for j in range(i):
            b, f = image[j], image[j] + sizes[j]
            if sizes[j] and b < e and a < f:
                q = self.first_entry(j)
                raise _Fail(C.INVALID_CONFIG,
                            f"PI bytes {a}..{e - 1} overlap those of "
                            f"0x{q[0]:04X}sub{q[1]:X} ({b}..{f - 1})", self.nv_first[i])

    def first_entry(self, i: int) -> tuple:
        return self.c.entries[self.nv_first[i]]

    # -- step 3 ----------------------------------------------------------------------------
    def entries(self) -> None:
        """Entry by entry: check it (existence, size, PDO semantics), then apply it. A
        failing entry is not applied."""
        attrs = self.c.attributes
        static = self.static
        cur = self.cur
        last = None
        subs = sdict = None
        no_static: dict = {}
        for pos, (index, sub, data) in enumerate(self.c.entries):
            if index != last:           # entries come in runs of one index: look it up once
                last = index
                subs = cur.get(index)
                sdict = static.entries(index) if static is not None else no_static
            rec = subs.get(sub) if subs is not None else None
            create = False
            if rec is None:
                st = sdict.get(sub)
                if st is not None:
                    fixed = static.fixed_size(st)
                    if fixed is not None and len(data) != fixed:
                        raise _Fail(C.INVALID_CONFIG, f"{len(data)} data bytes written into a "
                                                      f"{st.dtype.name} of {fixed} bytes", pos)
                    new = (None, data, st)
                elif attrs is not None:
                    new = (attrs[pos], data, None)
                    create = True
                elif self.partial:
                    self.warn("assumed")
                    new = (None, data, None)
                elif subs is None and not static.has(index):
                    raise _Fail(C.INDEX_NOT_EXIST, f"object 0x{index:04X} does not exist and "
                                "cannot be created without an extended info segment", pos)
                else:
                    raise _Fail(C.SUBINDEX_NOT_EXIST, f"0x{index:04X} has no sub {sub} and it "
                                "cannot be created without an extended info segment", pos)
            else:
                attr, old, st = rec
                if st is not None:
                    fixed = static.fixed_size(st)
                    tname = st.dtype.name if fixed is not None else ""
                elif attr is not None and attr & _NUMERIC_OR_BOOL:
                    fixed = len(old)
                    tname = "BOOLEAN" if attr & dt.ATTR_BOOLEAN else "NUMERIC entry"
                else:
                    fixed = None
                if fixed is not None and len(data) != fixed:
                    raise _Fail(C.INVALID_CONFIG, f"{len(data)} data bytes written into a "
                                                  f"{tname} of {fixed} bytes", pos)
                if attr is not None and st is None:
                    self.created_bytes += len(data) - len(old)
                new = (attr, data, st)
            if 0x1400 <= index <= 0x1BFF:
                self.creating = index if create else None
                self.pdo_write(pos, index, sub, data)
            if subs is None:
                subs = cur[index] = {}
                if create and (static is None or not static.has(index)):
                    self.created_objects.append(index)
            if create:
                self.n_created += 1
                self.created_bytes += len(data)
            subs[sub] = new
        self.applied = len(self.c.entries)

    # -- CiA 301 PDO semantics -------------------------------------------------------------
    def pdo_write(self, pos: int, index: int, sub: int, data: bytes) -> None:
        if index < 0x1600 or 0x1800 <= index < 0x1A00:
            if sub == 1:
                self.cob_write(pos, index, _le(data))
            return
        comm = index - 0x200
        value = _le(data)
        if sub == 0:
            if comm in self.valid:
                raise _Fail(C.PDO_MAPPING, f"the mapping of {_pdo_name(comm)} is changed while "
                                           "the PDO is valid (set COB-ID bit 31 first)", pos)
            if value:
                self.check_mapping(pos, index, value)
            return
        n = self.int_of(index, 0) or 0
        if n:
            raise _Fail(C.PDO_MAPPING, f"mapping entry written while sub 0 is {n} (write sub 0 "
                                       "= 0 first)", pos)
        if value:
            self.check_mapped(pos, value, _dir(comm))

    def cob_write(self, pos: int, comm: int, cob: int) -> None:
        d = _dir(comm)
        if cob & 0x80000000:
            can = self.valid.pop(comm, None)
            if can is not None:
                self.owner.pop((d, can), None)
                self.counts[d] -= 1
            return
        mapping = comm + 0x200
        has = self.exists_index(mapping)
        if has is None:
            self.warn(f"mapping:{mapping:04X}")
        elif not has:
            raise _Fail(C.INDEX_NOT_EXIST, f"{_pdo_name(comm)} becomes valid but its mapping "
                                           f"object 0x{mapping:04X} does not exist", pos)
        problem = can_id_problem(cob)
        if problem:
            raise _Fail(C.ILLEGAL_CAN_ID, f"{_pdo_name(comm)}: {problem}", pos)
        can = cob & 0x3FFFFFFF
        old = self.valid.get(comm)
        if old is not None and old != can:
            raise _Fail(C.ILLEGAL_CAN_ID, f"{_pdo_name(comm)} is valid with CAN-ID 0x{old:X}; "
                                          "a valid PDO may not change its CAN-ID (set bit 31 "
                                          "first)", pos)
        other = self.owner.get((d, can))
        if other is not None and other != comm:
            raise _Fail(C.COB_EXISTS, f"CAN-ID 0x{can:X} is already used by valid "
                                      f"{_pdo_name(other)}", pos)
        if old is None:
            limit = self.opts.rx_cobs if d == RX else self.opts.tx_cobs
            if limit is not None and self.counts[d] + 1 > limit:
                raise _Fail(C.NO_FREE_COB, f"{_pdo_name(comm)} would be valid {d.upper()} PDO "
                                           f"number {self.counts[d] + 1}; the target's "
                                           f"{d.upper()} COB table holds {limit}", pos)
            self.counts[d] += 1
        self.valid[comm] = can
        self.owner[(d, can)] = comm

    def mapped_object(self, value: int, direction: str):
        """(bits of the object, reason it cannot be mapped or None, code); None when the
        object cannot be checked (unknown static OD)."""
        m_idx, m_sub, bits = value >> 16, (value >> 8) & 0xFF, value & 0xFF
        label = f"0x{m_idx:04X}sub{m_sub:X}"
        if 1 <= m_idx <= 7 and m_sub == 0:                          # dummy entries
            t = dt.BY_CODE[m_idx]
            return self.length_problem(label, t.kind == dt.BOOL, t.bits, bits, True, True, True,
                                       direction)
        rec = self.record(m_idx, m_sub)
        if rec is None:
            if self.partial and m_idx not in self.created_objects:
                self.warn(f"mapped:{label}")
                return None
            if self.exists_index(m_idx):
                return C.SUBINDEX_NOT_EXIST, f"the mapped object {label} does not exist (no " \
                                             f"sub {m_sub} in 0x{m_idx:04X})"
            return C.INDEX_NOT_EXIST, f"the mapped object 0x{m_idx:04X} does not exist"
        attr, data, st = rec
        if st is not None:
            t = st.dtype
            obits = t.bits if t is not None and t.size is not None else len(data or b"") * 8
            is_bool = t is not None and t.kind == dt.BOOL
            return self.length_problem(label, is_bool, obits, bits, st.pdo_mapping,
                                       st.access in dt.READABLE, st.access in dt.WRITABLE,
                                       direction)
        if attr is None:
            self.warn(f"mapped:{label}")
            return None
        return self.length_problem(label, bool(attr & dt.ATTR_BOOLEAN), len(data) * 8, bits,
                                   bool(attr & dt.ATTR_PDO), bool(attr & dt.ATTR_READ),
                                   bool(attr & dt.ATTR_WRITE), direction)

    def length_problem(self, label, is_bool, obits, bits, mappable, readable, writable,
                       direction):
        if not mappable:
            return C.PDO_MAPPING, f"{label} is not PDO-mappable"
        if direction == RX and not writable:
            return C.PDO_MAPPING, f"{label} is not writable, so an RPDO cannot map it"
        if direction == TX and not readable:
            return C.PDO_MAPPING, f"{label} is not readable, so a TPDO cannot map it"
        if is_bool:
            if bits == 1 and not self.opts.bit_mapping:
                return C.PDO_MAPPING, f"{label} is a BOOLEAN mapped with 1 bit, and the target " \
                                      "has no bit mapping"
            if bits not in (1, 8):
                return C.PDO_MAPPING, f"{label} is a BOOLEAN mapped with {bits} bits (1 or 8)"
        elif bits != obits:
            return C.PDO_MAPPING, f"{label} has {obits} bits, the mapping says {bits}"
        if self.opts.granularity == 8 and bits % 8:
            return C.PDO_MAPPING, f"{label} is mapped with {bits} bits, and the target maps " \
                                  "whole bytes only (granularity 8)"
        return None

    def check_mapped(self, pos: int, value: int, direction: str) -> None:
        problem = self.mapped_object(value, direction)
        if problem is not None:
            raise _Fail(problem[0], problem[1], pos)

    def check_mapping(self, pos: int, index: int, n: int) -> None:
        total = 0
        for k in range(1, n + 1):
            rec = self.record(index, k)
            if rec is None:
                if self.partial and index not in self.cur and index != self.creating:
                    self.warn(f"mapping:{index:04X}")
                    continue
                raise _Fail(C.SUBINDEX_NOT_EXIST, f"sub 0 = {n}, but the mapping has no "
                                                  f"sub {k}", pos)
            bits = _le(rec[1] or b"") & 0xFF
            if self.opts.granularity == 8 and total % 8:
                raise _Fail(C.PDO_MAPPING, f"mapping entry {k} starts at bit {total}; the "
                                           "target maps whole bytes only (granularity 8)", pos)
            total += bits
        if total > 64:
            raise _Fail(C.PDO_MAPPING, f"the {n} mapped objects have {total} bits, more than "
                                       "the 64 of a CAN frame", pos)

    # -- results ---------------------------------------------------------------------------
    def nv_addresses(self) -> dict[tuple[int, int], int]:
        if self.image is None:
            return {}
        entries = self.c.entries
        return {entries[p][:2]: a for p, a in zip(self.nv_first, self.image)}

    def pdos(self) -> list[Pdo]:
        out = []
        addrs = None
        for comm in sorted(self.valid):
            mapping = comm + 0x200
            n = self.int_of(mapping, 0) or 0
            mapped = []
            for k in range(1, n + 1):
                v = self.int_of(mapping, k)
                if v is None:
                    continue
                m_idx, m_sub, bits = v >> 16, (v >> 8) & 0xFF, v & 0xFF
                addr = None
                if NV_FIRST <= m_idx <= NV_LAST and m_sub:
                    if addrs is None:
                        addrs = self.nv_addresses()
                    addr = addrs.get((m_idx, m_sub))
                mapped.append((m_idx, m_sub, bits, addr))
            cob = self.int_of(comm, 1)
            out.append(Pdo(_dir(comm), comm, cob if cob is not None else self.valid[comm],
                           mapped))
        return out

    def warning_texts(self) -> list[str]:
        out = []
        w = self.warned
        if "assumed" in w:
            n = w["assumed"]
            out.append(f"{n} entr{'y' if n == 1 else 'ies'} could not be checked: no extended "
                       "info segment and no static OD, so they are assumed to exist")
        for key in sorted(k for k in w if k.startswith("mapping:")):
            out.append(f"PDO mapping object 0x{key[8:]} is not in the container and the static "
                       "OD is unknown: not checked (give --static-od)")
        for key in sorted(k for k in w if k.startswith("mapped:")):
            out.append(f"mapped object {key[7:]} is not in the container and the static OD is "
                       "unknown: its existence, access and length were not checked "
                       "(give --static-od)")
        return out

    def build_od(self) -> dict[int, dict[int, TargetEntry]]:
        od: dict[int, dict[int, TargetEntry]] = {}
        static = self.static
        if static is not None:
            for index in static.indexes():
                subs = od[index] = {}
                for sub, st in static.entries(index).items():
                    subs[sub] = _from_static(st, static.data(st) or b"", False)
        addrs = self.nv_addresses()
        created = set(self.created_objects)
        for index in sorted(self.cur):
            subs = od.setdefault(index, {})
            for sub, (attr, data, st) in self.cur[index].items():
                if st is not None:
                    te = _from_static(st, data, True)
                else:
                    te = _from_attr(index, sub, attr, data, index in created or attr is not None)
                    te.pi_address = addrs.get((index, sub))
                subs[sub] = te
        return {i: dict(sorted(s.items())) for i, s in sorted(od.items())}


def _from_static(st, data: bytes, written: bool) -> TargetEntry:
    t = st.dtype
    return TargetEntry(st.index, st.sub, data, t, _kind(t), st.access in dt.READABLE,
                       st.access in dt.WRITABLE, st.pdo_mapping, None, False, written)


def _kind(t: dt.DataType | None) -> str:
    if t is None:
        return "domain"
    if t.kind == dt.BOOL:
        return "bool"
    if t.kind == dt.VSTRING:
        return "vstring"
    return "numeric" if t.is_numeric else "domain"


def _from_attr(index: int, sub: int, attr: int | None, data: bytes, created: bool) -> TargetEntry:
    if attr is None:                    # assumed to exist (unknown static OD)
        return TargetEntry(index, sub, data, None, "domain", True, True, False, None, False, True)
    if attr & dt.ATTR_BOOLEAN:
        t, kind = dt.BOOLEAN, "bool"
    elif attr & dt.ATTR_VSTRING:
        t, kind = dt.VISIBLE_STRING, "vstring"
    elif attr & dt.ATTR_NUMERIC:
        t, kind = _numeric_type(index, sub, len(data)), "numeric"
    else:
        t, kind = dt.DOMAIN_T, "domain"
    return TargetEntry(index, sub, data, t, kind, bool(attr & dt.ATTR_READ),
                       bool(attr & dt.ATTR_WRITE), bool(attr & dt.ATTR_PDO), None, created, True)


def _numeric_type(index: int, sub: int, size: int) -> dt.DataType | None:
    if NV_FIRST <= index <= NV_LAST and sub:
        from dcf2bin.layout import table_channel
        ch = table_channel(index)
        if ch is not None and ch.dtype.size == size:
            return ch.dtype
    return dt.UNSIGNED_BY_SIZE.get(size)


def emulate(container, options: TargetOptions | None = None, static=None,
            sources=None) -> Outcome:
    """Run DynBuildOd on ``container`` (a ``BinContainer``). ``static``: a ``StaticOD`` or
    None (unknown, SPEC §8.1); ``sources``: 1-based entry position -> DCF file:line (a
    mapping with ``get``, or a callable)."""
    # like compile_path: tens of thousands of small tuples and no cycles worth collecting
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        return _Engine(container, options or TargetOptions(), static, sources).run()
    finally:
        if was_enabled:
            gc.enable()


def emulate_bytes(data: bytes, options: TargetOptions | None = None, static=None) -> Outcome:
    """Read a container and emulate it; a container the reader rejects is 0xA1."""
    from dcf2bin.container import ContainerError, read
    try:
        c, _ = read(data)
    except ContainerError as exc:
        return Outcome(C.INVALID_CONFIG, str(exc), offset=exc.offset, step="structure",
                       descriptor=Descriptor(options.pi_size if options else None))
    return emulate(c, options, static)


__all__ = [
    "Created",
    "Descriptor",
    "Outcome",
    "Pdo",
    "TargetEntry",
    "TargetOptions",
    "can_id_problem",
    "emulate",
    "emulate_bytes",
]

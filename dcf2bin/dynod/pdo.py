"""The CiA 301 PDO semantics of the DynBuildOd emulation (communication and mapping).
"""
from __future__ import annotations

from dcf2bin import datatypes as dt
from dcf2bin.dynod import codes as C
from dcf2bin.dynod.outcome import _dir, _Fail, _le, _pdo_name, can_id_problem, RX, TX


def _label(key: tuple[int, int]) -> str:
    """``0x1A00sub1``: a mapped object as the messages name it."""
    return f"0x{key[0]:04X}sub{key[1]:X}"


class _PdoSemantics:
    """The CiA 301 PDO semantics ``_Engine`` applies to a write: COB-ID and mapping rules."""

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
            self.warn(("mapping", mapping), pos)
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

    def mapped_object(self, value: int, direction: str, pos: int | None = None):
        """(bits of the object, reason it cannot be mapped or None, code); None when the
        object cannot be checked (unknown static OD)."""
        m_idx, m_sub, bits = value >> 16, (value >> 8) & 0xFF, value & 0xFF
        key = (m_idx, m_sub)
        if 1 <= m_idx <= 7 and m_sub == 0:                          # dummy entries
            t = dt.BY_CODE[m_idx]
            return self.length_problem(key, t.kind == dt.BOOL, t.bits, bits, True, True, True,
                                       direction)
        rec = self.record(m_idx, m_sub)
        if rec is None:
            if self.partial and not self.made_here(m_idx):
                self.warn(("mapped", m_idx, m_sub), pos)
                return None
            if self.exists_index(m_idx):
                return C.SUBINDEX_NOT_EXIST, f"the mapped object 0x{m_idx:04X}sub{m_sub:X} " \
                                             f"does not exist (no sub {m_sub} in 0x{m_idx:04X})"
            return C.INDEX_NOT_EXIST, f"the mapped object 0x{m_idx:04X} does not exist"
        attr, data, st = rec
        if st is not None:
            t = st.dtype
            obits = t.bits if t is not None and t.size is not None else len(data or b"") * 8
            is_bool = t is not None and t.kind == dt.BOOL
            return self.length_problem(key, is_bool, obits, bits, st.pdo_mapping,
                                       st.access in dt.READABLE, st.access in dt.WRITABLE,
                                       direction)
        if attr is None:            # written earlier without an attribute byte
            self.warn(("mapped-untyped", m_idx, m_sub), pos)
            return None
        return self.length_problem(key, bool(attr & dt.ATTR_BOOLEAN), len(data) * 8, bits,
                                   bool(attr & dt.ATTR_PDO), bool(attr & dt.ATTR_READ),
                                   bool(attr & dt.ATTR_WRITE), direction)

    def length_problem(self, key, is_bool, obits, bits, mappable, readable, writable,
                       direction):
        """Why the object ``key`` (index, sub) cannot be mapped with ``bits``, or None (its
        label is made only for a message)."""
        if not mappable:
            return C.PDO_MAPPING, f"{_label(key)} is not PDO-mappable"
        if direction == RX and not writable:
            return C.PDO_MAPPING, f"{_label(key)} is not writable, so an RPDO cannot map it"
        if direction == TX and not readable:
            return C.PDO_MAPPING, f"{_label(key)} is not readable, so a TPDO cannot map it"
        if is_bool:
            if bits == 1 and not self.opts.bit_mapping:
                return C.PDO_MAPPING, f"{_label(key)} is a BOOLEAN mapped with 1 bit, and " \
                                      "the target has no bit mapping"
            if bits not in (1, 8):
                return C.PDO_MAPPING, f"{_label(key)} is a BOOLEAN mapped with {bits} bits " \
                                      "(1 or 8)"
        elif bits != obits:
            return C.PDO_MAPPING, f"{_label(key)} has {obits} bits, the mapping says {bits}"
        if self.opts.granularity == 8 and bits % 8:
            return C.PDO_MAPPING, f"{_label(key)} is mapped with {bits} bits, and the " \
                                  "target maps whole bytes only (granularity 8)"
        return None

    def check_mapped(self, pos: int, value: int, direction: str) -> None:
        problem = self.mapped_object(value, direction, pos)
        if problem is not None:
            raise _Fail(problem[0], problem[1], pos)

    def check_mapping(self, pos: int, index: int, n: int) -> None:
        total = 0
        for k in range(1, n + 1):
            rec = self.record(index, k)
            if rec is None:
                if self.partial and not self.made_here(index):
                    self.warn(("mapping-sub", index, k), pos)
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

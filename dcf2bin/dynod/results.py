"""The results of a DynBuildOd emulation: NV addresses, PDOs, warnings, the created OD.
"""
from __future__ import annotations

from operator import itemgetter

from dcf2bin import datatypes as dt
from dcf2bin.dynod.outcome import _dir, Pdo, TargetEntry
from dcf2bin.indexes import NV_FIRST, NV_LAST


_INDEX_SUB = itemgetter(slice(0, 2))     # (index, sub, data) -> (index, sub)


class _Results:
    """What ``_Engine`` reports after a run: NV addresses, PDOs, warnings, the created OD."""

    # -- results ---------------------------------------------------------------------------
    def nv_addresses(self) -> dict[tuple[int, int], int]:
        if self.image is None:
            return {}
        # (index, sub) of each first occurrence -> its address, built in C
        keys = map(_INDEX_SUB, map(self.c.entries.__getitem__, self.nv_first))
        return dict(zip(keys, self.image))

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

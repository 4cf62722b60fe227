"""The results of a DynBuildOd emulation: NV addresses, PDOs, warnings, the created OD.
"""
from __future__ import annotations

from bisect import bisect_left, bisect_right
from itertools import compress
from operator import itemgetter

from dcf2bin import datatypes as dt
from dcf2bin.dynod import codes as C
from dcf2bin.dynod.outcome import _dir, _pdo_name, Pdo, TargetEntry, TargetWarning
from dcf2bin.indexes import NV_FIRST, NV_LAST


_INDEX_SUB = itemgetter(slice(0, 2))     # (index, sub, data) -> (index, sub)
_INDEX = itemgetter(0)


def _key_at(entries):
    """position -> the key of the entry there (index << 8 | sub), for bisection."""
    def key_at(pos: int) -> int:
        index, sub, _ = entries[pos]
        return index << 8 | sub
    return key_at


class _Results:
    """What ``_Engine`` reports after a run: NV addresses, PDOs, warnings, the created OD."""

    # -- results ---------------------------------------------------------------------------
    def nv_addresses(self, wanted: set | None = None) -> dict[tuple[int, int], int]:
        """(index, sub) of each network variable's first occurrence -> its PI address;
        only the keys in ``wanted`` when given (a few mapped variables: no dict of every
        variable, 60,000 tuples at a compile's peak of memory): bisected when the keys
        ascend (a compiled container), else those of the wanted objects looked at."""
        if self.image is None:
            return {}
        get = self.c.entries.__getitem__
        if wanted is None:
            return dict(zip(map(_INDEX_SUB, map(get, self.nv_first)), self.image))
        first, image = self.nv_first, self.image
        out = {}
        if self.nv_ascending:
            # a compiled container's variables, by ascending key: each one bisected
            key_at = _key_at(self.c.entries)
            for key in wanted:
                i = bisect_left(first, key[0] << 8 | key[1], key=key_at)
                if i < len(first) and _INDEX_SUB(get(first[i])) == key:
                    out[key] = image[i]
            return out
        # the variables of the objects the wanted ones are in, told by their index alone
        # (no tuple per variable); then only those are looked at one by one
        indexes = {index for index, _ in wanted}
        near = compress(range(len(first)), map(indexes.__contains__, map(_INDEX, map(get, first))))
        for i in near:
            key = _INDEX_SUB(get(first[i]))
            if key in wanted:
                out[key] = image[i]
        return out

    def pdos(self) -> list[Pdo]:
        rows = []
        wanted = set()          # the network variables mapped, for their addresses
        for comm in sorted(self.valid):
            mapping = comm + 0x200
            n = self.int_of(mapping, 0) or 0
            mapped = []
            for k in range(1, n + 1):
                v = self.int_of(mapping, k)
                if v is None:
                    continue
                m_idx, m_sub, bits = v >> 16, (v >> 8) & 0xFF, v & 0xFF
                if NV_FIRST <= m_idx <= NV_LAST and m_sub:
                    wanted.add((m_idx, m_sub))
                mapped.append((m_idx, m_sub, bits))
            rows.append((comm, mapped))
        addrs = self.nv_addresses(wanted) if wanted else {}
        out = []
        for comm, mapped in rows:
            cob = self.int_of(comm, 1)
            out.append(Pdo(_dir(comm), comm, cob if cob is not None else self.valid[comm],
                           [(i, s, bits, addrs.get((i, s))) for i, s, bits in mapped]))
        return out

    def warnings(self) -> list[TargetWarning]:
        """One warning per thing the model could not check (an unknown static OD), saying
        what it assumed and what the target answers when the assumption is wrong. Where the
        container does hold the object, but only at a later entry, the warning says so."""
        w = self.warned
        out = []
        if ("assumed",) in w:
            n = w[("assumed",)]
            out.append(TargetWarning(C.UNCHECKED_ENTRY, f"{n} entr{'y' if n == 1 else 'ies'} "
                                     "could not be checked: no extended info segment and no "
                                     "static OD, so they are assumed to exist"))
        if len(w) == len(out):
            return out
        later = _Later(self.c.entries)
        at = self.warned_at
        for key in sorted(k for k in w if k[0] == "mapping"):
            out.append(self._mapping_object_warning(key[1], at[key], later))
        subs: dict[int, list[int]] = {}
        for key in sorted(k for k in w if k[0] == "mapping-sub"):
            subs.setdefault(key[1], []).append(key[2])
        for index, ks in subs.items():
            pos = min(at[("mapping-sub", index, k)] for k in ks)
            some = "sub " + str(ks[0]) if len(ks) == 1 else \
                "subs " + ", ".join(str(k) for k in ks)
            out.append(TargetWarning(
                C.UNCHECKED_MAPPING_ENTRY,
                f"0x{index:04X} sub 0 at entry {pos + 1} counts {some}, which the container has "
                f"not written before it: taken to be in the static OD; the target answers "
                f"0x{C.SUBINDEX_NOT_EXIST:02X} {C.name(C.SUBINDEX_NOT_EXIST)} if "
                f"{'it is' if len(ks) == 1 else 'they are'} not (give --static-od)"))
        for key in sorted(k for k in w if k[0] in ("mapped", "mapped-untyped")):
            if key[0] == "mapped-untyped":
                out.append(TargetWarning(
                    C.UNCHECKED_MAPPED_OBJECT,
                    f"mapped object 0x{key[1]:04X}sub{key[2]:X} is written by the container "
                    "without an attribute byte and the static OD is unknown: its access and "
                    "length were not checked (give --static-od)"))
            else:
                out.append(self._mapped_object_warning(key[1], key[2], at[key], later))
        return out

    def _mapping_object_warning(self, mapping: int, pos: int, later) -> TargetWarning:
        q = later.index(mapping, pos)
        if q is None:
            text = f"PDO mapping object 0x{mapping:04X} is not in the container and the " \
                   "static OD is unknown: not checked (give --static-od)"
        else:
            text = f"{_pdo_name(mapping - 0x200)} is made valid at entry {pos + 1}, but the " \
                   f"container writes its mapping object 0x{mapping:04X} only at entry " \
                   f"{q + 1}: it is taken to be in the static OD; the target answers " \
                   f"0x{C.INDEX_NOT_EXIST:02X} {C.name(C.INDEX_NOT_EXIST)} if it is not"
        return TargetWarning(C.UNCHECKED_MAPPING_OBJECT, text)

    def _mapped_object_warning(self, index: int, sub: int, pos: int, later) -> TargetWarning:
        label = f"0x{index:04X}sub{sub:X}"
        q = later.entry(index, sub, pos)
        if q is None:
            text = f"mapped object {label} is not in the container and the static OD is " \
                   "unknown: its existence, access and length were not checked " \
                   "(give --static-od)"
        else:
            has = later.index_before(index, pos) or \
                (self.static is not None and self.static.has(index))
            code = C.SUBINDEX_NOT_EXIST if has else C.INDEX_NOT_EXIST
            text = f"mapped object {label} is mapped at entry {pos + 1}, but the container " \
                   f"writes it only at entry {q + 1}: it is taken to be in the static OD; " \
                   f"the target refuses the mapping (0x{code:02X} {C.name(code)}) if it is not"
        return TargetWarning(C.UNCHECKED_MAPPED_OBJECT, text)

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


class _Later:
    """Where the container writes an index or an entry, for the warnings (built once, only
    when a warning needs it)."""

    def __init__(self, entries):
        self.first_index: dict[int, list[int]] = {}
        self.first_entry: dict[tuple[int, int], list[int]] = {}
        for pos, (index, sub, _) in enumerate(entries):
            self.first_index.setdefault(index, []).append(pos)
            self.first_entry.setdefault((index, sub), []).append(pos)

    @staticmethod
    def _after(positions, pos):
        if positions:
            k = bisect_right(positions, pos)
            if k < len(positions):
                return positions[k]
        return None

    def index(self, index: int, pos: int) -> int | None:
        """The first position after ``pos`` that writes ``index``."""
        return self._after(self.first_index.get(index), pos)

    def entry(self, index: int, sub: int, pos: int) -> int | None:
        return self._after(self.first_entry.get((index, sub)), pos)

    def index_before(self, index: int, pos: int) -> bool:
        positions = self.first_index.get(index)
        return bool(positions) and positions[0] < pos

"""Reading a container into the objects its DCF will hold (bin2dcf, SPEC §4).

Writes are grouped per (index, subindex) in container order, so ``ParameterValue``
is the last value written and the earlier writes stay for the comments. Network
variables are typed from their range, placed by the PI addresses, and where they
do not sit where the CiA 405 table puts them a ``[DynamicChannels]`` section is
reconstructed (SPEC §2.3). ARRAY/RECORD objects without a written sub 0 get the
one the model would imply; values become ParameterValue texts in the file's
encoding (UTF-8, or Latin-1 when a string needs it; SPEC §1).
"""
from __future__ import annotations

from itertools import groupby, repeat
from operator import is_, itemgetter

from dcf2bin import concise
from dcf2bin import datatypes as dt
from dcf2bin.container import BinContainer
from dcf2bin.dcfwriter.entries import EntryTyper
from dcf2bin.dcfwriter.spec import (R_HEADER, R_PI, R_SELECT, R_VALUE, ChannelSpec, DcfSpec,
                                    Issues, ObjSpec, SubSpec, Write, by_size, short,
                                    table_type, value_text)
from dcf2bin.dump import EdsInfo, entry_offsets, header_of
from dcf2bin.layout import INPUT, OUTPUT, OUTPUT_FIRST, PER_INDEX, TABLE_END
from dcf2bin.model import NV_FIRST, NV_LAST
from dcf2bin.model import is_network_variable_index as is_nv


def read_spec(c: BinContainer, name: str, eds: EdsInfo | None = None, *,
              what: str = "container") -> DcfSpec:
    """The DCF objects of container ``c`` (``what`` "concise DCF": a concise DCF's entries,
    as ``c.entries``); warnings collect in the result's ``issues``."""
    return _Reader(c, name, eds, what).run()


class _Reader:
    def __init__(self, c: BinContainer, name: str, eds: EdsInfo | None,
                 what: str = "container"):
        if what == "container":
            header = header_of(c)
            offsets = entry_offsets(c, header)
        else:       # a concise DCF: its own size, its entries' offsets in the file
            header = {"total_size": concise.size_of(c.entries)}
            offsets = concise.offsets(c.entries)
        self.c = c
        self.spec = DcfSpec(c, name, header, offsets, Issues(name), what=what)
        self.issues = self.spec.issues
        self.eds = eds
        self.typer = EntryTyper(eds, self.issues, what)
        self.objects = self.spec.objects

    def run(self) -> DcfSpec:
        c = self.c
        attrs = c.attributes or b""
        n = len(c.entries)
        if not self.spec.concise:
            self._header_issues(n, attrs)
        offsets = self.spec.offsets
        n_attrs = len(attrs)
        attr_of = list(attrs[:n]) + [None] * (n - n_attrs) if n_attrs < n else attrs
        indexes, subs, datas = zip(*c.entries) if n else ((), (), ())
        writes = list(map(Write, range(n), offsets, datas, attr_of))
        keys = list(zip(indexes, subs))
        groups: dict[tuple[int, int], list[Write]] = dict.fromkeys(keys)
        if len(groups) == n:        # every (index, sub) written once: one write each
            groups = dict(zip(keys, [[w] for w in writes]))
        else:
            for key, w in zip(keys, writes):
                g = groups[key]
                if g is None:
                    groups[key] = [w]
                else:
                    g.append(w)
        # network variables, first occurrence (SPEC §3.4)
        self.nv_order = [key for key in groups if key[1] and NV_FIRST <= key[0] <= NV_LAST]
        nv_vars = []
        objects = self.objects
        typer = self.typer
        # the written (index, sub) pairs in order, one object (a run of one index) at a time
        for index, written in groupby(sorted(groups), key=itemgetter(0)):
            written = list(written)
            kind = typer.object_type(index, [key[1] for key in written])
            obj = objects[index] = ObjSpec(index, kind, typer.object_name(index))
            if NV_FIRST <= index <= NV_LAST:
                if written[0][1] == 0:
                    obj.subs[0] = typer.entry(index, 0, groups[written[0]])
                    written = written[1:]
                nv_vars += [(index, key[1], groups[key]) for key in written]
                continue
            for key in written:
                obj.subs[key[1]] = typer.entry(index, key[1], groups[key])
        self._network_variables(nv_vars)
        for obj in objects.values():
            order = list(obj.subs)
            if order != sorted(order):
                obj.subs = dict(sorted(obj.subs.items()))
        self._implied_sub0()
        _choose_encoding(self.spec)
        _values(self.spec)
        return self.spec

    def _header_issues(self, n: int, attrs: bytes) -> None:
        c = self.c
        if c.header is not None:
            self.issues.add(R_HEADER, 0, "the header or segment layout is not the canonical one "
                            "(segments back to back after the header in table order, an "
                            "empty one at offset 0 and not counted); compile writes the "
                            "canonical layout")
        if c.raw_piparam is not None:
            self.issues.add(R_HEADER, self.spec.header["piparam_offset"],
                            f"the PI parameter segment has {len(c.raw_piparam)} bytes, not 20")
        if c.attributes is None and n:
            self.issues.add(R_HEADER, 0x18, f"no extended info segment: the {n} entries have "
                            "no attribute; written as DOMAIN rw")
        elif len(attrs) != n:
            self.issues.add(R_HEADER, 0x1C, f"the extended info segment has {len(attrs)} bytes "
                            f"for {n} entries")

    # -- network variables and [DynamicChannels] (SPEC §2.1-2.3) ------------------------------
    def _network_variables(self, nv_vars) -> None:
        c = self.c
        addr_of = {}
        if c.addresses is not None:
            if list(map(_KEY, nv_vars)) == self.nv_order:
                # first written in ascending order (as compile writes them): the addresses
                # follow the variables one for one
                addr_of = None
                addrs = c.addresses + [None] * (len(nv_vars) - len(c.addresses))
            else:
                addr_of = dict(zip(self.nv_order, c.addresses))
        vars_ = []
        append = vars_.append
        eds = self.eds
        typer = self.typer
        current = tt = None
        size, boolean = -1, False      # of the range's type (-1: no type, no data fits)
        for index, sub, writes in nv_vars:
            last = writes[-1]
            if len(writes) > 1 or last.attr != 0xF0 or sub > PER_INDEX:
                typer.nv_checks(index, sub, writes)
            if index != current:       # the range's type, once for each index
                current = index
                t = table_type(index) if eds is None else None
                tt = t[0] if t is not None else None
                size, boolean = (tt.size, tt.kind == dt.BOOL) if tt is not None else (-1, False)
            data = last.data
            if len(data) == size and (not boolean or data[0] < 2):
                dtype = tt             # fast path: the range's type holds the value (holds)
            else:
                dtype = typer.nv_type(index, sub, last)
            append((index, sub, dtype, writes, addr_of.get((index, sub))
                    if addr_of is not None else addrs[len(vars_)]))
        self._plan_channels(vars_)
        objects = self.objects
        current = access = subs = None
        for index, sub, dtype, writes, _ in vars_:
            if index != current:       # the area, access and subs of one index at a time
                current = index
                access = "ro" if self._direction_of(index) == INPUT else "rw"
                subs = objects[index].subs
            subs[sub] = SubSpec(index, sub, dtype, access, True, writes,
                                _VARIABLE[sub] if eds is None else typer.sub_name(index, sub))

    def _direction_of(self, index: int) -> str:
        for ch in self.spec.channels:
            if ch.first <= index <= ch.last:
                return ch.direction
        return INPUT if index < OUTPUT_FIRST else OUTPUT

    def _plan_channels(self, vars_) -> None:
        """Reconstruct [DynamicChannels] segments from the addresses (SPEC §2.3)."""
        c = self.c
        pi = c.pi
        by_index: dict[int, list] = {}
        # _area's common case inline: the address in the area of the index's range
        lo = hi = base = 0
        direction = None
        current = vs = None
        for index, sub, dtype, writes, addr in vars_:
            if dtype.size is None:
                continue      # reported: no segment can hold it, compile rejects it
            if index != current:        # the area of the index's range, once an index
                current = index
                vs = by_index.setdefault(index, [])
                lo, hi, base, direction = _range_area(index, pi)
            if addr is not None and lo <= addr < hi:
                vs.append((sub, dtype, direction, addr - base, writes[0].offset))
            else:
                vs.append((sub, dtype, *self._area(index, addr, pi, writes[0].offset),
                           writes[0].offset))
        nv_objects = sorted(i for i in self.objects if is_nv(i))
        regions = [(NV_FIRST + k * 0x40, NV_FIRST + k * 0x40 + 0x3F) for k in range(36)]
        regions.append((TABLE_END, NV_LAST))
        channels: list[ChannelSpec] = []
        for first, last in regions:
            idxs = [i for i in nv_objects if first <= i <= last]
            if not idxs:
                continue
            tt = table_type(first)
            region: list[ChannelSpec] = []
            for index in idxs:
                vs = by_index.get(index)
                if not vs:
                    continue
                _, dtype, direction, _, where = vs[0]
                if not (all(map(is_, repeat(dtype), map(_DTYPE, vs)))
                        and all(map(direction.__eq__, map(_DIRECTION, vs)))):
                    self.issues.add(R_PI, where, f"0x{index:04X}: its variables differ in type "
                                    "or area; one [DynamicChannels] segment cannot hold them")
                cur = region[-1] if region else None
                if cur is not None and cur.dtype is dtype and cur.direction == direction:
                    p = _pp(vs, index, cur.first, dtype)
                    if p is None:
                        continue                 # no address: any placement will do
                    if p != "mixed" and p >= 0 and (cur.pp is None or p == cur.pp):
                        cur.pp = p
                        continue
                start = first if not region else index
                p = _pp(vs, index, start, dtype)
                if start != index and (p == "mixed" or (p is not None and p < 0)):
                    start = index
                    p = _pp(vs, index, start, dtype)
                if p == "mixed" or (p is not None and p < 0):
                    self.issues.add(R_PI, where, f"0x{index:04X}: the addresses of its "
                                    "variables do not follow the layout start + element * "
                                    "size (254 variables an index)")
                    p0 = _pp(vs[:1], index, start, dtype)
                    p = p0 if isinstance(p0, int) and p0 >= 0 else 0
                region.append(ChannelSpec(dtype, direction, start, pp=p))
            for a, b in zip(region, region[1:]):
                a.last = b.first - 1
            if region:
                region[-1].last = last
            if tt is not None and region:
                r0 = region[0]
                if r0.first == first and r0.dtype is tt[0] and r0.direction == tt[1] and \
                        not r0.pp:
                    region = region[1:]
            elif tt is None and idxs:
                lowest = idxs[0]
                if not region:
                    region = [ChannelSpec(dt.UNSIGNED8, OUTPUT, lowest, last, 0)]
                elif lowest < region[0].first:
                    region.insert(0, ChannelSpec(dt.UNSIGNED8, OUTPUT, lowest,
                                                 region[0].first - 1, 0))
            for ch in region:
                if ch.pp is None:
                    ch.pp = 0
            channels.extend(region)
        self.spec.channels = channels

    def _area(self, index: int, addr: int | None, pi, offset: int):
        table_dir = INPUT if index < OUTPUT_FIRST else (OUTPUT if index < TABLE_END else None)
        if addr is None or pi is None:
            return table_dir or OUTPUT, None
        _, in_off, in_size, out_off, out_size = pi
        in_in = in_off <= addr < in_off + in_size
        in_out = out_off <= addr < out_off + out_size
        if table_dir == INPUT and in_in:
            return INPUT, addr - in_off
        if table_dir == OUTPUT and in_out:
            return OUTPUT, addr - out_off
        if in_in:
            return INPUT, addr - in_off
        if in_out:
            return OUTPUT, addr - out_off
        self.issues.add(R_PI, offset, f"0x{index:04X}: address 0x{addr:04X} lies outside both "
                        "areas of the PI parameter segment")
        return table_dir or OUTPUT, None

    def _implied_sub0(self) -> None:
        """ARRAY/RECORD objects without a written sub 0 get the one the model would imply."""
        for obj in self.objects.values():
            if obj.object_type == dt.OT_VAR or 0 in obj.subs:
                continue
            highest = max(obj.subs)
            spec = SubSpec(obj.index, 0, dt.UNSIGNED8, "ro", False, [],
                           self.typer.sub_name(obj.index, 0), default=str(highest))
            obj.subs[0] = spec
            obj.subs = dict(sorted(obj.subs.items()))
            if is_nv(obj.index) and not self.spec.concise:
                self.issues.add(R_SELECT, None, f"0x{obj.index:04X}sub0 is not in the "
                                "container; compile writes sub 0 of every network-variable "
                                "object")


# -- values ---------------------------------------------------------------------------------------

def _choose_encoding(spec: DcfSpec) -> None:
    """UTF-8, unless a VISIBLE_STRING holds bytes that are not: then Latin-1 (SPEC §1)."""
    for obj in spec.objects.values():
        for s in obj.subs.values():
            if s.writes and s.dtype.kind == dt.VSTRING:
                try:
                    s.data.decode("utf-8")
                except UnicodeDecodeError:
                    spec.encoding = "latin-1"
                    return


def _values(spec: DcfSpec) -> None:
    """The ParameterValue text of every written sub (SPEC §1 encodings)."""
    enc = spec.encoding
    # the text of a value depends on its type and bytes only: made once for each pair
    # (the variables of one object share a type; tens of thousands of them share a few
    # hundred values)
    by_type: dict = {}
    dtype = texts = None
    for obj in spec.objects.values():
        for s in obj.subs.values():
            if not s.writes:
                continue
            if s.dtype is not dtype:
                dtype = s.dtype
                texts = by_type.setdefault(dtype, {})
            data = s.writes[-1].data
            text = texts.get(data, False)
            if text is False:
                text = texts[data] = value_text(dtype, data, enc)
            if text is None:
                # BOOLEAN other than 0/1, a string with CR/LF or not in the file's
                # encoding: keep the bytes exact, lose the type (and its attribute bit)
                old = s.dtype
                s.dtype = dt.OCTET_STRING if old.size is None else by_size(len(s.data))
                text = value_text(s.dtype, s.data, enc)
                spec.issues.add(R_VALUE, s.writes[-1].offset,
                                f"0x{s.index:04X}sub{s.sub:X}: {short(s.data)} cannot be "
                                f"written as a {old.name} value in a DCF; written as "
                                f"{s.dtype.name}")
            s.value = text


def _range_area(index: int, pi) -> tuple[int, int, int, str | None]:
    """(first address, end, area start, area) of the area of ``index``'s CiA 405 range in
    the PI parameters: an address in [first, end) lies where _area puts it, at its
    offset from the area start. An empty span where there is no such area."""
    if pi is None or index >= TABLE_END:
        return 0, 0, 0, None
    _, in_off, in_size, out_off, out_size = pi
    if index < OUTPUT_FIRST:
        return in_off, in_off + in_size, in_off, INPUT
    return out_off, out_off + out_size, out_off, OUTPUT


_VARIABLE = [f"Variable {sub}" for sub in range(256)]   # a network variable's name
_KEY, _DTYPE, _DIRECTION = itemgetter(0, 1), itemgetter(1), itemgetter(2)


def _pp(vs, index: int, start: int, dtype: dt.DataType):
    """The segment start (PPOffset) that places all of ``vs`` in index ``index``."""
    first = (index - start) * PER_INDEX - 1
    size = dtype.size
    pps = {off - (first + sub) * size for sub, _, _, off, _ in vs if off is not None}
    if not pps:
        return None
    if len(pps) > 1:
        return "mixed"
    return pps.pop()




__all__ = ["read_spec"]

"""Steps 1 and 2 of the DynBuildOd emulation: structure (0xA1) and PI memory (0xA0).
"""
from __future__ import annotations

from itertools import compress, groupby, islice
from operator import add, itemgetter, le, lt, ne, sub as minus

from dcf2bin.dynod import codes as C
from dcf2bin.dynod.outcome import _Fail, _OUTPUT_FIRST
from dcf2bin.indexes import NV_FIRST, NV_LAST


_INDEX, _SUB, _DATA = itemgetter(0), itemgetter(1), itemgetter(2)   # of (index, sub, data)
_FEW_BLOCKS = 256         # blocks of consecutive addresses compared span by span


def nv_firsts(entries: list) -> tuple[list[int], bool]:
    """The positions of the first occurrence of each network variable (SPEC §3.4: an entry
    of 0xA000-0xAFFF with sub >= 1), ascending, and whether the variables' keys ascend
    with them (then a variable is found by bisection).

    A compiled container writes each variable once, by ascending index and subindex: when
    the keys ascend strictly, every position is a first occurrence. That is found run by
    run of one index (``_ascending_runs``). Otherwise a dict from the reversed keys keeps,
    for every key, the smallest position (a dict of 60,000 keys and positions was the
    memory peak of a compile: hence not the first try)."""
    positions = _ascending_runs(entries)
    if positions is not None:
        return positions, True
    keys = [index << 8 | sub if NV_FIRST <= index <= NV_LAST and sub else 0
            for index, sub, _ in entries]          # 0: no network variable
    firsts = dict(zip(reversed(keys), range(len(keys) - 1, -1, -1)))
    del keys                    # (each temporary goes as soon as it is used)
    firsts.pop(0, None)
    return sorted(firsts.values()), False


def _ascending_runs(entries: list) -> list[int] | None:
    """The positions of the network variables when their keys (index << 8 | sub) ascend
    strictly, else None. The entries come in runs of one index (an object's sub-entries):
    a run's subindexes are taken at once, and only a network-variable object's, instead
    of a key made per entry (at 60,000 variables: 4.5 against 7.2 ms, most of it in
    reaching the entries, which the target check reads here first)."""
    positions: list[int] = []
    pos, last = 0, -1           # last: the key of the last network variable so far
    for index, run in groupby(entries, key=_INDEX):
        run = list(run)
        if NV_FIRST <= index <= NV_LAST:
            subs = list(map(_SUB, run))
            variables = list(filter(None, subs))        # sub 0 is none
            if variables:
                if (index << 8 | variables[0]) <= last or not all(
                        map(lt, variables, islice(variables, 1, None))):
                    return None
                last = index << 8 | variables[-1]
                positions.extend(compress(range(pos, pos + len(run)), subs))
        pos += len(run)
    return positions


class _StructureStep:
    """Steps 1 and 2 of ``_Engine``: the container's structure (0xA1) and the placement of the
    network variables in the PI memory (0xA0).
    """

    def structure(self) -> None:
        c = self.c
        entries = c.entries
        n = len(entries)
        if c.attributes is not None and len(c.attributes) != n:
            raise _Fail(C.INVALID_CONFIG, f"the extended info segment has {len(c.attributes)} "
                                          f"attribute bytes for {n} index entries")
        first = self.nv_first
        positions, self.nv_ascending = nv_firsts(entries)
        first.extend(positions)
        del positions
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
        sizes = list(map(len, map(_DATA, map(entries.__getitem__, first))))
        total = pi[0] if pi is not None else None
        if _clean(image, sizes, total):
            return                  # nothing for the byte map below to find
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


def _clean(image: list[int], sizes: list[int], total: int | None) -> bool:
    """True when no variable ends beyond ``total`` and none overlaps another, told in C.
    False means "maybe": the loop over the byte map finds which variable fails, and says
    it as the target would."""
    if not image:
        return True
    n = len(image)
    # a compiled PLC's variables lie in a few blocks of consecutive addresses, each
    # starting where the one before ends (told in C from the differences of the
    # addresses: small ints, nothing allocated); a block overlaps nothing in itself and
    # ends where its last variable ends, so only the blocks' spans are compared
    breaks = list(compress(range(1, n), map(ne, map(minus, islice(image, 1, None), image),
                                            sizes)))
    if len(breaks) < _FEW_BLOCKS:
        spans = sorted((image[a], image[b - 1] + sizes[b - 1])
                       for a, b in zip([0] + breaks, breaks + [n]))
        if total is not None and max(e for _, e in spans) > total:
            return False
        return all(e <= a for (_, e), (a, _) in zip(spans, spans[1:]))
    ends = list(map(add, image, sizes))
    if total is not None and max(ends) > total:
        return False
    # in address order, no variable overlaps another when each ends at or before the
    # next one starts (then the ends ascend too, and each end is the furthest so far);
    # anything else, a variable of 0 bytes inside another say, is a "maybe"
    starts = image
    if not all(map(le, image, islice(image, 1, None))):
        # in address order (the sort merges ascending runs in linear time)
        order = sorted(range(n), key=image.__getitem__)
        starts, ends = list(map(image.__getitem__, order)), list(map(ends.__getitem__, order))
    return all(map(le, ends, islice(starts, 1, None)))

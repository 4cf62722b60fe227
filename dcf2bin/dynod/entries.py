"""Step 3 of the DynBuildOd emulation: create or write each index entry.
"""
from __future__ import annotations

from collections.abc import Iterable
from itertools import chain, groupby, repeat
from operator import itemgetter

from dcf2bin import datatypes as dt
from dcf2bin.dynod import codes as C
from dcf2bin.dynod.outcome import _Fail, _NUMERIC_OR_BOOL


_INDEX, _SUB, _DATA = itemgetter(0), itemgetter(1), itemgetter(2)


def _records(attrs: bytes, datas: list) -> tuple[Iterable[tuple], int]:
    """The records ``(attr, data, None)`` of the entries of a created object, and their
    data bytes in all. When every entry after the first has the same attribute byte and
    the same data (a network-variable object of one type and value: sub 0, then 254
    alike), they share one record, which is immutable (60,000 tuples fewer held by the
    target check of a 60,000-variable compile: 1.4 MiB of its peak)."""
    n = len(datas)
    if n > 2:
        a, d = attrs[1:], datas[1:]
        if a.count(a[0]) == n - 1 and d.count(d[0]) == n - 1:
            return (chain(((attrs[0], datas[0], None),), repeat((a[0], d[0], None), n - 1)),
                    len(datas[0]) + (n - 1) * len(d[0]))
    return zip(attrs, datas, repeat(None)), sum(map(len, datas))


class _EntriesStep:
    """Step 3 of ``_Engine``: the index entries one by one, checked (existence, size, PDO
    semantics) and then created or written.
    """
    # a run of entries that creates a whole object is applied at once (the tests compare
    # the results with this off: entry by entry)
    _whole_objects = True

    # -- step 3 ----------------------------------------------------------------------------
    def entries(self) -> None:
        """Entry by entry: check it (existence, size, PDO semantics), then apply it. A
        failing entry is not applied."""
        attrs = self.c.attributes
        static = self.static
        cur = self.cur
        no_static: dict = {}
        pos = 0
        # entries come in runs of one index: look it up once per run
        for index, run in groupby(self.c.entries, key=_INDEX):
            run = list(run)
            subs = cur.get(index)
            sdict = static.entries(index) if static is not None else no_static
            if subs is None and not sdict and attrs is not None and self._whole_objects \
                    and not 0x1400 <= index <= 0x1BFF:
                # a whole object created (a network variable, say): no entry can fail
                # (nothing to compare a size with, no PDO semantics) unless a subindex
                # comes twice; then entry by entry below
                run_subs = list(map(_SUB, run))
                n = len(run)
                if len(set(run_subs)) == n:
                    records, size = _records(attrs[pos:pos + n], list(map(_DATA, run)))
                    cur[index] = dict(zip(run_subs, records))
                    if static is None or not static.has(index):
                        self.created_objects.append(index)
                        self.created_set.add(index)
                    self.n_created += n
                    self.created_bytes += size
                    pos += n
                    continue
            pos = self._run(pos, run, subs, sdict)
        self.applied = len(self.c.entries)

    def _run(self, pos: int, run: list, subs, sdict) -> int:
        """The entries of ``run`` (one index), the first at ``pos``, one by one; the
        position after them."""
        attrs = self.c.attributes
        static = self.static
        cur = self.cur
        for pos, (index, sub, data) in enumerate(run, pos):
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
                    self.warn(("assumed",))
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
            new_object = create and subs is None and (static is None or not static.has(index))
            if 0x1400 <= index <= 0x1BFF:
                self.creating = index if new_object else None
                self.pdo_write(pos, index, sub, data)
            if subs is None:
                subs = cur[index] = {}
                if new_object:
                    self.created_objects.append(index)
                    self.created_set.add(index)
            if create:
                self.n_created += 1
                self.created_bytes += len(data)
            subs[sub] = new
        return pos + 1

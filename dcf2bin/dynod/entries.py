"""Step 3 of the DynBuildOd emulation: create or write each index entry.
"""
from __future__ import annotations

from dcf2bin import datatypes as dt
from dcf2bin.dynod import codes as C
from dcf2bin.dynod.outcome import _Fail, _NUMERIC_OR_BOOL


class _EntriesStep:
    """Step 3 of ``_Engine``: the index entries one by one, checked (existence, size, PDO
    semantics) and then created or written.
    """

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

"""The PDO objects [DeviceInfo] CompactPDO implies (a step of ``builder._Builder``).
"""
from __future__ import annotations

from dcf2bin import datatypes as dt, values
from dcf2bin.indexes import RPDO_COMM, TPDO_COMM
from dcf2bin.model.objects import Entry, Obj
from dcf2bin.model.sections import _int_or


class _CompactPdoStep:
    """The PDO objects ``_Builder`` adds for [DeviceInfo] CompactPDO (CiA 306 §4.6.3.4.1)."""

    # -- CompactPDO (CiA 306 §4.6.3.4.1, SPEC §1) -------------------------------------------
    def _compact_pdo(self) -> None:
        dev = self.dev
        info = self.ini.section("deviceinfo")
        if info is None:
            return
        numbers = []
        for key in ("compactpdo", "nrofrxpdo", "nroftxpdo"):
            try:
                numbers.append(_int_or(info.get(key), 0))
            except values.ValueProblem as exc:   # at the key's line, not the header's
                dev.error(f"[DeviceInfo] {info.keys[key].name}: {exc}", self.w(info.line_of(key)),
                          rule="DCF040")
                return
        mask, n_rx, n_tx = numbers
        if not mask:
            return
        where = self.w(info.line_of("compactpdo"))
        for base, n, cob_bases in ((RPDO_COMM, n_rx, (0x200, 0x300, 0x400, 0x500)),
                                   (TPDO_COMM, n_tx, (0x180, 0x280, 0x380, 0x480))):
            for k in range(min(n, 512)):
                comm, mapping = base + k, base + 0x200 + k
                if comm not in dev.objects:
                    obj = Obj(comm, "PDO communication parameter", dt.OT_RECORD, where=where,
                              implicit=True, complex=True)
                    present = [s for s in range(1, 7) if mask & (1 << (s - 1))]
                    obj.entries[0] = Entry(comm, 0, "Highest sub-index supported", dt.UNSIGNED8,
                                           "ro", default=str(max(present, default=0)),
                                           where=where, implicit=True)
                    for s in present:
                        if s == 1:
                            cob = (f"$NODEID+0x{cob_bases[k]:X}" if k < 4 else "0x80000000")
                            e = Entry(comm, 1, "COB-ID", dt.UNSIGNED32, "rw", default=cob)
                        elif s == 2:
                            e = Entry(comm, 2, "Transmission type", dt.UNSIGNED8, "rw",
                                      default="255")
                        elif s in (3, 5):
                            e = Entry(comm, s, "Inhibit time" if s == 3 else "Event timer",
                                      dt.UNSIGNED16, "rw", default="0")
                        else:
                            e = Entry(comm, s, "Reserved" if s == 4 else "SYNC start value",
                                      dt.UNSIGNED8, "rw", default="0")
                        e.where, e.implicit = where, True
                        obj.entries[s] = e
                    dev.objects[comm] = obj
                if mapping not in dev.objects:
                    obj = Obj(mapping, "PDO mapping parameter", dt.OT_RECORD, where=where,
                              implicit=True, complex=True)
                    obj.entries[0] = Entry(mapping, 0, "Number of mapped objects", dt.UNSIGNED8,
                                           "rw", default="0", where=where, implicit=True)
                    for s in range(1, 9):
                        obj.entries[s] = Entry(mapping, s, f"Mapped object {s}", dt.UNSIGNED32,
                                               "rw", default="0", where=where, implicit=True)
                    dev.objects[mapping] = obj

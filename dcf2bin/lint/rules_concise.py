"""CON0xx: concise DCFs (CiA 302-3), what a configuration manager writes to a node.

CON001-CON004 are the reader's own findings (``concise.read_concise``: the bytes are not a
whole concise DCF; one finding, at its byte). The checks below look at the entries of one
that reads:

* CON010-CON012, the PDO reconfiguration of CiA 301, replayed entry by entry on what the
  file itself writes (a COB-ID with or without bit 31, a mapping's sub 0): a mapping, an
  inhibit time, a SYNC start value or a CAN-ID changed while the file has made the PDO
  valid, or mapping entries written while sub 0 is not 0, are refused by every node
  (errors); the same written before the file has made the PDO invalid (or set sub 0 to 0)
  depend on the state the node is in (warnings);
* CON020-CON022, the entries against the device's description (``validate --eds FILE``, or
  the DCF of the same name beside the file): a size that is not its type's, an entry the
  device does not have, a read-only one;
* CON030/CON031: repeated writes and an empty file, as information.
"""
from __future__ import annotations

from dataclasses import dataclass

from dcf2bin.lint.registry import CONCISE, ERROR, INFO, WARNING, Finding, core, rule

core("CON001", "concise-too-short", ERROR,
     "The file is shorter than the DWORD that counts a concise DCF's entries.",
     hint="a concise DCF starts with the number of its entries", kind=CONCISE)
core("CON002", "concise-entry-past-end", ERROR,
     "An entry's head or data runs past the end of the file.",
     hint="each entry is WORD index, BYTE subindex, DWORD size and that many bytes",
     kind=CONCISE)
core("CON003", "concise-trailing-bytes", ERROR,
     "Bytes follow the last of the entries the count names.",
     hint="the count is the number of entries; nothing follows the last one", kind=CONCISE)
core("CON004", "concise-count-mismatch", ERROR,
     "Whole entries fill the file, but the count says another number of them.",
     hint="the first DWORD is the number of entries", kind=CONCISE)

_COB_VALID = 0x80000000       # COB-ID bit 31: the PDO does not exist (invalid)
_COB_ID_BITS = 0x3FFFFFFF     # bits 0-29: CiA 301 changes them only while the PDO is invalid
_GUARDED = {3: "inhibit time", 6: "SYNC start value"}   # comm subs: only while invalid


# -- the PDO sequence, replayed (CiA 301) ------------------------------------------------------

@dataclass
class _Pdo:
    """What the file has written to one PDO so far: whether it made it valid (None: not
    yet said), with which COB-ID, at which entry; its mapping's sub 0."""
    valid: bool | None = None
    cob_id: int = 0
    cob_entry: int = 0
    mapped: int | None = None
    mapped_entry: int = 0


def _pdo_of(index: int) -> tuple[int, str] | None:
    """(communication index, 'RPDO3') of a PDO communication or mapping object."""
    for first, kind in ((0x1400, "RPDO"), (0x1600, "RPDO"), (0x1800, "TPDO"), (0x1A00, "TPDO")):
        if first <= index < first + 0x200:
            comm = index if first in (0x1400, 0x1800) else index - 0x200
            return comm, f"{kind}{index - first + 1}"
    return None


def _label(index: int, sub: int) -> str:
    return f"0x{index:04X}sub{sub:X}"


def _sequence(ctx) -> list[tuple[str, int, str]]:
    """(rule, entry number, message) for every step of a PDO block that CiA 301 forbids,
    the first of each kind per PDO; worked out once per file."""
    got = ctx.cache.get("pdo")
    if got is not None:
        return got
    found: list[tuple[str, int, str]] = []
    seen: set[tuple[str, int, str]] = set()
    pdos: dict[int, _Pdo] = {}

    def add(rule_id: str, k: int, comm: int, cause: str, message: str) -> None:
        if (rule_id, comm, cause) not in seen:
            seen.add((rule_id, comm, cause))
            found.append((rule_id, k, message))

    for k, (index, sub, data) in enumerate(ctx.entries):
        pdo = _pdo_of(index)
        if pdo is None:
            continue
        comm, name = pdo
        st = pdos.setdefault(comm, _Pdo())
        label = _label(index, sub)
        made_valid = (f"{name} is valid (entry {st.cob_entry + 1}, "
                      f"{_label(comm, 1)} = 0x{st.cob_id:08X})")
        not_invalid = (f"the file has not made {name} invalid before ({_label(comm, 1)} with "
                       "bit 31 set)")
        if index == comm and sub == 1 and len(data) == 4:
            value = int.from_bytes(data, "little")
            if not value & _COB_VALID:
                if st.valid and (value ^ st.cob_id) & _COB_ID_BITS:
                    add("CON010", k, comm, "cob", f"{label} = 0x{value:08X} changes {name}'s "
                        f"COB-ID while {made_valid}")
                elif st.valid is None:
                    add("CON011", k, comm, "cob", f"{label} = 0x{value:08X} sets {name}'s "
                        f"COB-ID, but {not_invalid}: a node whose {name} is valid with "
                        "another one refuses it")
            st.valid, st.cob_id, st.cob_entry = not value & _COB_VALID, value, k
        elif index == comm and sub in _GUARDED:
            what = _GUARDED[sub]
            if st.valid:
                add("CON010", k, comm, what, f"{label} changes {name}'s {what} while "
                    f"{made_valid}")
            elif st.valid is None:
                add("CON011", k, comm, what, f"{label} changes {name}'s {what}, but "
                    f"{not_invalid}: a node whose {name} is valid refuses it")
        elif index != comm:                       # the mapping object
            if st.valid:
                add("CON010", k, comm, "mapping", f"{label} changes {name}'s mapping while "
                    f"{made_valid}")
            elif st.valid is None:
                add("CON011", k, comm, "mapping", f"{label} changes {name}'s mapping, but "
                    f"{not_invalid}: a node whose {name} is valid refuses it")
            if sub == 0:
                st.mapped = data[0] if len(data) == 1 else -1      # -1: not one byte
                st.mapped_entry = k
            elif st.mapped is None:
                add("CON011", k, comm, "count", f"{label} is written before the file sets "
                    f"{_label(index, 0)} to 0: a node whose {name} maps objects refuses it")
            elif st.mapped:
                shown = str(st.mapped) if st.mapped >= 0 else "not one byte"
                add("CON012", k, comm, "count", f"{label} is written while {_label(index, 0)} "
                    f"is {shown} (entry {st.mapped_entry + 1}); CiA 301 writes a mapping's "
                    "entries while its sub 0 is 0")
    ctx.cache["pdo"] = found
    return found


def _findings(ctx, rule_id: str):
    for r, k, message in _sequence(ctx):
        if r == rule_id:
            yield Finding(message, offset=ctx.offsets[k])


@rule("CON010", "pdo-changed-while-valid", ERROR,
      "A PDO's mapping, inhibit time, SYNC start value or CAN-ID is changed while the file "
      "has made the PDO valid.",
      hint="write its COB-ID with bit 31 set (invalid) first, then the change, then the "
           "valid COB-ID, as CiA 301 reconfigures a PDO", kind=CONCISE)
def pdo_changed_while_valid(ctx):
    yield from _findings(ctx, "CON010")


@rule("CON011", "pdo-not-invalidated", WARNING,
      "A PDO's mapping, inhibit time, SYNC start value or COB-ID is written before the file "
      "makes the PDO invalid, or a mapping entry before it sets the mapping's sub 0 to 0: "
      "the node refuses it unless it is in that state already.",
      hint="begin the PDO's block with its COB-ID | 0x80000000 and the mapping's sub 0 = 0",
      kind=CONCISE)
def pdo_not_invalidated(ctx):
    yield from _findings(ctx, "CON011")


@rule("CON012", "pdo-mapping-while-counted", ERROR,
      "A mapping entry (sub 1-64) is written while the file has set the mapping's sub 0 to "
      "a number other than 0.",
      hint="write sub 0 = 0, then the entries, then sub 0 = their number", kind=CONCISE)
def pdo_mapping_while_counted(ctx):
    yield from _findings(ctx, "CON012")


# -- the entries against the device's description ----------------------------------------------

def _described(ctx):
    """(entry number, index, sub, data, the EDS's entry or None, its object or None) of
    every entry, with an EDS; nothing without one."""
    eds = ctx.eds
    if eds is None:
        return
    for k, (index, sub, data) in enumerate(ctx.entries):
        yield k, index, sub, data, eds.entries.get((index, sub)), eds.objects.get(index)


@rule("CON020", "concise-size-mismatch", ERROR,
      "An entry's data has another size than its data type in the device's description.",
      hint="a value is written with its type's exact size (--eds names the description)",
      kind=CONCISE)
def size_mismatch(ctx):
    for k, index, sub, data, e, _ in _described(ctx):
        t = e.dtype if e is not None else None
        if t is not None and t.size is not None and t.size != len(data):
            yield Finding(f"{_label(index, sub)}: {_bytes(len(data))}, {ctx.eds_name} gives "
                          f"{t.name} ({_bytes(t.size)})", offset=ctx.offsets[k])


@rule("CON021", "concise-unknown-entry", WARNING,
      "An entry the device's description does not have: the node refuses the write.",
      hint="check the index and sub-index against the device's EDS", kind=CONCISE)
def unknown_entry(ctx):
    for k, index, sub, _, e, obj in _described(ctx):
        if e is None:
            what = f"no object 0x{index:04X}" if obj is None else "no such sub-index"
            yield Finding(f"{_label(index, sub)}: {ctx.eds_name} has {what}",
                          offset=ctx.offsets[k])


@rule("CON022", "concise-read-only", ERROR,
      "An entry the device's description gives as read-only (ro or const): the node refuses "
      "the write.", hint="a configuration writes only entries that are rw, wo, rwr or rww",
      kind=CONCISE)
def read_only(ctx):
    for k, index, sub, _, e, _ in _described(ctx):
        if e is not None and e.access in ("ro", "const"):
            yield Finding(f"{_label(index, sub)}: {ctx.eds_name} gives AccessType={e.access}",
                          offset=ctx.offsets[k])


def _bytes(n: int) -> str:
    return f"{n} byte{'s' if n != 1 else ''}"


# -- information ---------------------------------------------------------------------------------

@rule("CON030", "concise-repeated-entry", INFO,
      "An entry is written more than once (besides a PDO's COB-ID and its mapping's sub 0, "
      "which its reconfiguration writes twice): the node keeps the last value.",
      hint="write each entry once, unless a sequence of the device needs each write",
      kind=CONCISE)
def repeated_entry(ctx):
    where: dict[tuple[int, int], list[int]] = {}
    for k, (index, sub, _) in enumerate(ctx.entries):
        where.setdefault((index, sub), []).append(k)
    for (index, sub), ks in where.items():
        pdo = _pdo_of(index)
        if len(ks) < 2 or (pdo is not None and (index, sub) in ((pdo[0], 1),
                                                                 (pdo[0] + 0x200, 0))):
            continue
        last = ctx.entries[ks[-1]][2].hex().upper() or "no data"
        yield Finding(f"{_label(index, sub)} is written {len(ks)} times (entries "
                      f"{', '.join(str(k + 1) for k in ks)}); the node keeps the last, {last}",
                      offset=ctx.offsets[ks[0]])


@rule("CON031", "concise-empty", INFO,
      "The concise DCF has no entries: it configures nothing.",
      hint="nothing to fix when the node needs no configuration", kind=CONCISE)
def empty(ctx):
    if not ctx.entries:
        yield Finding("no entries: the file configures nothing", offset=0)

"""A deterministic model of the target's ``DynBuildOd()`` (SPEC §8, D-11).

``emulate(container, options, static, sources)`` runs the steps of SPEC §8.2 in order
and stops at the first failure, like the target: structure (0xA1), PI memory (0xA0),
then the index entries one by one with create/write and the CiA 301 PDO semantics.

Speed: a PLC container creates tens of thousands of network variables. The engine
keeps one small tuple per written entry, ``(attr, data, static entry)``, in a dict per
index; the public ``TargetEntry`` objects of ``Outcome.od`` are built only when asked for.

The engine's steps live in their own modules (``structure``, ``entries``, ``pdo``,
``results``; the data in ``outcome``); ``_Engine`` here runs them in order.
"""
from __future__ import annotations

import gc

from dcf2bin.dynod import codes as C
from dcf2bin.dynod.entries import _EntriesStep
from dcf2bin.dynod.outcome import (_Fail, _le, can_id_problem, Created, Descriptor, Outcome, Pdo,
                                   RX, TargetEntry, TargetOptions, TargetWarning, TX)
from dcf2bin.dynod.pdo import _PdoSemantics
from dcf2bin.dynod.results import _Results
from dcf2bin.dynod.structure import _StructureStep


class _Engine(_StructureStep, _EntriesStep, _PdoSemantics, _Results):
    def __init__(self, c, opts: TargetOptions, static, sources):
        self.c = c
        self.opts = opts
        self.static = static
        # unknown (no static OD) or partial: what it lacks may still be on the target
        self.partial = static is None or not static.complete
        self.sources = sources
        self.cur: dict[int, dict[int, tuple]] = {}
        self.created_objects: list[int] = []
        self.created_set: set[int] = set()              # the same, for lookups
        self.n_created = 0
        self.created_bytes = 0
        self.valid: dict[int, int] = {}                 # comm index -> CAN-ID
        self.owner: dict[tuple[str, int], int] = {}     # (direction, CAN-ID) -> comm index
        self.counts = {RX: 0, TX: 0}
        self.warned: dict[tuple, int] = {}              # warning key -> how many times
        self.warned_at: dict[tuple, int] = {}           # warning key -> first entry position
        self.nv_first: list[int] = []                   # positions of first NV occurrences
        self.nv_ascending = False                       # ... and their keys ascend with them
        self.image: list[int] | None = None             # image address per NV (address order)
        self.applied = 0
        self.creating: int | None = None                # the index the current entry creates

    # -- helpers ---------------------------------------------------------------------------
    def warn(self, key: tuple, pos: int | None = None) -> None:
        self.warned[key] = self.warned.get(key, 0) + 1
        if pos is not None:
            self.warned_at.setdefault(key, pos)

    def made_here(self, index: int) -> bool:
        """Has the container created ``index`` (so far, or with the entry being applied)?
        Such an index has exactly the subs created so far; any other index, with an unknown
        static OD, counts as having all its subs (SPEC §8.2 step 3)."""
        return index in self.created_set or index == self.creating

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
        out.warnings = self.warnings()    # out.pdos: when asked for
        return out

    def locate(self, out: Outcome, pos: int) -> None:
        index, sub, data = self.c.entries[pos]
        out.entry, out.index, out.subindex, out.value = pos + 1, index, sub, data
        from dcf2bin.dump.binary import header_of
        h = header_of(self.c)
        off = h["index_offset"] + 4
        for _, _, d in self.c.entries[:pos]:
            off += 7 + len(d)
        out.offset = off
        src = self.sources
        if src is not None:
            w = src(pos + 1) if callable(src) else src.get(pos + 1)
            out.where = None if w is None else str(w)


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
    "TargetWarning",
    "can_id_problem",
    "emulate",
    "emulate_bytes",
]

"""The comparison of two ``Side``s: which entries take part, and for each what differs.

Entries compared (docs/diff.md, "What it compares"):

* two descriptions, or two write lists: every entry either holds;
* a write list (container, JSON form, concise DCF) and a description: the entries the
  write list writes, and the description's entries that a node at its defaults holds only
  when they are written (a ParameterValue or DownloadFile other than the DefaultValue, on
  a writable entry, ObjFlags bit 0 clear) -- every other entry of the description is
  what such a node holds already, and a write list says nothing of it;
* a node and a file: the entries the file lists that were read (``Side.unread`` holds
  those that were not: write-only, no value in the file, left out).

Per entry the value (bytes; integers by number where the two sides give two integer
types) -- except between two descriptions where only one states a value: the other's
type's zero says nothing of what the node holds there (as a file's entry without a value
is not read from a node), so that value is not compared, and counted (``no_value``) --
and where both sides know it the data type, the access, the PDO mapping
flag and a container's attribute byte -- unless ``Scope.values_only``. The node's state
and ``--ignore`` entries are left out and counted (``scope``).
"""
from __future__ import annotations

from dataclasses import dataclass, field

from dcf2bin import datatypes as dt
from dcf2bin.compare.scope import Scope, state_reason
from dcf2bin.compare.side import DESCRIPTION, WRITES, Item, Side
from dcf2bin.diagnostics import Diagnostic, Severity

CHANGED, REMOVED, ADDED = "changed", "removed", "added"     # removed: only in A; added: B
FACETS = ("value", "datatype", "access", "pdo_mapping", "attribute")


@dataclass
class Change:
    key: tuple[int, int]
    kind: str
    a: Item | None
    b: Item | None
    facets: tuple[str, ...] = ()


@dataclass
class FileDiff:
    """What two inputs differ in. ``left_out``: why entries were not compared, with the
    count of each (state, ignored; no_value: entries whose value only one description
    states, their other facets compared); ``only_a``/``only_b``: objects of which one side
    holds no compared entry."""
    a: Side
    b: Side
    changes: list[Change] = field(default_factory=list)
    compared: int = 0
    left_out: dict[str, int] = field(default_factory=dict)
    only_a: set[int] = field(default_factory=set)
    only_b: set[int] = field(default_factory=set)
    # Side.problems as diagnostics: of entries compared (errors, per input "a", "b") and
    # of entries not compared (warnings)
    entry_errors: dict[str, list] = field(default_factory=lambda: {"a": [], "b": []})
    entry_warnings: list = field(default_factory=list)

    def errors_of(self, which: str) -> int:
        """The errors of input ``which`` ("a" or "b"): its reader's of no object and
        those of the entries compared."""
        side = self.a if which == "a" else self.b
        return side.errors + len(self.entry_errors[which])

    @property
    def errors(self) -> int:
        return self.errors_of("a") + self.errors_of("b")

    def diagnostics(self) -> list[Diagnostic]:
        return self.entry_errors["a"] + self.entry_errors["b"] + self.entry_warnings

    @property
    def equal(self) -> bool:
        """No entry differs and both inputs were read without errors: a file with errors
        compared as read is never equal to another (exit 0 means both are clean)."""
        return not self.changes and not self.errors


@dataclass
class Result:
    """A whole comparison: one FileDiff for two files; for two folders one per file both
    hold, the files only one holds (``only_a``, ``only_b``: differences) and those not
    compared (``not_compared``: a build folder's files an upload folder has no kind of)."""
    a: str
    b: str
    files: list[FileDiff] = field(default_factory=list)
    only_a: list[str] = field(default_factory=list)
    only_b: list[str] = field(default_factory=list)
    not_compared: list[str] = field(default_factory=list)
    folders: bool = False

    @property
    def equal(self) -> bool:
        return not self.only_a and not self.only_b and all(f.equal for f in self.files)


def keys(a: Side, b: Side) -> tuple[set, set]:
    """The entries of each side that take part (see the module's docstring)."""
    unread = a.unread.keys() | b.unread.keys()
    ka, kb = set(a.items) - unread, set(b.items) - unread
    if a.source == WRITES and b.source != WRITES:
        kb = {k for k in kb if k in ka or b.items[k].configured}
    elif b.source == WRITES and a.source != WRITES:
        ka = {k for k in ka if k in kb or a.items[k].configured}
    return ka, kb


def compare(a: Side, b: Side, scope: Scope | None = None) -> FileDiff:
    scope = scope or Scope()
    out = FileDiff(a, b)
    ka, kb = keys(a, b)
    for why in (*a.unread.values(), *b.unread.values()):   # left out before a node was read
        if why in ("state", "ignored"):
            out.left_out[why] = out.left_out.get(why, 0) + 1
    shown_a, shown_b, compared = set(), set(), set()
    for key in sorted(ka | kb):
        ia, ib = (a.items[key] if key in ka else None), (b.items[key] if key in kb else None)
        if scope.ignored(key):
            out.left_out["ignored"] = out.left_out.get("ignored", 0) + 1
            continue
        if scope.state:
            complex_ = a.is_complex(key[0])
            if complex_ is None:
                complex_ = b.is_complex(key[0])
            if state_reason(key, (ia, ib), complex_) is not None:
                out.left_out["state"] = out.left_out.get("state", 0) + 1
                continue
        out.compared += 1
        compared.add(key)
        if ia is not None:
            shown_a.add(key[0])
        if ib is not None:
            shown_b.add(key[0])
        if ib is None:
            out.changes.append(Change(key, REMOVED, ia, None))
        elif ia is None:
            out.changes.append(Change(key, ADDED, None, ib))
        else:
            unstated = one_states(a, b, ia, ib)
            if unstated:
                out.left_out["no_value"] = out.left_out.get("no_value", 0) + 1
            facets = differing(ia, ib, scope.values_only, values=not unstated)
            if facets:
                out.changes.append(Change(key, CHANGED, ia, ib, facets))
    out.only_a, out.only_b = shown_a - shown_b, shown_b - shown_a
    _problems(out, compared)
    return out


def _problems(out: FileDiff, compared: set) -> None:
    """Each side's errors of an object or entry: an error where an entry they touch was
    compared, else a warning ``(not compared)`` -- as compile words one of an entry it
    does not write."""
    objects = {index for index, _ in compared}
    for which, side in (("a", out.a), ("b", out.b)):
        for index, sub, d, as_written in side.problems:
            hit = (index, sub) in compared if sub is not None else index in objects
            if hit:
                message = f"{d.message}; compared as written" if as_written else d.message
                out.entry_errors[which].append(Diagnostic(
                    Severity.ERROR, message, d.file, d.line, d.column, d.offset, d.rule,
                    d.hint))
            else:
                out.entry_warnings.append(Diagnostic(
                    Severity.WARNING, f"{d.message} (not compared)", d.file, d.line,
                    d.column, d.offset, d.rule, d.hint))


def one_states(a: Side, b: Side, ia: Item, ib: Item) -> bool:
    """Two descriptions of which only one states the entry's value (the other's is its
    type's zero, ``Value.implied``): the value is not compared."""
    return a.source == DESCRIPTION and b.source == DESCRIPTION \
        and ia.value.implied != ib.value.implied


def differing(a: Item, b: Item, values_only: bool = False,
              values: bool = True) -> tuple[str, ...]:
    """The facets in which two sides' entries differ (FACETS' order); ``values``: False
    leaves the value out."""
    out = []
    if values and not same_value(a, b):
        out.append("value")
    if values_only:
        return tuple(out)
    if a.dtype is not None and b.dtype is not None and a.dtype.code != b.dtype.code:
        out.append("datatype")
    if a.access is not None and b.access is not None and a.access != b.access:
        out.append("access")
    if a.pdo_mapping is not None and b.pdo_mapping is not None \
            and a.pdo_mapping != b.pdo_mapping:
        out.append("pdo_mapping")
    if a.attr is not None and b.attr is not None and a.attr != b.attr:
        out.append("attribute")
    return tuple(out)


def same_value(a: Item, b: Item) -> bool:
    va, vb = a.value, b.value
    if va.key() == vb.key():
        return True
    ta, tb = a.dtype, b.dtype
    if va.data is None or vb.data is None or ta is None or tb is None or ta is tb:
        return False
    if ta.is_integer and tb.is_integer and ta.size == len(va.data) \
            and tb.size == len(vb.data):
        return _int(ta, va.data) == _int(tb, vb.data)
    return False


def _int(t: dt.DataType, data: bytes) -> int:
    return int.from_bytes(data, "little", signed=t.kind == dt.SINT)

"""Every input ``diff`` compares, read into a ``Side`` (``compare.side``), in two steps:
``load`` reads the bytes (a description into its ``Device``, a write list into its
entries) and ``side`` makes the comparable form with the node-ID the comparison settled
on, so that a description without a node-ID takes the one of the file it is compared
with before a ``$NODEID`` value is worked out.

What each kind holds:

* a description (DCF/EDS, CiA 311 XML): every entry of every object from 0x1000 on,
  with its effective value (ParameterValue, else the DownloadFile's bytes, else
  DefaultValue; for an identity entry, 0x1018 sub 1-4, else what [DeviceInfo] or
  LSS_SerialNumber states, ``model.identity``, as the node made of the file answers it;
  else the type's zero, SPEC §1: ``Value.implied``), data type, access,
  PDO mapping flag and whether a write list must write it (``Item.configured``: a
  ParameterValue or DownloadFile other than its DefaultValue on a writable entry whose
  ObjFlags bit 0 is clear);
* a write list -- a container, a concise DCF, the JSON form of either -- the last write of
  each entry (what the target holds after it), with a container's attribute byte.

A file that cannot be read as its kind raises ``Unreadable`` with its diagnostics. A
description read with errors is compared as read, its errors kept (``Source.errors``):
those of no object (a line that is no key, conflict markers) count in ``Side.errors``;
those of an object or entry (an unknown AccessType), and values that cannot be encoded
(kept as written), go to ``Side.problems`` and are errors where the entry is compared
(``engine``), as compile's are where it writes the entry. A comparison with errors is
never "equal": ``diff`` exits 0 only for two inputs read cleanly that are equal.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from dcf2bin import datatypes as dt
from dcf2bin.compare.side import (DESCRIPTION, NO_VALUE, WRITES, Item, ObjInfo, Side, Value,
                                  objects_of)
from dcf2bin.diagnostics import DcfError, Diagnostic, Severity
from dcf2bin.indexes import is_pdo_mapping

DESCRIPTIONS = ("dcf", "xdd")
WRITE_LISTS = ("bin", "json", "concise", "concise-json")
KINDS = DESCRIPTIONS + WRITE_LISTS
# access types compile writes (SPEC §1: configured writable entries; D-9)
_WRITABLE = frozenset({"rw", "wo", "rwr", "rww"})


class Unreadable(Exception):
    """An input that cannot be compared; ``diagnostics`` say why."""

    def __init__(self, diagnostics: list[Diagnostic]):
        super().__init__("; ".join(d.message for d in diagnostics))
        self.diagnostics = diagnostics


@dataclass
class Source:
    """An input read, before its comparable form is made: a description's ``dev``, or a
    write list's ``entries`` (index, sub, bytes) in order with the container's
    ``attributes`` and each entry's place (``places``)."""
    label: str
    kind: str
    dev: object = None
    entries: list[tuple[int, int, bytes]] = field(default_factory=list)
    attributes: bytes | None = None
    places: list[str] | None = None
    warnings: list[Diagnostic] = field(default_factory=list)
    errors: list = field(default_factory=list)     # the reader's errors: model Problems

    @property
    def node_id(self) -> int | None:
        """The node-ID the input itself gives (-n, else [DeviceComissioning] NodeID)."""
        return getattr(self.dev, "node_id", None)


def load(data: bytes, path: str, kind: str, *, label: str | None = None,
         node_id: int | None = None) -> Source:
    """Read ``data`` (the file ``path``) as ``kind`` (a key of ``KINDS``); ``node_id``
    (-n) is the node-ID of ``$NODEID`` values whatever the file says."""
    label = label or path
    if kind in DESCRIPTIONS:
        return _description(data, path, label, kind, node_id)
    if kind == "concise":
        return _concise(data, label)
    if kind == "concise-json":
        return _concise_json(data, label)
    return _container(data, label, kind)


def _concise(data: bytes, label: str) -> Source:
    """A concise DCF's entries, read by ``dcf2bin.concise`` (the one reader: its error
    names the byte offset and the CON00x rule, as dump and validate say it)."""
    from dcf2bin.concise import offsets, read_concise
    entries, diags = read_concise(data, label)
    if entries is None:
        raise Unreadable(diags)
    places = [f"{label}:0x{off:X}" for off in offsets(entries)]
    return Source(label, "concise", entries=entries, places=places)


def _concise_json(data: bytes, label: str) -> Source:
    """The JSON form of a concise DCF (``dump -f json``): the bytes it records, read as a
    concise DCF is; its entries are placed by the file alone (a JSON form's byte offsets
    are the concise DCF's, not the file's)."""
    from dcf2bin.dump import from_json_bytes
    raw, diags = from_json_bytes(data, label)
    if raw is None:
        raise Unreadable(diags)
    src = _concise(raw, label)
    src.kind, src.places = "concise-json", None
    return src


def _container(data: bytes, label: str, kind: str) -> Source:
    from dcf2bin.dump import entry_offsets, from_json_bytes, read_bytes
    warnings: list[Diagnostic] = []
    if kind == "json":
        data, diags = from_json_bytes(data, label)
        warnings += diags
        if data is None:
            raise Unreadable(diags)
    c, diags = read_bytes(data, label)
    warnings += diags
    if c is None:
        raise Unreadable(diags)
    places = None
    if kind == "bin":
        places = [f"{label}:0x{off:X}" for off in entry_offsets(c)]
    return Source(label, kind, entries=c.entries, attributes=c.attributes, places=places,
                  warnings=[d for d in warnings if d.severity is not Severity.ERROR])


def _description(data: bytes, path: str, label: str, kind: str,
                 node_id: int | None) -> Source:
    from dcf2bin import formats
    dev = formats.load(path, node_id=node_id, data=data)
    errors = [p for p in dev.problems if p.diagnostic.severity is Severity.ERROR]
    if errors and not any(i >= 0x1000 for i in dev.objects):
        raise Unreadable([p.diagnostic for p in errors])
    return Source(label, kind, dev=dev, errors=errors)


def side(src: Source, node_id: int | None) -> tuple[Side, list[Diagnostic]]:
    """The comparable form of ``src``; ``node_id`` is for a description whose own
    node-ID is unknown (the other input's). Returns it and the reader's errors of no
    object (counted in ``Side.errors``); those of an object or entry, and values that
    cannot be worked out (kept as written), are in ``Side.problems``."""
    if src.dev is not None:
        out = _description_side(src, node_id)
        general = [p.diagnostic for p in src.errors if p.index is None]
        out.errors = len(general)
        out.problems[:0] = [(p.index, p.sub, p.diagnostic, False) for p in src.errors
                            if p.index is not None]
        return out, general
    items: dict[tuple[int, int], Item] = {}
    attrs = src.attributes
    for k, (index, sub, data) in enumerate(src.entries):
        attr = attrs[k] if attrs is not None and k < len(attrs) else None
        where = src.places[k] if src.places is not None else src.label
        items[(index, sub)] = Item(index, sub, Value(bytes(data)), attr=attr, where=where)
    return Side(src.label, src.kind, WRITES, items, objects_of(items)), []


def _description_side(src: Source, node_id: int | None) -> Side:
    dev = src.dev
    if dev.node_id is None and node_id is not None:
        dev.node_id = node_id
        dev.encoded.clear()          # no encoding made before holds a $NODEID value
    out = Side(src.label, src.kind, DESCRIPTION, node_id=dev.node_id)
    identity = _identity(dev)
    for obj in dev.sorted_objects():
        if obj.index < 0x1000:       # data type definitions hold no entries (SPEC §1)
            continue
        out.objects[obj.index] = ObjInfo(obj.name, obj.complex)
        count = None
        for e in obj.sorted_entries():
            value, problem = _value(dev, e)
            where = ""
            if value.implied and (e.index, e.sub) in identity:
                value, where = identity[(e.index, e.sub)]
            if problem is not None:
                out.problems.append((e.index, e.sub, problem, True))
            if e.sub == 0 and is_pdo_mapping(obj.index) and value.data is not None:
                count = int.from_bytes(value.data, "little")
            # a mapping's subs above its count are unused: compile writes 1..n (SPEC §3.2)
            unused = count is not None and e.sub > count
            out.items[(e.index, e.sub)] = Item(
                e.index, e.sub, value, e.dtype, e.access, e.pdo_mapping, name=e.name,
                configured=not unused and _changes_default(dev, e, value), entry=e,
                where=where)
    return out


def _identity(dev) -> dict[tuple[int, int], tuple[Value, str]]:
    """0x1018 sub 1-4 as the file states them outside the object (``model.identity``: the
    rule the software node answers by), each with the place of its key; only an UNSIGNED32
    entry takes one."""
    obj = dev.objects.get(0x1018)
    if obj is None:
        return {}
    from dcf2bin.model.identity import stated_identity
    out = {}
    for sub, stated in stated_identity(dev.ini).items():
        e = obj.entries.get(sub)
        if e is not None and e.dtype is not None and e.dtype.code == dt.UNSIGNED32.code:
            place = str(dev.ini.where(stated.line))
            out[(0x1018, sub)] = (Value(stated.value.to_bytes(4, "little"), source=stated.key),
                                  place)
    return out


def _changes_default(dev, e, value: Value) -> bool:
    """A write list must write this entry for a node at its defaults to hold the
    description's value: a ParameterValue or DownloadFile on a writable entry whose
    ObjFlags bit 0 is clear, other than its DefaultValue (the type's zero without one);
    not a PDO mapping's sub above its count, which no PDO block writes."""
    if not e.configured or e.access not in _WRITABLE or e.obj_flags & 1:
        return False
    if value.data is None:
        return True
    if e.default is None:
        from dcf2bin import values
        return value.data != values.zero(e.dtype)
    try:
        return value.data != dev.encode(e, e.default)
    except DcfError:
        return True


def _value(dev, e) -> tuple[Value, Diagnostic | None]:
    """An entry's effective value; a value that cannot be encoded is kept as written,
    with the encoder's error."""
    if e.param is None and e.download_file is not None:
        text = e.download_file
    else:
        text = e.value_text
        if text is None:             # the type's zero (SPEC §1), as compile writes it
            if e.dtype is None:
                return NO_VALUE, None
            from dcf2bin import values
            return Value(values.zero(e.dtype), implied=True), None
    if e.dtype is None:
        return Value(text=text, problem="no valid DataType"), None
    try:
        return Value(dev.encode(e), text=text), None
    except DcfError as exc:
        d = exc.diagnostic
        if d.rule == "DCF201":       # $NODEID and no node-ID on either side
            formula = _formula(e.dtype, text)
            if formula is not None:
                return Value(text=text, formula=formula), None
        problem = d.message.removeprefix(f"{e.label}: ")
        return Value(text=text, problem=problem), d


def _formula(dtype: dt.DataType, text: str) -> tuple[bytes, bytes] | None:
    from dcf2bin import values
    number = values.split_numeric_comment(text)[0]
    try:
        return (values.encode(dtype, number, node_id=1), values.encode(dtype, number, node_id=127))
    except values.ValueProblem:
        return None

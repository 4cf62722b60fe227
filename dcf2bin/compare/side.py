"""The one comparable form every input of ``diff`` is read into: a ``Side`` of ``Item``s,
one per (index, sub-index), each with its ``Value`` and what else the input says of the
entry (data type, access, PDO mapping, a container's attribute byte, its name).

A fact an input does not know is None (a container knows no exact data type, a node
nothing but its values), and a fact is compared only where both sides know it. Data
only: no reading, no rendering.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from dcf2bin import datatypes as dt

# What a Side is read from: a description (DCF/EDS, CiA 311 XML), a write list (a
# container, its JSON form, a concise DCF: only the entries it writes) or a live node.
DESCRIPTION, WRITES, NODE = "description", "writes", "node"


@dataclass(frozen=True, slots=True)
class Value:
    """An entry's value. ``data``: the bytes it holds; else ``formula``: a ``$NODEID``
    value where no node-ID is known, as the bytes it has at node-IDs 1 and 127 (two such
    values are equal for every node-ID exactly when they are equal at both: each is the
    node-ID plus a constant, or a constant); else ``problem``: why the text as written
    (``text``) has no bytes (a value out of range, an SDO abort). ``implied``: the input
    states no value, and ``data`` is the type's zero that stands for it (SPEC §1).
    ``source``: where a value the entry itself does not state comes from (an identity
    entry's ``[DeviceInfo] ProductNumber``: ``model.identity``). All None: no value and
    no type to give it one."""
    data: bytes | None = None
    text: str | None = None
    formula: tuple[bytes, bytes] | None = None
    problem: str | None = None
    implied: bool = False
    source: str | None = None

    @property
    def stated(self) -> bool:
        return not (self.data is None and self.formula is None and self.problem is None
                    and self.text is None)

    def key(self):
        """What two values are compared by (bytes for bytes, formula for formula, the
        text as written for values that have neither)."""
        if self.data is not None:
            return ("data", self.data)
        if self.formula is not None:
            return ("formula", self.formula)
        if self.text is not None or self.problem is not None:
            return ("text", (self.text or "").strip(), self.problem)
        return ("none",)


NO_VALUE = Value()


@dataclass(slots=True)
class Item:
    """One entry as one side holds it."""
    index: int
    sub: int
    value: Value = NO_VALUE
    dtype: dt.DataType | None = None
    access: str | None = None         # ro, wo, rw, rwr, rww, const
    pdo_mapping: bool | None = None
    attr: int | None = None           # a container's attribute byte
    name: str = ""                    # ParameterName
    configured: bool = False          # a description's value a write list must write
                                      # (readers._changes_default)
    where: str = ""                   # file:0x1C, "node 5" (a description: see ``place``)
    entry: object = None              # a description's model Entry

    @property
    def place(self) -> str:
        """Where the value stands: file:line of a description's value (worked out when
        asked: a large file's 60,000 entries need it only for what differs)."""
        if not self.where and self.entry is not None:
            self.where = str(self.entry.value_where)
        return self.where

    @property
    def label(self) -> str:
        return f"0x{self.index:04X}sub{self.sub:X}"

    @property
    def readable(self) -> bool | None:
        """Whether the entry can be read by SDO (None: not known)."""
        if self.access is not None:
            return self.access != "wo"
        if self.attr is not None:
            return bool(self.attr & dt.ATTR_READ)
        return None

    @property
    def read_only(self) -> bool | None:
        """``ro`` (a container: read, not write), None when not known; ``const`` is not."""
        if self.access is not None:
            return self.access == "ro"
        if self.attr is not None:
            return bool(self.attr & dt.ATTR_READ) and not self.attr & dt.ATTR_WRITE
        return None


@dataclass(slots=True)
class ObjInfo:
    """An object as a description names it: its name and whether it is an ARRAY/RECORD."""
    name: str = ""
    complex: bool = False


@dataclass
class Side:
    """One input, read: ``label`` names it in the output (the path as given, ``node 5``),
    ``kind`` is its file kind (dcf, xdd, bin, json, concise) or ``node``, ``source`` one
    of DESCRIPTION, WRITES, NODE."""
    label: str
    kind: str
    source: str
    items: dict[tuple[int, int], Item] = field(default_factory=dict)
    objects: dict[int, ObjInfo] = field(default_factory=dict)
    node_id: int | None = None
    # entries a node was not asked for -> why: "state", "ignored" (counted as left out),
    # "write-only", "no value" (the file gives none)
    unread: dict = field(default_factory=dict)
    # the errors its reader met of no object (a line that is no key, conflict markers):
    # it is compared as read, and never counts as equal
    errors: int = 0
    # errors of an object or entry: (index, sub or None for the whole object, Diagnostic,
    # True for a value that cannot be encoded and is compared as written); an error where
    # the entry takes part in the comparison, a warning where it does not (engine)
    problems: list = field(default_factory=list)

    def object_name(self, index: int) -> str:
        o = self.objects.get(index)
        return o.name if o is not None else ""

    def is_complex(self, index: int) -> bool | None:
        """ARRAY/RECORD (a write list or a node: it has a sub-index above 0); None when
        this side does not hold the object."""
        o = self.objects.get(index)
        return o.complex if o is not None else None


def objects_of(items) -> dict[int, ObjInfo]:
    """The objects of a write list or node, unnamed: complex where a sub-index above 0
    is held."""
    out: dict[int, ObjInfo] = {}
    for index, sub in items:
        o = out.get(index)
        if o is None:
            o = out[index] = ObjInfo()
        if sub > 0:
            o.complex = True
    return out

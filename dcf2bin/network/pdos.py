"""A node's PDOs: read from its file, then changed by the YAML (SPEC §10.1, D-17).

A PDO *exists in the network* when its COB-ID has bit 31 clear and it maps at least one
object. PDOs the YAML does not list keep their file's state (lely's rule). The mapping
rules (the object is in the file; TPDO: readable and not ``rww``; RPDO: writable and not
``rwr``) hold for every PDO that exists, whatever the master.
"""
from __future__ import annotations

from dcf2bin import datatypes as dt
from dcf2bin.diagnostics import DcfError, Diagnostics, Where, shorten
from dcf2bin.indexes import RPDO_COMM, TPDO_COMM
from dcf2bin.network.model import COB_INVALID, RPDO, TPDO, Mapped, Node, Pdo

# (kind, first comm index)
KINDS = ((RPDO, RPDO_COMM), (TPDO, TPDO_COMM))


def comm_index(kind: str, number: int) -> int:
    return (RPDO_COMM if kind == RPDO else TPDO_COMM) + number - 1


def map_index(kind: str, number: int) -> int:
    return comm_index(kind, number) + 0x200


def entry_int(dev, index: int, sub: int, default: int | None = None) -> int | None:
    """The effective value of an integer entry, or ``default`` (absent or unreadable:
    validate reports the value itself)."""
    e = dev.entry(index, sub)
    if e is None or e.dtype is None or not e.dtype.is_integer:
        return default
    try:
        return dev.effective_int(e)
    except (DcfError, ValueError):
        return default


def entry_where(dev, index: int, sub: int) -> Where:
    e = dev.entry(index, sub)
    if e is None:
        o = dev.objects.get(index)
        return (o.where if o is not None else None) or Where(dev.path)
    return e.value_where


def mapped_bits(dtype: dt.DataType | None) -> int | None:
    """§10.1: an object's length is its data type's size in bits, BOOLEAN 1."""
    if dtype is None or dtype.size is None:
        return None
    return 1 if dtype.kind == dt.BOOL else dtype.size * 8


_BY_NODE = object()      # a value that uses $NODEID: worked out per node


def _value(dev, index: int, sub: int, default):
    e = dev.entry(index, sub)
    if e is not None and e.value_text is not None and "$" in e.value_text:
        return _BY_NODE
    return entry_int(dev, index, sub, default)


def _template(dev) -> list[tuple]:
    """The PDOs of a file, their values worked out once for every node that uses the
    file (a value with $NODEID is marked, and worked out per node)."""
    objects = dev.objects
    out = []
    for kind, first in KINDS:
        for comm in range(first, first + 512):
            if comm not in objects:
                continue
            values = (_value(dev, comm, 1, COB_INVALID), _value(dev, comm, 2, 255),
                      _value(dev, comm, 3, 0) if kind == TPDO else 0,
                      _value(dev, comm, 5, 0),
                      _value(dev, comm, 6, 0) if kind == TPDO else 0)
            mapping = []
            mindex = comm + 0x200
            if mindex in objects:
                n = _value(dev, mindex, 0, 0)
                if n is _BY_NODE:
                    n = entry_int(dev, mindex, 0, 0)
                for sub in range(1, min(n or 0, 64) + 1):
                    mapping.append((sub, _value(dev, mindex, sub, 0),
                                    entry_where(dev, mindex, sub)))
            out.append((kind, comm - first + 1, comm, values, entry_where(dev, comm, 1),
                        mapping))
    return out


def from_file(node: Node, cache: dict | None = None) -> None:
    """node.pdos from its file: every PDO communication object with its mapping.
    ``cache``: a dict kept across the nodes of one network, so that the nodes sharing a
    file read its PDOs once."""
    dev = node.device
    key = id(dev.objects)
    tmpl = cache.get(key) if cache is not None else None
    if tmpl is None:
        tmpl = _template(dev)
        if cache is not None:
            cache[key] = tmpl
    subs = (1, 2, 3, 5, 6)
    defaults = (COB_INVALID, 255, 0, 0, 0)
    for kind, number, comm, values, where, mapping in tmpl:
        got = [entry_int(dev, comm, sub, d) if v is _BY_NODE else v
               for v, sub, d in zip(values, subs, defaults)]
        cob = got[0]
        pdo = Pdo(node.node_id, kind, number, cob, transmission=got[1],
                  inhibit_time=got[2], event_timer=got[3], sync_start=got[4],
                  where=where, file_cob_id=cob)
        for sub, v, mwhere in mapping:
            if v is _BY_NODE:
                v = entry_int(dev, comm + 0x200, sub, 0)
            v = v or 0
            index, msub, bits = v >> 16, (v >> 8) & 0xFF, v & 0xFF
            e = dev.entry(index, msub)
            code = e.dtype.code if e is not None and e.dtype is not None else (
                index if 1 <= index <= 7 else None)
            pdo.mapping.append(Mapped(index, msub, bits, code, None, mwhere))
        node.pdos.append(pdo)


def apply_yaml(node: Node, diags: Diagnostics) -> None:
    """The YAML's rpdo/tpdo entries on the node's PDOs: enabled, an explicit cob_id, the
    other subs, the mapping (COB-IDs to assign are left to ``cobids.assign``)."""
    for (kind, number), pc in sorted(node.pdo_config.items(),
                                     key=lambda kv: (kv[0][0] != RPDO, kv[0][1])):
        pdo = node.pdo(kind, number)
        if pdo is None:
            diags.error(f"{shorten(node.name)} has no {kind.upper()}{number} (its file lacks "
                        f"0x{comm_index(kind, number):04X})", pc.where, rule="NET101")
            continue
        pdo.listed, pdo.config, pdo.where = True, pc, pc.where
        for key in ("transmission", "inhibit_time", "sync_start"):
            value = getattr(pc, key)
            if value is not None and (key == "transmission" or kind == TPDO):
                setattr(pdo, key, value)
        if kind == TPDO and pc.event_timer is not None:
            pdo.event_timer = pc.event_timer
        if kind == RPDO and pc.event_deadline is not None:
            pdo.event_timer = pc.event_deadline
        if pc.mapping is not None:
            pdo.mapping = []
            first: dict[tuple[int, int], Where] = {}
            for mc in pc.mapping:
                m = yaml_mapped(node, kind, mc.index, mc.sub, mc.where, diags)
                if m is not None:
                    m.name = mc.name
                    pdo.mapping.append(m)
                    _once(node, pdo, m, first, diags)
            _fits(node, pdo, pc.wheres.get("mapping", pc.where), diags)
        if pc.empty_mapping and pc.enabled is not False:
            diags.warning(f"{shorten(node.name)} {pdo.label}: mapping: is empty, so the PDO is "
                          "enabled with no object: it exists on the device but not in the "
                          "network, and nothing links it (map an object, or write "
                          "enabled: false)", pc.wheres.get("mapping", pc.where),
                          rule="NET121")
        if pc.enabled is False:
            pdo.cob_id = (pdo.file_cob_id or 0) | COB_INVALID
        elif isinstance(pc.cob_id, int):
            pdo.cob_id = pc.cob_id


# SPEC §5: a PDO is one classic CAN frame, at most 8 bytes
MAX_PDO_BITS = 64


def _fits(node: Node, pdo: Pdo, where: Where, diags: Diagnostics) -> None:
    """NET125: a YAML mapping longer than a CAN frame (validate's DCF408 says it of a
    file's own mapping). Such a PDO is broken: nothing links it or is reported about it
    besides (one cause, one finding)."""
    total = sum(m.bits for m in pdo.mapping)
    if total > MAX_PDO_BITS:
        diags.error(f"{shorten(node.name)} {pdo.label} maps {total} bits, more than "
                    f"{MAX_PDO_BITS}: "
                    "a PDO is one CAN frame of at most 8 bytes", where, rule="NET125")
        pdo.broken = True


def _once(node: Node, pdo: Pdo, m: Mapped, first: dict, diags: Diagnostics) -> None:
    """NET122: one object twice in one YAML mapping (a dummy entry may repeat: it only
    skips bits)."""
    if m.is_dummy:
        return
    key = (m.index, m.sub)
    if key not in first:
        first[key] = m.where
        return
    what = ("sends it twice in every frame" if pdo.kind == TPDO
            else "writes it twice from every frame, the later value last")
    diags.warning(f"{shorten(node.name)} {pdo.label} maps 0x{m.index:04X}sub{m.sub:X} twice (also "
                  f"at line {first[key].line}): it {what}", m.where, rule="NET122")


def needs_id(pdo: Pdo) -> bool:
    """``cob_id: auto``, or an enabled listed PDO without cob_id whose file COB-ID is
    invalid (bit 31, or no CAN-ID)."""
    pc = pdo.config
    if pc is None or pc.enabled is False:
        return False
    if pc.cob_id == "auto":
        return True
    if pc.cob_id is not None:
        return False
    cob = pdo.file_cob_id
    return cob is None or bool(cob & COB_INVALID) or (cob & 0x7FF) == 0 and not cob & 0x20000000


def keep_file_id(pdo: Pdo) -> None:
    """An enabled listed PDO without cob_id whose file COB-ID is valid keeps it, bit 31
    cleared."""
    pc = pdo.config
    if pc is not None and pc.enabled is not False and pc.cob_id is None and not needs_id(pdo):
        pdo.cob_id = pdo.file_cob_id & ~COB_INVALID


def yaml_mapped(node: Node, kind: str, index: int, sub: int, where: Where,
                diags: Diagnostics) -> Mapped | None:
    dev = node.device
    if 1 <= index <= 7:          # a dummy entry: its data type is its index
        dtype = dt.BY_CODE.get(index)
        return Mapped(index, sub, mapped_bits(dtype) or 0, index, None, where)
    e = dev.entry(index, sub)
    if e is None:
        diags.error(f"{shorten(node.name)}'s file has no 0x{index:04X}sub{sub:X} to map",
                    where, rule="NET102")
        return None
    bits = mapped_bits(e.dtype)
    if bits is None:
        diags.error(f"0x{index:04X}sub{sub:X} of {shorten(node.name)} has no fixed size "
                    f"({e.dtype.name if e.dtype else 'no DataType'}): it cannot be mapped",
                    where, rule="NET103")
        return None
    if not _direction_ok(kind, e.access):
        diags.error(_direction_message(node, kind, index, sub, e.access), where,
                    rule="NET103")
        return None
    return Mapped(index, sub, bits, e.dtype.code, None, where)


def _direction_ok(kind: str, access: str | None) -> bool:
    return (access in dt.READABLE) if kind == TPDO else (access in dt.WRITABLE)


def _direction_message(node: Node, kind: str, index: int, sub: int, access) -> str:
    if kind == TPDO:
        need = "a TPDO maps readable objects that are not rww"
    else:
        need = "an RPDO maps writable objects that are not rwr"
    return (f"0x{index:04X}sub{sub:X} of {shorten(node.name)} is {access or 'without AccessType'}: "
            f"{need}")


def check_kept(node: Node, diags: Diagnostics) -> None:
    """The mapping rules for a PDO kept from the file that exists in the network; a zero
    entry among subs 1..n breaks it (neither mirrored nor counted): an error when the
    YAML lists that PDO, else a warning -- a vendor file keeping such a PDO that nobody
    uses does not stop the network (D-17)."""
    dev = node.device
    for pdo in node.pdos:
        if (pdo.config is not None and pdo.config.mapping is not None) or not pdo.exists:
            continue
        for m in pdo.mapping:
            if m.index == 0 and m.sub == 0 and m.bits == 0:
                if pdo.config is not None:
                    diags.error(f"{shorten(node.name)} {pdo.label} maps a zero entry (sub 0 counts "
                                f"{len(pdo.mapping)} objects); the network file lists this "
                                "PDO: give its mapping, or disable it", m.where,
                                rule="NET105")
                else:
                    diags.warning(f"{shorten(node.name)} {pdo.label} maps a zero entry (sub 0 "
                                  "counts "
                                  f"{len(pdo.mapping)} objects): the PDO is kept as the "
                                  "file has it, and nothing links it", m.where,
                                  rule="NET105")
                pdo.broken = True
                break
            if m.is_dummy:
                continue
            e = dev.entry(m.index, m.sub)
            if e is None:
                diags.error(f"{shorten(node.name)} {pdo.label} maps 0x{m.index:04X}sub{m.sub:X}, "
                            "which its file lacks", m.where, rule="NET102")
                pdo.broken = True
            elif not _direction_ok(pdo.kind, e.access):
                diags.error(_direction_message(node, pdo.kind, m.index, m.sub, e.access),
                            m.where, rule="NET103")
                pdo.broken = True

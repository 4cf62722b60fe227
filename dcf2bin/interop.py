"""The model as a python-canopen ``ObjectDictionary`` (for SDO download and friends).

Values are decoded from the exact bytes dcf2bin would write, so what python-canopen
sees is what the container holds. A value that cannot be encoded (out of range,
$NODEID without a node-ID) is left unset (None); ``dcf2bin validate`` reports it.
"""
from __future__ import annotations

from dcf2bin import values
from dcf2bin.diagnostics import DcfError


def _variable(od_mod, dev, entry, name: str):
    var = od_mod.ODVariable(name or f"0x{entry.index:04X}sub{entry.sub}", entry.index, entry.sub)
    if entry.dtype is not None:
        var.data_type = entry.dtype.code
    var.access_type = entry.access or "rw"
    var.pdo_mappable = bool(entry.pdo_mapping)
    if entry.dtype is not None and entry.dtype.size is not None:
        for attr, text in (("min", entry.low), ("max", entry.high)):
            if text is not None:
                try:
                    setattr(var, attr, values.to_python(entry.dtype, dev.encode(entry, text),
                                                        dev.encoding))
                except DcfError:
                    pass
    if entry.dtype is not None:
        try:
            if entry.default is not None:
                var.default = values.to_python(entry.dtype, dev.encode(entry, entry.default),
                                                dev.encoding)
            if entry.configured:
                var.value = values.to_python(entry.dtype, dev.encode(entry), dev.encoding)
        except DcfError:
            pass
    return var


def to_canopen(dev):
    """Build a ``canopen.objectdictionary.ObjectDictionary`` from a dcf2bin Device."""
    import canopen.objectdictionary as od_mod
    from dcf2bin import datatypes as dt

    od = od_mod.ObjectDictionary()
    od.node_id = dev.node_id
    for obj in dev.sorted_objects():
        if obj.index < 0x1000:
            continue
        if not obj.complex:
            od.add_object(_variable(od_mod, dev, obj.entries[0], obj.name))
            continue
        cls = od_mod.ODArray if obj.object_type == dt.OT_ARRAY else od_mod.ODRecord
        container = cls(obj.name or f"0x{obj.index:04X}", obj.index)
        for e in obj.entries.values():
            container.add_member(_variable(od_mod, dev, e, e.name or f"sub{e.sub}"))
        od.add_object(container)
    return od

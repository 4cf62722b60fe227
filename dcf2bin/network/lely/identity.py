"""The identity a lely master checks (0x1F84-0x1F88), as dcfgen fills it, and the master's
own writes, its ``master.bin`` (D-21).

Per slave: the device type (0x1000); the vendor-ID and product code from the YAML's
``vendor_id``/``product_code`` (dcf2bin's keys), else the file's [DeviceInfo]
VendorNumber/ProductNumber, else its 0x1018 sub 1/2; the revision and serial number from
the YAML's ``revision_number``/``serial_number``, else [DeviceInfo] RevisionNumber /
[DeviceComissioning] LSS_SerialNumber, else 0x1018 sub 3/4. Each only when nonzero; the
product code, revision and serial number only when the slave's 0x1018 has that sub (the
master reads it there). 0x1F84-0x1F86 go into ``master.dcf``, 0x1F55, 0x1F87 and 0x1F88
into ``master.bin``.
"""
from __future__ import annotations

from dcf2bin import datatypes as dt
from dcf2bin import values
from dcf2bin.network.entries import int_write
from dcf2bin.network.lely.order import dcfgen_order
from dcf2bin.network.model import Network, Node, Write
from dcf2bin.network.pdos import entry_int

# index -> (YAML key, (INI section, key) of the file, 0x1018 sub)
_SOURCES = {0x1F85: ("vendor_id", ("deviceinfo", "vendornumber"), 1),
            0x1F86: ("product_code", ("deviceinfo", "productnumber"), 2),
            0x1F87: ("revision_number", ("deviceinfo", "revisionnumber"), 3),
            0x1F88: ("serial_number", ("devicecomissioning", "lss_serialnumber"), 4)}


def identity(slave: Node) -> dict[int, int]:
    """0x1F84-0x1F88 -> value for ``slave``: only the nonzero ones it can be checked by."""
    dev = slave.device
    out = {0x1F84: entry_int(dev, 0x1000, 0, 0) or 0}
    for index, (key, (section, ini_key), sub) in _SOURCES.items():
        if sub > 1 and dev.entry(0x1018, sub) is None:
            continue
        if key in slave.config:
            out[index] = slave.config[key]
            continue
        value = _ini_int(dev, section, ini_key)
        out[index] = value if value is not None else (entry_int(dev, 0x1018, sub, 0) or 0)
    return {k: v for k, v in out.items() if v}


def _ini_int(dev, section: str, key: str) -> int | None:
    sec = dev.ini.section(section) if dev.ini is not None else None
    text = sec.get(key) if sec is not None else None
    if not text:
        return None
    try:
        return values.parse_int(values.split_numeric_comment(text)[0])
    except values.ValueProblem:
        return None


def apply(net: Network) -> None:
    """Every slave's identity as a lely master checks it (``show`` and ``scan`` read it)."""
    for s in net.slaves:
        if s.device is not None:
            s.identity = identity(s)


def master_writes(net: Network) -> list[Write]:
    """The lely master's own configuration (``master.bin``), slaves in dcfgen's order:
    0x1F55 (``software_version``), 0x1F87, 0x1F88; each only when nonzero. (dcfgen also
    writes the master's own ``serial_number`` here, into 0x1018 sub 4, which master.dcf
    marks ro; dcf2bin states it as that entry's DefaultValue: docs/network.md.)"""
    out = []
    for s in dcfgen_order(net):
        version = s.config.get("software_version", 0)
        for index, value, why in ((0x1F55, version, "software version"),
                                  (0x1F87, s.identity.get(0x1F87, 0), "revision number"),
                                  (0x1F88, s.identity.get(0x1F88, 0), "serial number")):
            if value:
                out.append(int_write(dt.UNSIGNED32, index, s.node_id, value, "",
                                     f"{s.name}'s {why}", s.where))
    return out

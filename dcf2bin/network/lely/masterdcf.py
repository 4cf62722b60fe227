"""``master.dcf`` of a lely master, as text (D-21): the sections, keys and values that
``dcfgen -r`` (lely dcf-tools 2.4.2) writes, in its order.

The file is a list of sections, each a list of (key, value); :func:`render` joins them.
Everything the master does is stated as DefaultValue: its PDOs (layout), the slaves it
manages (0x1F81), monitors (0x1016), checks (0x1F84-0x1F86), whose EMCY it consumes
(0x1028), configures (0x1F22 names each slave's concise DCF with ``UploadFile=``), restores
(0x1F8A) and updates (0x1F58 names a slave's ``software_file``). The master's own keys
give its identity (0x1018, [DeviceInfo]) and 0x1012, 0x1015, 0x1019, 0x1029, 0x102A.
"""
from __future__ import annotations

import posixpath

from dcf2bin.network.lely.layout import Layout, MasterPdo, layout
from dcf2bin.network.lely.order import dcfgen_order
from dcf2bin.network.model import COB_INVALID, Network, Node
from dcf2bin.network.pdos import entry_int
from dcf2bin.network.slaveconfig import multiplier, times

Section = tuple[str, list[tuple[str, str]]]

_DUMMIES = (0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x10, 0x12, 0x13, 0x14, 0x15, 0x16,
            0x18, 0x19, 0x1A, 0x1B)
_MANAGER = (0x1F25, 0x1F55, 0x1F58, 0x1F80, 0x1F81, 0x1F82, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88,
            0x1F89, 0x1F8A)


def h8(v: int) -> str:
    return f"0x{v:08X}"


def render(sections: list[Section]) -> str:
    return "\n".join(f"[{name}]\n" + "".join(f"{k}={v}\n" for k, v in keys)
                     for name, keys in sections)


def var(name: str, dtype: int, access: str, default: str | None = None,
        *extra: tuple[str, str]) -> list[tuple[str, str]]:
    keys = [("ParameterName", name), ("DataType", f"0x{dtype:04X}"), ("AccessType", access)]
    if default is not None:
        keys.append(("DefaultValue", default))
    return keys + list(extra)


def array(index: int, name: str, dtype: int, access: str, count: int,
          values: dict[int, str] | None = None, default: str | None = None) -> list[Section]:
    """A CompactSubObj array, with its [xxxxValue] section when ``values`` is given."""
    keys = [("ParameterName", name), ("ObjectType", "0x08"), ("DataType", f"0x{dtype:04X}"),
            ("AccessType", access)]
    if default is not None:
        keys.append(("DefaultValue", default))
    out = [(f"{index:04X}", keys + [("CompactSubObj", str(count))])]
    if values is not None:
        out.append((f"{index:04X}Value", [("NrOfEntries", str(len(values)))]
                    + [(str(k), v) for k, v in values.items()]))
    return out


def record(index: int, name: str, subs: list[list[tuple[str, str]]],
           object_type: str = "0x09") -> list[Section]:
    """A RECORD (or, with ``object_type`` 0x08, an ARRAY) with one section per sub."""
    out = [(f"{index:04X}", [("SubNumber", str(len(subs))), ("ParameterName", name),
                             ("ObjectType", object_type)])]
    return out + [(f"{index:04X}sub{k:X}", keys) for k, keys in enumerate(subs)]


def master_dcf(net: Network, names: dict[str, str]) -> str:
    """The text of the lely master's DCF."""
    lay = layout(net)
    slaves = dcfgen_order(net)
    master = net.master
    uploads = {s.node_id: upload_file(net, s, names[s.name]) for s in slaves}
    sections = [_file_info(names[master.name] + ".dcf")] + _header(master, lay)
    sections += _lists(master, lay, bool(uploads), _updates(slaves))
    sections += _communication(net, slaves)
    sections += _pdos(lay)
    if uploads:
        sections += record(0x1F22, "Concise DCF", [var("Highest sub-index supported", 0x05,
                                                        "const", "127")]
                           + [var(f"Node-ID {i}", 0x0F, "ro", None,
                                  *([("UploadFile", uploads[i])] if i in uploads else []))
                              for i in range(1, 128)], "0x08")
    sections += _manager(net, slaves)
    for rec in lay.records:
        access = "rww" if rec.index < 0x2200 else "rwr"
        sections += record(rec.index, rec.title,
                           [var("Highest sub-index supported", 0x05, "const",
                                str(len(rec.subs)))]
                           + [var(s.name, s.datatype, access, None, ("PDOMapping", "1"))
                              for s in rec.subs])
    sections += _remote(lay)
    return render(sections)


def upload_file(net: Network, s: Node, base: str) -> str:
    """The slave's concise DCF as the lely master finds it: the slave's
    ``configuration_file``, else ``<base>.bin`` under the slave's ``dcf_path``, else under
    ``options: dcf_path``; as written (ros2_canopen's build replaces @BUS_CONFIG_PATH@
    before; dcfgen expands $VARIABLES from its environment, dcf2bin does not).
    (dcfgen 2.4.2 reads ``configuration_file`` into its dcf_path, which it has used
    already, so the key has no effect there: docs/network.md.)"""
    if "configuration_file" in s.config:
        return s.config["configuration_file"]
    folder = s.config.get("dcf_path", net.options.get("dcf_path", ""))
    return posixpath.join(folder, base + ".bin")


def _updates(slaves: list[Node]) -> dict[int, str]:
    """node-ID -> the program the master downloads to it (``software_file``, 0x1F58)."""
    return {s.node_id: s.config["software_file"] for s in slaves
            if "software_file" in s.config}


def _file_info(file_name: str) -> Section:
    """[FileInfo], which dcfgen does not write and CiA 306 requires (validate: DCF060):
    no CreationDate/CreationTime, as bin2dcf and allocate write none, so that a build of
    the same network gives the same bytes (the tests' golden files, a user's diff)."""
    return ("FileInfo", [("FileName", file_name), ("FileVersion", "1"),
                         ("FileRevision", "0"), ("EDSVersion", "4.0"),
                         ("Description", "lely master built by dcf2bin network build"),
                         ("CreatedBy", "dcf2bin network build")])


def _header(master: Node, lay: Layout) -> list[Section]:
    cfg = master.config
    baud = cfg.get("baudrate", 1000)
    info = [("VendorName", ""), ("VendorNumber", h8(cfg.get("vendor_id", 0))),
            ("ProductName", ""), ("ProductNumber", h8(cfg.get("product_code", 0))),
            ("RevisionNumber", h8(cfg.get("revision_number", 0))), ("OrderCode", "")]
    info += [(f"BaudRate_{b}", "1") for b in (10, 20, 50, 125, 250, 500, 800, 1000)]
    info += [("SimpleBootUpMaster", "1"), ("SimpleBootUpSlave", "0"), ("Granularity", "1"),
             ("DynamicChannelsSupported", "0"), ("GroupMessaging", "0"),
             ("NrOfRxPDO", str(len(lay.rpdos))), ("NrOfTxPDO", str(len(lay.tpdos))),
             ("LSS_Supported", "1")]
    return [("DeviceComissioning",
             [("NodeID", str(master.node_id)), ("NodeName", ""), ("NodeRefd", ""),
              ("Baudrate", str(baud)), ("NetNumber", "1"), ("NetworkName", ""),
              ("NetRefd", ""), ("CANopenManager", "1"),
              ("LSS_SerialNumber", h8(cfg.get("serial_number", 0)))]),
            ("DeviceInfo", info),
            ("DummyUsage", [(f"Dummy{d:04X}", "1") for d in _DUMMIES])]


def _object_list(name: str, indexes: list[int]) -> Section:
    return (name, [("SupportedObjects", str(len(indexes)))]
            + [(str(k), f"0x{i:04X}") for k, i in enumerate(indexes, 1)])


def _lists(master: Node, lay: Layout, configures: bool,
           updates: dict[int, str]) -> list[Section]:
    consumer = master.config.get("heartbeat_consumer", True) is not False
    nr, nt = len(lay.rpdos), len(lay.tpdos)
    optional = [0x1003, 0x1005, 0x1006, 0x1007, 0x1012, 0x1013, 0x1014, 0x1015]
    optional += [0x1016] if consumer else []
    optional += [0x1017, 0x1019, 0x1028, 0x1029, 0x102A]
    for first, count in ((0x1400, nr), (0x1600, nr), (0x1800, nt), (0x1A00, nt)):
        optional += range(first, first + count)
    optional += [0x1F22] if configures else []
    optional += [i for i in _MANAGER if i != 0x1F58 or updates]
    maker = [r.index for r in lay.records]
    for first, count in ((0x5800, nr), (0x5A00, nr), (0x5C00, nt), (0x5E00, nt)):
        maker += range(first, first + count)
    return [_object_list("MandatoryObjects", [0x1000, 0x1001, 0x1018]),
            _object_list("OptionalObjects", optional),
            _object_list("ManufacturerObjects", maker)]


def _communication(net: Network, slaves: list[Node]) -> list[Section]:
    master = net.master
    cfg = master.config
    out = [("1000", var("Device type", 0x07, "ro", h8(0))),
           ("1001", var("Error register", 0x05, "ro"))]
    out += array(0x1003, "Pre-defined error field", 0x07, "ro", 254)
    out += [("1005", var("COB-ID SYNC message", 0x07, "rw", "0x40000080")),
            ("1006", var("Communication cycle period", 0x07, "rw",
                         str(cfg.get("sync_period", 0)))),
            ("1007", var("Synchronous window length", 0x07, "rw",
                         str(cfg.get("sync_window", 0)))),
            ("1012", var("COB-ID time stamp object", 0x07, "rw",
                         h8(cfg.get("time_cob_id", 0x100)))),
            ("1013", var("High resolution time stamp", 0x07, "rw", None,
                         ("PDOMapping", "1"))),
            ("1014", var("COB-ID EMCY", 0x07, "rw", "$NODEID+0x80")),
            ("1015", var("Inhibit time EMCY", 0x06, "rw",
                         str(cfg.get("emcy_inhibit_time", 0))))]
    if cfg.get("heartbeat_consumer", True) is not False:
        out += array(0x1016, "Consumer heartbeat time", 0x07, "rw", 127,
                     _consumers(net, slaves))
    out += [("1017", var("Producer heartbeat time", 0x06, "rw",
                         str(cfg.get("heartbeat_producer", 0))))]
    # the master's own serial number as the entry's value: dcfgen writes it in master.bin,
    # a concise DCF that would write a read-only entry (docs/network.md)
    serial = [h8(cfg["serial_number"])] if cfg.get("serial_number") else []
    out += record(0x1018, "Identity Object",
                  [var("Highest sub-index supported", 0x05, "const", "4"),
                   var("Vendor-ID", 0x07, "ro", h8(cfg.get("vendor_id", 0))),
                   var("Product code", 0x07, "ro", h8(cfg.get("product_code", 0))),
                   var("Revision number", 0x07, "ro", h8(cfg.get("revision_number", 0))),
                   var("Serial number", 0x07, "ro", *serial)])
    out += [("1019", var("Synchronous counter overflow value", 0x05, "rw",
                         str(cfg.get("sync_overflow", 0))))]
    emcy = {}
    for s in slaves:
        cob = entry_int(s.device, 0x1014, 0) if s.device is not None else None
        if cob is not None and not cob & COB_INVALID:
            emcy[s.node_id] = h8(cob)
    out += array(0x1028, "Emergency consumer object", 0x07, "rw", 127, emcy, h8(COB_INVALID))
    behavior = {1: 0} | {k: v for k, (v, _) in cfg.get("error_behavior", {}).items()}
    out += array(0x1029, "Error behavior object", 0x05, "rw", 254,
                 {k: f"0x{behavior[k]:02X}" for k in sorted(behavior)})
    out += [("102A", var("NMT inhibit time", 0x06, "rw",
                         str(cfg.get("nmt_inhibit_time", 0))))]
    return out


def _consumers(net: Network, slaves: list[Node]) -> dict[int, str]:
    """0x1016: one sub per slave that produces a heartbeat, in dcfgen's order; a time of
    the master's ``{slave: ms}`` mapping instead of producer time x multiplier."""
    setting = net.master.config.get("heartbeat_consumer", True)
    explicit = setting if isinstance(setting, dict) else {}
    out = {}
    for s in slaves:
        if s.name in explicit:
            t = explicit[s.name][0]
        elif s.heartbeat_producer:
            t = times(s.heartbeat_producer, multiplier(net, s))
        else:
            continue
        out[len(out) + 1] = h8((s.node_id << 16) | t)
    return out


def _comm(kind: str, mp: MasterPdo) -> list[list[tuple[str, str]]]:
    m = mp.mirror
    cob = var(f"COB-ID used by {kind}", 0x07, "rw", h8(m.cob_id))
    trans = var("transmission type", 0x05, "rw", f"0x{m.transmission:02X}")
    if kind == "RPDO":
        return [var("highest sub-index supported", 0x05, "const", "5"), cob, trans,
                var("inhibit time", 0x06, "rw"), var("compatibility entry", 0x05, "rw"),
                var("event-timer", 0x06, "rw", "0")]
    pc = mp.src.config
    sync_start = pc.sync_start if pc is not None and pc.sync_start is not None else 0
    return [var("highest sub-index supported", 0x05, "const", "6"), cob, trans,
            var("inhibit time", 0x06, "rw", str(m.inhibit_time)),
            var("reserved", 0x05, "rw"), var("event timer", 0x06, "rw", str(m.event_timer)),
            var("SYNC start value", 0x05, "rw", str(sync_start))]


def _pdos(lay: Layout) -> list[Section]:
    out: list[Section] = []
    for kind, rows, comm in (("RPDO", lay.rpdos, 0x1400), ("TPDO", lay.tpdos, 0x1800)):
        for mp in rows:
            out += record(comm + mp.mirror.number - 1, f"{kind} communication parameter",
                          _comm(kind, mp))
        for mp in rows:
            index = comm + 0x200 + mp.mirror.number - 1
            keys = [("ParameterName", f"{kind} mapping parameter"), ("ObjectType", "0x09"),
                    ("DataType", "0x0007"), ("AccessType", "rw"),
                    ("CompactSubObj", str(len(mp.mapping)))]
            out.append((f"{index:04X}", keys))
            out.append((f"{index:04X}Value", [("NrOfEntries", str(len(mp.mapping)))]
                        + [(str(k), h8(v)) for k, v in enumerate(mp.mapping, 1)]))
    return out


def slave_assignment(net: Network, s: Node) -> int:
    """0x1F81 as dcfgen fills it: software update (``software_file``, bit 6), restore
    (``restore_configuration``, bit 7), the retry factor and the guard time (YAML, else
    the file's 0x100C) -- no guard time when the slave also has a life time factor and
    produces a heartbeat, which rules node guarding out."""
    sc = s.config
    guard = _configured(s, 0x100C, "guard_time")
    life = _configured(s, 0x100D, "life_time_factor")
    if guard and life and s.heartbeat_producer:
        guard = 0
    return (0x01 | (0x04 if sc.get("boot", True) else 0)
            | (0x08 if sc.get("mandatory", False) else 0)
            | (0x10 if not sc.get("reset_communication", True) else 0)
            | (0x20 if sc.get("software_version", 0) else 0)
            | (0x40 if "software_file" in sc else 0)
            | (0x80 if sc.get("restore_configuration", 0) else 0)
            | (sc.get("retry_factor", net.options.get("retry_factor", 3)) << 8)
            | (guard << 16)) & 0xFFFFFFFF


def _configured(s: Node, index: int, key: str) -> int:
    if key in s.config:
        return s.config[key]
    return (entry_int(s.device, index, 0, 0) or 0) if s.device is not None else 0


def _manager(net: Network, slaves: list[Node]) -> list[Section]:
    cfg = net.master.config
    out = array(0x1F25, "Configuration request", 0x05, "wo", 127)
    out += array(0x1F55, "Expected software identification", 0x07, "rw", 127)
    updates = _updates(slaves)
    if updates:
        out += record(0x1F58, "Program data", [var("Highest sub-index supported", 0x05,
                                                    "const", "127")]
                      + [var(f"Program data of node-ID {i}", 0x0F, "ro", None,
                             *([("UploadFile", updates[i])] if i in updates else []))
                         for i in range(1, 128)], "0x08")
    start = (0x01 | (0x02 if cfg.get("start_all_nodes", False) else 0)
             | (0x04 if not cfg.get("start", True) else 0)
             | (0x08 if not cfg.get("start_nodes", True) else 0)
             | (0x10 if cfg.get("reset_all_nodes", False) else 0)
             | (0x40 if cfg.get("stop_all_nodes", False) else 0))
    out.append(("1F80", var("NMT startup", 0x07, "rw", h8(start))))
    out += array(0x1F81, "NMT slave assignment", 0x07, "rw", 127,
                 {s.node_id: h8(slave_assignment(net, s)) for s in slaves})
    out += array(0x1F82, "Request NMT", 0x05, "rw", 127)
    for index, name in ((0x1F84, "Device type identification"),
                        (0x1F85, "Vendor identification"), (0x1F86, "Product code")):
        out += array(index, name, 0x07, "rw", 127,
                     {s.node_id: h8(s.identity[index]) for s in slaves
                      if index in s.identity})
    out += array(0x1F87, "Revision_number", 0x07, "rw", 127)
    out += array(0x1F88, "Serial number", 0x07, "rw", 127)
    out.append(("1F89", var("Boot time", 0x07, "rw", str(cfg.get("boot_time", 0)))))
    out += array(0x1F8A, "Restore configuration", 0x05, "rw", 127,
                 {s.node_id: f"0x{s.config['restore_configuration']:02X}" for s in slaves
                  if s.config.get("restore_configuration", 0)})
    return out


def _remote(lay: Layout) -> list[Section]:
    out: list[Section] = []
    for kind, rows, first in (("TPDO", lay.rpdos, 0x5800), ("RPDO", lay.tpdos, 0x5C00)):
        for mp in rows:
            out.append((f"{first + mp.mirror.number - 1:04X}",
                        var(f"Remote {kind} number and node-ID", 0x07, "rw",
                            f"0x{mp.src.number:06X}{mp.slave.node_id:02X}")))
        for mp in rows:
            remote = mp.remote
            out += array(first + 0x200 + mp.mirror.number - 1, f"Remote {kind} mapping parameter",
                         0x07, "rw", len(remote),
                         {k: h8(v) for k, v in enumerate(remote, 1)})
    return out

"""The PLC's NMT entries (SPEC §10.2, D-17): the objects lely's dcfgen fills, with the
values D-17 gives (docs/network.md lists where dcfgen's differ: 0x1F85-0x1F88 taken from
the slave's file, 0x1F81 bit 6, 0x1F55 for a zero software_version, 0x1016 truncated).

0x1F81, 0x1F84-0x1F86 and 0x1016 always; 0x1F87, 0x1F88, 0x1F55, 0x1017, 0x1006, 0x1007,
0x1F80, 0x1F89, and the lely master keys a PLC takes too (0x1019, 0x1012, 0x1015, 0x102A,
0x1029, 0x1F8A with 0x1F81 bit 7) only when the YAML gives a key they come from; 0x1005
with ``sync_period``; 0x1F22 whenever the PLC's file has it (filled in by ``concise``).
An entry the PLC's file lacks is a warning and not written; a sub beyond its object's
subs is an error. A key of dcfgen's that a PLC master does not use is a warning.
"""
from __future__ import annotations

from dcf2bin.diagnostics import Diagnostics, Where, shorten
from dcf2bin.network.entries import write_to
from dcf2bin.network.model import Heartbeat, Network, Node
from dcf2bin.network.pdos import entry_int
from dcf2bin.network.slaveconfig import multiplier, times

_MISSING_WHY = {0x1F81: "slave assignment", 0x1F84: "device type check",
                0x1F85: "vendor-ID check", 0x1F86: "product code check",
                0x1F87: "revision check", 0x1F88: "serial number check",
                0x1F55: "software version check", 0x1016: "heartbeat consumer",
                0x1017: "heartbeat producer", 0x1006: "SYNC period", 0x1007: "SYNC window",
                0x1005: "SYNC producer", 0x1F80: "NMT start-up", 0x1F89: "boot time",
                0x1F22: "concise DCFs", 0x1019: "SYNC counter", 0x1012: "TIME COB-ID",
                0x1015: "EMCY inhibit time", 0x102A: "NMT inhibit time",
                0x1029: "error behaviour", 0x1F8A: "restore configuration"}


class PlcWriter:
    """Collects the PLC's configured entries (master.settings, master.writes)."""

    def __init__(self, master: Node, diags: Diagnostics):
        self.master = master
        self.diags = diags
        self.warned: set[int] = set()

    def put(self, index: int, sub: int, value, why: str, where: Where | None) -> None:
        dev = self.master.device
        if dev is not None and index not in dev.objects:
            if index not in self.warned:
                self.warned.add(index)
                self.diags.warning(f"the PLC's file has no 0x{index:04X}: the PLC cannot do "
                                   f"the {_MISSING_WHY.get(index, 'entry')} ({why}); not "
                                   "written", where, rule="NET110")
            return
        w = write_to(dev, index, sub, value, why, where, self.diags, rule="NET111",
                     slave=False, who="the PLC")
        if w is not None:
            self.master.writes.append(w)
            self.master.settings[(index, sub)] = w


def identity(slave: Node, diags: Diagnostics) -> dict[int, int]:
    """0x1F84-0x1F88 for a slave: device type, vendor, product (YAML or [DeviceInfo]),
    revision and serial (YAML); only the nonzero ones."""
    dev, cfg = slave.device, slave.config
    out = {0x1F84: entry_int(dev, 0x1000, 0, 0) or 0}
    info = dev.ini.section("deviceinfo") if dev.ini is not None else None
    for index, key, info_key, sub in ((0x1F85, "vendor_id", "vendornumber", 1),
                                      (0x1F86, "product_code", "productnumber", 2)):
        if key in cfg:
            out[index] = cfg[key]
            continue
        value = _info_int(info, info_key)
        out[index] = value or 0
        e = dev.entry(0x1018, sub)
        if value is not None and e is not None and e.default is not None:
            own = entry_int(dev, 0x1018, sub)
            if own is not None and own != value:
                diags.warning(f"{shorten(slave.name)}: [DeviceInfo] "
                              f"{shorten(info.keys[info_key].name)} is "
                              f"0x{value:X} but its 0x1018sub{sub} is 0x{own:X}; the master "
                              f"will expect 0x{value:X}",
                              Where(dev.path, info.line_of(info_key)), rule="NET113")
    out[0x1F87] = cfg.get("revision_number", 0)
    out[0x1F88] = cfg.get("serial_number", 0)
    return {k: v for k, v in out.items() if v}


def _info_int(info, key: str) -> int | None:
    if info is None or info.get(key) is None:
        return None
    from dcf2bin import values
    try:
        return values.parse_int(values.split_numeric_comment(info.get(key))[0])
    except values.ValueProblem:
        return None


def nmt_entries(net: Network, plc: PlcWriter, diags: Diagnostics) -> None:
    master = net.master
    cfg, mw = master.config, master.config_where
    retry_default = net.options.get("retry_factor", 3)
    for s in net.slaves:
        sc, where = s.config, s.where
        value = (0x01 | (0x04 if sc.get("boot", True) else 0)
                 | (0x08 if sc.get("mandatory", False) else 0)
                 | (0x10 if not sc.get("reset_communication", True) else 0)
                 | (0x20 if sc.get("software_version", 0) else 0)
                 | (sc.get("retry_factor", retry_default) << 8)
                 | (sc.get("guard_time", 0) << 16))
        if _restore(plc, s):
            value |= 0x80
        plc.put(0x1F81, s.node_id, value, f"slave assignment of {s.name}", where)
        if s.device is not None:
            s.identity = identity(s, diags)
        for index, v in sorted(s.identity.items()):
            plc.put(index, s.node_id, v, f"{s.name}'s {_MISSING_WHY[index]}", where)
        if "software_version" in sc:
            plc.put(0x1F55, s.node_id, sc["software_version"], f"{s.name}'s software version",
                    s.config_where.get("software_version"))
    _consumers(net, plc, diags)
    if "heartbeat_producer" in cfg:
        plc.put(0x1017, 0, cfg["heartbeat_producer"], "producer heartbeat time",
                mw["heartbeat_producer"])
    for key, index, why in (("sync_period", 0x1006, "communication cycle period (µs)"),
                            ("sync_window", 0x1007, "synchronous window length (µs)"),
                            ("boot_time", 0x1F89, "boot time (ms)")):
        if key in cfg:
            plc.put(index, 0, cfg[key], why, mw[key])
    if cfg.get("sync_period"):
        dev = master.device
        can = (entry_int(dev, 0x1005, 0, 0x80) if dev is not None else 0x80) & 0x7FF
        plc.put(0x1005, 0, 0x40000000 | can, "COB-ID SYNC: the PLC produces SYNC",
                mw["sync_period"])
    keys = ("start", "start_nodes", "start_all_nodes", "reset_all_nodes", "stop_all_nodes")
    given = [k for k in keys if k in cfg]
    if given:
        value = (0x01 | (0x02 if cfg.get("start_all_nodes", False) else 0)
                 | (0x04 if not cfg.get("start", True) else 0)
                 | (0x08 if not cfg.get("start_nodes", True) else 0)
                 | (0x10 if cfg.get("reset_all_nodes", False) else 0)
                 | (0x40 if cfg.get("stop_all_nodes", False) else 0))
        plc.put(0x1F80, 0, value, "NMT start-up", mw[given[0]])
    if master.device is not None:
        _plc_keys(net, plc, diags)


# the master's keys of lely's dcfgen that a PLC's own objects take (D-17, as 0x1006/0x1007)
_PLC_OBJECTS = (("sync_overflow", 0x1019, "synchronous counter overflow value"),
                ("time_cob_id", 0x1012, "COB-ID TIME"),
                ("emcy_inhibit_time", 0x1015, "inhibit time EMCY (x 100 us)"),
                ("nmt_inhibit_time", 0x102A, "NMT inhibit time (x 100 us)"))
_IDENTITY = ("vendor_id", "product_code", "revision_number", "serial_number")
_UPLOAD = "a PLC master holds the slaves' concise DCFs in its own 0x1F22"
# a key that does not apply to a PLC master: what it does for a lely master, why not here
_NOT_FOR_A_PLC = {
    "identity": ("lely's dcfgen writes {them} as a lely master's own identity (0x1018 sub "
                 "1-4, [DeviceInfo], LSS_SerialNumber)", "a PLC's identity is its own "
                 "file's"),
    "dcf_path": ("lely's dcfgen names the concise DCFs under it in a lely master's "
                 "0x1F22 (UploadFile=)", _UPLOAD),
    "configuration_file": ("it names the slave's concise DCF in a lely master's 0x1F22 "
                           "(UploadFile=; lely's dcfgen 2.4.2 reads it but does not use "
                           "it)", _UPLOAD),
    "software_file": ("lely's dcfgen has a lely master download this program to the slave "
                      "(0x1F58, 0x1F81 bit 6)", "dcf2bin does not configure a PLC's "
                      "program download"),
}


def _not_for_a_plc(key: str, where: Where | None, diags: Diagnostics,
                   keys: str | None = None) -> None:
    what, why = _NOT_FOR_A_PLC[key]
    what = what.format(them="them" if keys and "," in keys else "it")
    diags.warning(f"{keys or key}: {what}; {why}: not used", where, rule="NET124")


def _plc_keys(net: Network, plc: PlcWriter, diags: Diagnostics) -> None:
    """The keys lely's dcfgen reads for a lely master, for a PLC master: its own 0x1019,
    0x1012, 0x1015, 0x102A and 0x1029 subs where its file has them (as 0x1006/0x1007);
    the others (its own identity, the lely master's files) do not apply: a warning each."""
    master = net.master
    cfg, mw = master.config, master.config_where
    for key, index, why in _PLC_OBJECTS:
        if key in cfg:
            plc.put(index, 0, cfg[key], why, mw[key])
    for sub, (value, where) in cfg.get("error_behavior", {}).items():
        plc.put(0x1029, sub, value, f"error behaviour of class {sub}", where)
    given = [k for k in mw if k in _IDENTITY]
    if given:                   # one finding for the master's identity
        _not_for_a_plc("identity", mw[given[0]], diags, ", ".join(given))
    if "dcf_path" in net.options_where:
        _not_for_a_plc("dcf_path", net.options_where["dcf_path"], diags)
    for s in net.slaves:
        for key, where in s.config_where.items():
            if key in _NOT_FOR_A_PLC:
                _not_for_a_plc(key, where, diags)


def _restore(plc: PlcWriter, s: Node) -> bool:
    """``restore_configuration`` of a slave, for a PLC master: 0x1F8A sub <node> (the
    sub-index of the slave's 0x1011 the PLC restores before configuring it), where the
    PLC's file has 0x1F8A; True when written (then 0x1F81 bit 7 asks for it)."""
    n = s.config.get("restore_configuration", 0)
    if not n or plc.master.device is None:
        return False
    plc.put(0x1F8A, s.node_id, n, f"{s.name}'s restore configuration",
            s.config_where.get("restore_configuration"))
    return (0x1F8A, s.node_id) in plc.master.settings


def _consumers(net: Network, plc: PlcWriter, diags: Diagnostics) -> None:
    master = net.master
    setting = master.config.get("heartbeat_consumer", True)
    where = master.config_where.get("heartbeat_consumer", master.where)
    if setting is False:
        return
    explicit = setting if isinstance(setting, dict) else {}
    names = {s.name: s for s in net.slaves}
    for name, (_, w) in explicit.items():
        if name not in names:
            diags.error(f"heartbeat_consumer: '{shorten(name)}' is not a slave of the network", w,
                        rule="NET004")
    k = 0
    for s in net.slaves:
        if not s.heartbeat_producer and s.name not in explicit:
            continue           # (asked for by the mapping: the rules report NET251)
        k += 1
        if s.name in explicit:
            t, w = explicit[s.name]
        else:
            t, w = times(s.heartbeat_producer, multiplier(net, s)), where
            if t > 0xFFFF:
                diags.error(f"{shorten(s.name)}'s heartbeat time {s.heartbeat_producer} ms x "
                            f"{multiplier(net, s):g} = {t} ms is over 65535 ms",
                            s.config_where.get("heartbeat_producer", s.where), rule="NET112")
                continue
        master.heartbeat_consumers.append(Heartbeat(s.node_id, t, w))
        plc.put(0x1016, k, (s.node_id << 16) | t,
                f"consumer heartbeat time: monitors {s.name} (node {s.node_id}, {t} ms)", w)

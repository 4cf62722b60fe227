"""The network file in YAML (SPEC §10.1, D-16): lely's ``dcfgen`` format, which
ros2_canopen's ``bus.yml`` also is.

Two layouts: flat (lely: ``options``, ``master``, every other key a slave) and
ros2_canopen's (``nodes:`` holds the slaves, ``defaults:`` is merged into each, the
node's own key winning with a warning). Top-level keys starting with ``.`` are templates.
Every value is checked where it is read, and every finding names its ``file:line``.
"""
from __future__ import annotations

import difflib
import os

from dcf2bin import values
from dcf2bin.diagnostics import Diagnostics, Where
from dcf2bin.network.model import (MASTER, RPDO, SLAVE, TPDO, MapConfig, Network, Node,
                                   PdoConfig, SdoConfig)
from dcf2bin.network.yamltree import YamlError, YMap, YSeq, read_tree

PLACEHOLDER = "@BUS_CONFIG_PATH@/"
MAX_FILE = 64 << 20

# key -> kind of value: int, bool, float (a number), str, or a special reader
OPTION_KEYS = {"heartbeat_multiplier": "float", "retry_factor": "int", "dcf_path": "info"}
MASTER_KEYS = {
    "node_id": "int", "dcf": "path", "name": "str", "heartbeat_producer": "int",
    "heartbeat_consumer": "consumer", "heartbeat_multiplier": "float", "sync_period": "int",
    "sync_window": "int", "start": "bool", "start_nodes": "bool", "start_all_nodes": "bool",
    "reset_all_nodes": "bool", "stop_all_nodes": "bool", "boot_time": "int",
    "bitrate": "int", "baudrate": "int",
}
SLAVE_KEYS = {
    "dcf": "path", "node_id": "int", "rpdo": "pdos", "tpdo": "pdos",
    "heartbeat_producer": "int", "heartbeat_consumer": "bool", "heartbeat_multiplier": "float",
    "boot": "bool", "mandatory": "bool", "reset_communication": "bool", "retry_factor": "int",
    "guard_time": "int", "life_time_factor": "int", "vendor_id": "int", "product_code": "int",
    "revision_number": "int", "serial_number": "int", "software_version": "int",
    "sdo": "sdo",
}
PDO_KEYS = {"enabled": "bool", "cob_id": "cob", "transmission": "int", "inhibit_time": "int",
            "event_timer": "int", "event_deadline": "int", "sync_start": "int",
            "mapping": "mapping"}
MAP_KEYS = {"index": "int", "sub_index": "int", "name": "str"}
SDO_KEYS = {"index": "int", "sub_index": "int", "value": "any"}
# keys lely's dcfgen or ros2_canopen read that dcf2bin does not use: info, never a near-miss
KNOWN_UNUSED = frozenset("""
dcf_path baud_rate driver package polling period enable_lazy_load position_mode
sdo_timeout_ms boot_timeout_ms scale_pos_to_dev scale_pos_from_dev scale_vel_to_dev
scale_vel_from_dev scale_eff_to_dev scale_eff_from_dev switching_state homing_timeout_seconds
diagnostics use_ros2_control emcy_inhibit_time sync_overflow error_behavior
nmt_inhibit_time time_cob_id time_producer software_file configuration_file
restore_configuration offset_pos_to_dev offset_pos_from_dev vendor_id product_code
revision_number serial_number
""".split())
# ranges of the integer keys (inclusive); a time multiplied later is checked there
RANGES = {
    "node_id": (1, 127), "heartbeat_producer": (0, 0xFFFF), "sync_period": (0, 0xFFFFFFFF),
    "sync_window": (0, 0xFFFFFFFF), "boot_time": (0, 0xFFFFFFFF), "bitrate": (1, 10**7),
    "baudrate": (1, 10**4), "retry_factor": (0, 0xFF), "guard_time": (0, 0xFFFF),
    "life_time_factor": (0, 0xFF), "vendor_id": (0, 0xFFFFFFFF),
    "product_code": (0, 0xFFFFFFFF), "revision_number": (0, 0xFFFFFFFF),
    "serial_number": (0, 0xFFFFFFFF), "software_version": (0, 0xFFFFFFFF),
    "transmission": (0, 0xFF), "inhibit_time": (0, 0xFFFF), "event_timer": (0, 0xFFFF),
    "event_deadline": (0, 0xFFFF), "sync_start": (0, 0xFF), "index": (0, 0xFFFF),
    "sub_index": (0, 0xFF),
}


class _Bad(Exception):
    """A value that cannot be read; the caller names the line."""


def as_int(value, what: str = "") -> int:
    """D-16: a YAML integer or a string in SPEC §1's integer syntax, never $NODEID."""
    if isinstance(value, bool):
        raise _Bad(f"expected an integer, found a boolean ({value})")
    if isinstance(value, int):
        return value
    if isinstance(value, str):
        if values.uses_nodeid(value):
            raise _Bad(f"$NODEID is not allowed in the network file: '{value}'")
        try:
            return values.parse_int(value)
        except values.ValueProblem as exc:
            raise _Bad(str(exc)) from None
    raise _Bad(f"expected an integer, found {_kind(value)}")


def as_bool(value) -> bool:
    if isinstance(value, bool):
        return value
    if isinstance(value, str) and value.lower() in ("true", "false"):
        return value.lower() == "true"
    raise _Bad(f"expected true or false, found {_kind(value)}")


def _kind(value) -> str:
    if isinstance(value, YMap):
        return "a mapping"
    if isinstance(value, YSeq):
        return "a list"
    if value is None:
        return "nothing"
    if isinstance(value, str):
        return f"'{value[:40]}'"
    return f"{type(value).__name__} {value!r}"[:60]


def load_network(path: str, data: bytes | None = None) -> Network:
    """Read a YAML network file. Problems are collected in ``network.diagnostics``; a
    file that cannot be read raises OSError."""
    if data is None:
        with open(path, "rb") as f:
            data = f.read(MAX_FILE + 1)
    net = Network(path=path, kind="yaml")
    diags = net.diagnostics
    if len(data) > MAX_FILE:
        diags.error(f"the network file is larger than {MAX_FILE >> 20} MiB", Where(path, 1),
                    rule="NET001")
        return net
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data[:exc.start].count(b"\n") + 1
        diags.error("the network file is not UTF-8 text", Where(path, line), rule="NET001")
        return net
    try:
        root = read_tree(text, path, diags)
    except YamlError:
        return net
    _Reader(net, os.path.dirname(path)).run(root)
    return net


class _Reader:
    def __init__(self, net: Network, folder: str):
        self.net = net
        self.path = net.path
        self.folder = folder
        self.diags: Diagnostics = net.diagnostics

    def w(self, line: int | None) -> Where:
        return Where(self.path, line)

    def err(self, message: str, line: int | None, rule: str = "NET004") -> None:
        self.diags.error(message, self.w(line), rule=rule)

    def run(self, root) -> None:
        if not isinstance(root, YMap):
            self.err("the network file must be a mapping of 'options', 'master' and the "
                     "slaves", getattr(root, "line", 1), "NET001")
            return
        nodes_layout = "nodes" in root or "defaults" in root
        self.net.layout = "nodes" if nodes_layout else "flat"
        options = root.get("options")
        if options is not None:
            self.options(options, root.lines["options"])
        if "master" not in root:
            self.err("no 'master' in the network file", root.line, "NET005")
        else:
            self.net.master_where = self.w(root.lines["master"])
            self.node("master", root["master"], root.lines["master"], MASTER, None)
        defaults = None
        if nodes_layout:
            defaults = root.get("defaults")
            if defaults is not None and not isinstance(defaults, YMap):
                self.err(f"'defaults' must be a mapping, found {_kind(defaults)}",
                         root.lines["defaults"])
                defaults = None
            slaves = root.get("nodes")
            line = root.lines.get("nodes", root.line)
            if slaves is None:
                slaves = YMap(line)
            elif not isinstance(slaves, YMap):
                self.err(f"'nodes' must be a mapping of slaves, found {_kind(slaves)}", line)
                slaves = YMap(line)
            for key in root:
                if key not in ("options", "master", "defaults", "nodes") and not (
                        isinstance(key, str) and key.startswith(".")):
                    self.diags.info(f"top-level key '{key}' is not read in the nodes: "
                                    "layout; ignored", self.w(root.lines[key]), rule="NET007")
        else:
            slaves = YMap(root.line)
            for key, value in root.items():
                if key in ("options", "master") or (isinstance(key, str) and key.startswith(".")):
                    continue
                slaves[key] = value
                slaves.lines[key] = root.lines[key]
        if not slaves:
            self.err("no slave in the network file", line if nodes_layout else root.line,
                     "NET005")
        for key, value in slaves.items():
            self.node(str(key), value, slaves.lines[key], SLAVE, defaults)
        self.net.nodes.sort(key=lambda n: (n.role != MASTER, n.node_id))
        # a finding in defaults: or a template is reported once, not once per node
        seen, items = set(), []
        for d in self.diags.items:
            key = (d.severity, d.message, d.file, d.line, d.rule)
            if key not in seen:
                seen.add(key)
                items.append(d)
        self.diags.items[:] = items

    # -- options ---------------------------------------------------------------------------
    def options(self, value, line: int) -> None:
        if not isinstance(value, YMap):
            self.err(f"'options' must be a mapping, found {_kind(value)}", line)
            return
        for key, v in value.items():
            kline = value.lines[key]
            if key == "dcf_path":
                self.diags.info("options: dcf_path is not used: the outputs go where -o "
                                "says", self.w(kline), rule="NET007")
                continue
            kind = OPTION_KEYS.get(key)
            if kind is None:
                self.unknown(key, kline, OPTION_KEYS)
                continue
            got = self.scalar(key, kind, v, kline)
            if got is not None:
                self.net.options[key] = got

    # -- a node ----------------------------------------------------------------------------
    def node(self, name: str, value, line: int, role: str, defaults: YMap | None) -> None:
        if not isinstance(value, YMap):
            self.err(f"'{name}' must be a mapping of its keys, found {_kind(value)}", line)
            return
        merged = value
        if defaults:
            merged = YMap(value.line)
            for k, v in defaults.items():
                merged[k] = v
                merged.lines[k] = defaults.lines[k]
            for k, v in value.items():
                if k in defaults:
                    self.diags.warning(
                        f"'{k}' of {name} is also in defaults: (line {defaults.lines[k]}); "
                        "the node's value is taken", self.w(value.lines[k]), rule="NET009")
                merged[k] = v
                merged.lines[k] = value.lines[k]
        node = Node(name=name, node_id=0, role=role, where=self.w(line))
        keys = MASTER_KEYS if role == MASTER else SLAVE_KEYS
        for key, v in merged.items():
            kline = merged.lines[key]
            if key == "eds" and role == SLAVE:
                if "dcf" in merged:
                    self.diags.warning("'eds' is ignored: 'dcf' is given too", self.w(kline),
                                       rule="NET008")
                    continue
                self.diags.warning("'eds' is read as 'dcf'", self.w(kline), rule="NET008")
                key = "dcf"
            kind = keys.get(key)
            if kind is None:
                self.unknown(key, kline, keys)
                continue
            node.config_where[key] = self.w(kline)
            if kind == "pdos":
                self.pdos(node, key, v, kline)
            elif kind == "sdo":
                self.sdos(node, v, kline)
            elif kind == "consumer":
                self.consumer(node, v, kline)
            elif kind == "path":
                got = self.scalar(key, "str", v, kline)
                if got is not None:
                    node.config[key] = node.file = self.resolve(got)
            else:
                got = self.scalar(key, kind, v, kline)
                if got is not None:
                    node.config[key] = got
        if role == MASTER and "name" in node.config:
            node.name = node.config["name"]
        nid = node.config.get("node_id")
        if nid is None:
            if "node_id" not in node.config_where:
                self.err(f"{name} has no node_id", line, "NET005")
            return
        if role == SLAVE and "dcf" not in node.config_where:
            self.err(f"{name} has no dcf (its EDS or DCF file)", line, "NET005")
        node.node_id = nid
        node.mandatory = bool(node.config.get("mandatory", False))
        self.net.nodes.append(node)
        if role == MASTER:
            rate = node.config.get("bitrate")
            if rate is None and "baudrate" in node.config:
                rate = node.config["baudrate"] * 1000
            if rate is not None:
                self.net.bitrate = rate

    def resolve(self, text: str) -> str:
        if text.startswith(PLACEHOLDER):
            text = text[len(PLACEHOLDER):]
        return os.path.normpath(os.path.join(self.folder, text)) if text else text

    def unknown(self, key, line: int, known: dict) -> None:
        text = str(key)
        if text not in KNOWN_UNUSED:
            close = [k for k in known
                     if difflib.SequenceMatcher(None, text, k).ratio() >= 0.8]
            if close:
                best = max(close, key=lambda k: difflib.SequenceMatcher(None, text, k).ratio())
                self.diags.warning(f"unknown key '{text}': did you mean '{best}'?",
                                   self.w(line), rule="NET006")
                return
        self.diags.info(f"key '{text}' is not used by dcf2bin; ignored", self.w(line),
                        rule="NET007")

    def scalar(self, key: str, kind: str, value, line: int):
        """The value of ``key`` as ``kind``, range-checked; None (reported) when bad."""
        try:
            if kind == "int":
                got = as_int(value)
                lo, hi = RANGES.get(key, (0, 0xFFFFFFFF))
                if not lo <= got <= hi:
                    raise _Bad(f"{got} is outside {lo}..{hi}")
                return got
            if kind == "bool":
                return as_bool(value)
            if kind == "float":
                if isinstance(value, bool) or not isinstance(value, (int, float, str)):
                    raise _Bad(f"expected a number, found {_kind(value)}")
                try:
                    got = float(value)
                except ValueError:
                    raise _Bad(f"expected a number, found {_kind(value)}") from None
                if not 0 <= got <= 1000 or got != got:
                    raise _Bad(f"{value} is outside 0..1000")
                return got
            if kind == "str":
                if not isinstance(value, str) or not value:
                    raise _Bad(f"expected a text, found {_kind(value)}")
                return value
            if kind == "any":
                return value
        except _Bad as exc:
            self.err(f"{key}: {exc}", line)
            return None
        raise AssertionError(kind)

    # -- master heartbeat_consumer ---------------------------------------------------------
    def consumer(self, node: Node, value, line: int) -> None:
        if not isinstance(value, YMap):
            got = self.scalar("heartbeat_consumer", "bool", value, line)
            if got is not None:
                node.config["heartbeat_consumer"] = got
            return
        times = {}
        for key, v in value.items():
            t = self.scalar("heartbeat_consumer", "int", v, value.lines[key])
            if t is not None:
                times[str(key)] = (t, self.w(value.lines[key]))
        node.config["heartbeat_consumer"] = times

    # -- rpdo / tpdo -----------------------------------------------------------------------
    def pdos(self, node: Node, kind_key: str, value, line: int) -> None:
        kind = TPDO if kind_key == "tpdo" else RPDO
        if not isinstance(value, YMap):
            self.err(f"'{kind_key}' must be a mapping of PDO numbers, found {_kind(value)}",
                     line)
            return
        for key, v in value.items():
            kline = value.lines[key]
            try:
                number = as_int(key)
            except _Bad:
                number = None
            if number is None or not 1 <= number <= 512:
                self.err(f"{kind_key}: PDO number '{key}' is not an integer 1..512", kline)
                continue
            if (kind, number) in node.pdo_config:
                first = node.pdo_config[(kind, number)].where.line
                self.err(f"{kind_key} {number} repeated (first at line {first})", kline,
                         "NET002")
                continue
            pc = PdoConfig(kind, number, self.w(kline))
            node.pdo_config[(kind, number)] = pc
            if v is None:
                continue
            if not isinstance(v, YMap):
                self.err(f"{kind_key} {number} must be a mapping, found {_kind(v)}", kline)
                continue
            for k, item in v.items():
                iline = v.lines[k]
                pkind = PDO_KEYS.get(k)
                if pkind is None:
                    self.unknown(k, iline, PDO_KEYS)
                    continue
                pc.wheres[k] = self.w(iline)
                if pkind == "mapping":
                    pc.mapping = self.mapping(item, iline)
                elif pkind == "cob":
                    if isinstance(item, str) and item.lower() == "auto":
                        pc.cob_id = "auto"
                    else:
                        try:
                            pc.cob_id = as_int(item)
                            if not 0 <= pc.cob_id <= 0xFFFFFFFF:
                                raise _Bad(f"{pc.cob_id} is outside 0..0xFFFFFFFF")
                        except _Bad as exc:
                            self.err(f"cob_id: {exc} (auto or an integer)", iline)
                else:
                    setattr(pc, k, self.scalar(k, pkind, item, iline))

    def mapping(self, value, line: int) -> list[MapConfig] | None:
        if value is None:
            return []
        if not isinstance(value, YSeq):
            self.err(f"mapping must be a list of {{index, sub_index}}, found {_kind(value)}",
                     line)
            return None
        if len(value) > 64:
            self.err(f"mapping has {len(value)} objects; a PDO maps at most 64", line)
            return None
        out = []
        for item, iline in zip(value, value.lines):
            got = self.item(item, iline, MAP_KEYS, "mapping")
            if got is None:
                continue
            name = got.get("name")
            out.append(MapConfig(got["index"], got.get("sub_index", 0), name, self.w(iline),
                                 self.w(got["_lines"].get("name", iline))))
        return out

    def item(self, item, line: int, keys: dict, what: str) -> dict | None:
        if not isinstance(item, YMap):
            self.err(f"a {what} item must be a mapping with index and sub_index, found "
                     f"{_kind(item)}", line)
            return None
        got: dict = {"_lines": {}}
        ok = True
        for k, v in item.items():
            kline = item.lines[k]
            kind = keys.get(k)
            if kind is None:
                self.unknown(k, kline, keys)
                continue
            x = self.scalar(k, kind, v, kline)
            if x is None and kind != "any":
                ok = False
            got[k] = x
            got["_lines"][k] = kline
        if "index" not in got:
            if ok:
                self.err(f"a {what} item without index", line, "NET005")
            return None
        if what == "sdo" and "value" not in got:
            self.err("an sdo item without value", line, "NET005")
            return None
        return got if ok else None

    def sdos(self, node: Node, value, line: int) -> None:
        if not isinstance(value, YSeq):
            self.err(f"sdo must be a list of {{index, sub_index, value}}, found {_kind(value)}",
                     line)
            return
        for item, iline in zip(value, value.lines):
            got = self.item(item, iline, SDO_KEYS, "sdo")
            if got is not None:
                node.sdo_config.append(SdoConfig(got["index"], got.get("sub_index", 0),
                                                 got["value"], self.w(iline)))

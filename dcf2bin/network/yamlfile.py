"""The network file in YAML (SPEC §10.1, D-16): lely's ``dcfgen`` format, which
ros2_canopen's ``bus.yml`` also is.

Two layouts: flat (lely: ``options``, ``master``, every other key a slave) and
ros2_canopen's (``nodes:`` holds the slaves, ``defaults:`` is merged into each, the
node's own key winning with a warning). Top-level keys starting with ``.`` are templates.
Every value is checked where it is read, and every finding names its ``file:line``.
"""
from __future__ import annotations

import os
import re

from dcf2bin.diagnostics import Summarised, Where, shorten
from dcf2bin.fileio.reading import MAX_INPUT, read_file
from dcf2bin.network.model import MASTER, SLAVE, Network, Node
from dcf2bin.network.yamlkeys import (MASTER_KEYS, OPTION_KEYS, SLAVE_KEYS, Items,
                                      _Bad, as_int, kind_of)
from dcf2bin.network.yamltree import MAX_NODES, YamlError, YMap, read_tree


MAX_SLAVES = 1024      # read of a network file (issue 26): 8 times the node-IDs


def load_network(path: str, data: bytes | None = None) -> Network:
    """Read a YAML network file. Problems are collected in ``network.diagnostics``; a
    file that cannot be read raises OSError."""
    if data is None:
        data = read_file(path)          # never a FIFO or /dev/zero, at most MAX_INPUT
    # a finding in defaults: or a template is reported once, not once per node, and one
    # mistake repeated 100,000 times five times and then counted (issue 26)
    net = Network(path=path, kind="yaml", diagnostics=Summarised())
    diags = net.diagnostics
    if len(data) > MAX_INPUT:
        diags.error(f"the network file is larger than {MAX_INPUT >> 20} MiB", Where(path, 1),
                    rule="NET001")
        return net
    try:
        data.decode("utf-8-sig")      # (libyaml reads the bytes: no copy of the text kept)
    except UnicodeDecodeError as exc:
        other = other_kind(path, data)       # a container, a concise DCF: what it is
        if other is not None:
            diags.error(other, Where(path), rule="IO001")
            return net
        line = data.count(b"\n", 0, exc.start) + 1
        diags.error("the network file is not UTF-8 text", Where(path, line), rule="NET001")
        return net
    try:
        root = read_tree(data, path, diags)
    except YamlError:
        root = None
    if not isinstance(root, YMap):
        other = other_kind(path, data)
        if other is not None:        # one line for what it is, not its YAML syntax error
            net.diagnostics = Summarised()
            net.diagnostics.error(other, Where(path), rule="IO001")
            return net
        if root is None and diags.has_errors:
            return net
    _Reader(net, os.path.dirname(path)).run(root)
    return net


def other_kind(path: str, data: bytes) -> str | None:
    """What a file that YAML cannot read as a mapping is, when the file-kind detection
    every command uses says it is another kind (an EDS given as the network file, an XDD,
    a container): ``ts.eds is DCF/EDS text, not a YAML network file or a CiA 306-3 network
    project; a network file names it as a node's dcf: ...`` -- the words ``validate`` has for a network file
    given to it, the other way round. None for a YAML file (its syntax error is the
    finding)."""
    from dcf2bin import filekind
    node_file = ("a network file names it as a node's dcf: (dcf2bin validate checks it, "
                 "compile makes a container of it)")
    return filekind.mismatch(path, filekind.detect(data, path), ("yaml", "cpj"),
                             use={filekind.DCF: node_file, filekind.XDD: node_file})


_OBJECT = re.compile(r"(.+?)sub([0-9a-fA-F]{1,2}|0[xX][0-9a-fA-F]{1,2})", re.IGNORECASE)


def object_key(key) -> tuple[int, int] | None:
    """(index, sub) of a ``names:`` key: an integer index (sub 0), or a text
    ``<index>sub<sub>`` whose index is an integer as D-16 reads one and whose sub-index
    is hex as dcf2bin's messages and DCF section names write it; None when it is neither
    (or out of range)."""
    text, sub = key, 0
    if isinstance(key, str):
        m = _OBJECT.fullmatch(key.strip())
        if m is not None:
            text, sub = m.group(1), int(m.group(2), 16)
    try:
        index = as_int(text)
    except _Bad:
        return None
    return (index, sub) if 0 <= index <= 0xFFFF and 0 <= sub <= 0xFF else None


def key_text(key) -> str:
    """A ``names:`` key as the user wrote it: a text quoted, an integer in hex as indexes
    are written (YAML gave ``0x99999`` as 629145)."""
    if isinstance(key, bool):
        return str(key).lower()
    if isinstance(key, int):
        return f"-0x{-key:X}" if key < 0 else f"0x{key:X}"
    return f"'{shorten(key)}'"


class _Reader(Items):
    """The layouts and the nodes."""

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
                self.err(f"'defaults' must be a mapping, found {kind_of(defaults)}",
                         root.lines["defaults"])
                defaults = None
            slaves = root.get("nodes")
            line = root.lines.get("nodes", root.line)
            if slaves is None:
                slaves = YMap(line)
            elif not isinstance(slaves, YMap):
                self.err(f"'nodes' must be a mapping of slaves, found {kind_of(slaves)}", line)
                slaves = YMap(line)
            for key in root:
                if key not in ("options", "master", "defaults", "nodes") and not (
                        isinstance(key, str) and key.startswith(".")):
                    self.diags.info(f"top-level key '{shorten(key)}' is not read in the nodes: "
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
        if defaults and root.size + defaults.size * (len(slaves) - 1) > MAX_NODES:
            # defaults: is read once per node: a bound on that work too (issue 26)
            self.err(f"the network expands to more than {MAX_NODES:,} nodes: its defaults: "
                     f"({defaults.size:,}) are merged into each of its {len(slaves):,} "
                     "nodes", root.lines["defaults"], "NET003")
            return
        for n, (key, value) in enumerate(slaves.items()):
            if n == MAX_SLAVES:
                # a node costs a kilobyte or two; 127 node-IDs make these repeats anyway
                self.err(f"{len(slaves):,} slaves, but a CANopen network has 127 node-IDs: "
                         f"those after the first {MAX_SLAVES:,} are not read",
                         slaves.lines[key], "NET004")
                break
            self.node(str(key), value, slaves.lines[key], SLAVE, defaults)
        self.net.nodes.sort(key=lambda n: (n.role != MASTER, n.node_id))

    # -- a slave's names: ------------------------------------------------------------------
    def names(self, node: Node, value, line: int) -> None:
        """``names: {0x6040: controlword, "0x6041sub0": statusword}`` (D-17): the PLC
        variable of each object, for PDOs the file configures (no ``mapping:`` to carry a
        ``name:``). A key is an index (sub 0) or ``<index>sub<sub>``, the sub-index in hex
        as dcf2bin writes it (``0x6411subA``); a value is a text."""
        if not isinstance(value, YMap):
            self.err(f"names must be a mapping of objects to variable names, found "
                     f"{kind_of(value)}", line)
            return
        for key, v in value.items():
            kline = value.lines[key]
            obj = object_key(key)
            if obj is None:
                self.err(f"names: {key_text(key)} is not an object (an index 0x0000..0xFFFF "
                         "such as 0x6040, or \"0x6041sub0\" with the sub-index in hex)", kline)
                continue
            index, sub = obj
            got = self.scalar(f"names: 0x{index:04X}sub{sub:X}", "str", v, kline)
            if got is None:
                continue
            if obj in node.names:
                self.err(f"names: 0x{index:04X}sub{sub:X} is named twice (first at line "
                         f"{node.names[obj][1].line})", kline, "NET002")
                continue
            node.names[obj] = (got, self.w(kline))

    # -- options ---------------------------------------------------------------------------
    def options(self, value, line: int) -> None:
        if not isinstance(value, YMap):
            self.err(f"'options' must be a mapping, found {kind_of(value)}", line)
            return
        for key, v in value.items():
            kline = value.lines[key]
            kind = OPTION_KEYS.get(key)
            if kind is None:
                self.unknown(key, kline, OPTION_KEYS)
                continue
            got = self.scalar(key, kind, v, kline)
            if got is not None:
                self.net.options[key] = got
                self.net.options_where[key] = self.w(kline)

    # -- a node ----------------------------------------------------------------------------
    def node(self, name: str, value, line: int, role: str, defaults: YMap | None) -> None:
        if not isinstance(value, YMap):
            self.err(f"'{shorten(name)}' must be a mapping of its keys, found "
                     f"{kind_of(value)}", line)
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
                        f"'{shorten(k)}' of {shorten(name)} is also in defaults: "
                        f"(line {defaults.lines[k]}); the node's value is taken "
                        "(ros2_canopen's generator takes the one of defaults:)",
                        self.w(value.lines[k]), rule="NET009")
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
            elif kind == "names":
                self.names(node, v, kline)
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
                self.err(f"{shorten(name)} has no node_id", line, "NET005")
            return
        if role == SLAVE and "dcf" not in node.config_where:
            self.err(f"{shorten(name)} has no dcf (its EDS or DCF file)", line, "NET005")
        node.node_id = nid
        node.mandatory = bool(node.config.get("mandatory", False))
        self.net.nodes.append(node)
        if role == MASTER:
            rate = node.config.get("bitrate")
            if rate is None and "baudrate" in node.config:
                rate = node.config["baudrate"] * 1000
            if rate is not None:
                self.net.bitrate = rate

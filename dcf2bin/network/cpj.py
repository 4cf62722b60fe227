"""The CiA 306-3 nodelist project (``.cpj``) reader (SPEC §10.1, D-16).

A ``.cpj`` is INI text: each section ``[Topology]``, ``[Topology2]``, … is one network, with
the keys ``NetName``, ``Nodes`` (how many nodes are present), ``EDSBaseName`` (the folder of
the device descriptions) and, per node-ID X in decimal (1…127), ``NodeXPresent``,
``NodeXName``, ``NodeXDCFName`` and ``NodeXRefd``. Each present node is its DCF as it is:
there is no master role and nothing is configured. File names are relative to the
project's folder.

``read(path, net=None)`` returns a :class:`~.model.Network` (kind ``"cpj"``) whose
``diagnostics`` hold the project's problems (NET050–NET069); it never raises for a problem
in the file (``OSError`` when the project itself cannot be read).
"""
from __future__ import annotations

import os
import re

from dcf2bin import ini, values
from dcf2bin.diagnostics import Diagnostics, Severity, Summarised, Where, shorten
from dcf2bin.network.model import SLAVE, Network, Node
from dcf2bin.network.rules import NetRule

ERROR, WARNING = Severity.ERROR, Severity.WARNING


def _r(id, name, severity, description, hint=""):
    return NetRule(id, name, severity, description, hint, "network")


RULES: dict[str, NetRule] = {r.id: r for r in (
    _r("NET050", "cpj-syntax", ERROR,
       "The .cpj project is not readable INI text (a bad line, a repeated section or key, "
       "more than 100,000 lines).",
       "a .cpj is INI text: [Topology] and Key=Value lines"),
    _r("NET051", "cpj-no-topology", ERROR,
       "The .cpj project has no [Topology] section (or not the one --net asks for).",
       "each network of a .cpj is a section [Topology], [Topology2], …"),
    _r("NET052", "cpj-value", ERROR,
       "A .cpj value is not an integer, or NodeXPresent/NodeXRefd is not 0 or 1.",
       "write integers in decimal, 0x hex or 0 octal"),
    _r("NET053", "cpj-node-id", ERROR,
       "A NodeX… key names a node-ID outside 1…127.", "X is the node-ID in decimal, 1…127"),
    _r("NET054", "cpj-no-dcf", ERROR,
       "A present node has no NodeXDCFName.", "name the node's DCF with NodeXDCFName"),
    _r("NET055", "cpj-dcf-unreadable", ERROR,
       "A node's DCF cannot be read (missing, a directory, no permission).",
       "NodeXDCFName is relative to the .cpj's folder"),
    _r("NET056", "cpj-nodes-count", WARNING,
       "Nodes= is not the number of nodes marked present.",
       "set Nodes to the number of NodeXPresent=1 keys"),
    _r("NET057", "cpj-no-nodes", ERROR,
       "The network of the .cpj has no present node.", "mark nodes with NodeXPresent=1"),
    _r("NET058", "cpj-unknown-key", WARNING,
       "A key of a [Topology] section that CiA 306-3 does not define.",
       "the keys are NetName, Nodes, EDSBaseName, NodeXPresent, NodeXName, NodeXDCFName, "
       "NodeXRefd"),
    _r("NET059", "cpj-dcf-node-id", WARNING,
       "A node's DCF sets another NodeID in [DeviceComissioning] than the project gives it.",
       "make the DCF's NodeID the node-ID of NodeX… (the project's node-ID is used)"),
)}

_NODE_KEY = re.compile(r"node([0-9]+)(present|name|dcfname|refd)")
# a .cpj longer than this is not read (issue 26): a [TopologyN] section of 127 nodes has
# 511 keys, so this is about 190 networks of every node-ID
MAX_LINES = 100_000
_NET_KEYS = ("netname", "nodes", "edsbasename")


def _add(diags: Diagnostics, code: str, message: str, where: Where) -> None:
    r = RULES[code]
    diags.add(r.severity, message, where, rule=code, hint=r.hint)


def section_name(net: int | None) -> str:
    """``[Topology]`` for network 1 (and for None), ``[Topology2]`` for 2, …"""
    return "topology" if net in (None, 1) else f"topology{net}"


def read(path: str, net: int | None = None, *, data: bytes | None = None) -> Network:
    """Read a .cpj project: the network of ``[Topology]`` (``net`` N > 1: ``[TopologyN]``)
    with every present node read from its DCF."""
    from dcf2bin import formats
    from dcf2bin.network import pdos
    from dcf2bin.network.configuration import _node_facts as node_facts
    from dcf2bin.network.files import read_node_file, wrong_kind
    if data is None:
        from dcf2bin.fileio import read_file
        data = read_file(path)
    network = Network(path, kind="cpj", diagnostics=Summarised())   # issue 26: see there
    diags = network.diagnostics
    lines = data.count(b"\n") + 1
    if lines > MAX_LINES:
        # every key of INI text is an object or two: 5 million short lines would take GBs
        _add(diags, "NET050", f"the project has {lines:,} lines, more than {MAX_LINES:,} "
             "(a network of 127 nodes takes about 520): not read", Where(path, MAX_LINES + 1))
        return network
    parsed = ini.parse_bytes(data, path)
    for d in parsed.diagnostics:
        if d.severity is Severity.ERROR:
            _add(diags, "NET050", d.message, Where(path, d.line))
    for dup in parsed.duplicates:
        what = (f"key '{shorten(dup.key)}'" if dup.key else
                f"section [{shorten(dup.section)}]")
        _add(diags, "NET050", f"{what} repeated (first at line {dup.first_line}; the "
             "first is used)", Where(path, dup.line))
    name = section_name(net)
    sec = parsed.section(name)
    if sec is None:
        shown = name.replace("topology", "Topology")
        have = sorted(s for s in parsed.sections if s.startswith("topology"))
        _add(diags, "NET051", f"the project has no [{shown}] section" + (
            f" (it has "
            f"{', '.join('[' + shorten(s.replace('topology', 'Topology')) + ']' for s in have)})"
            if have else ""), Where(path, 1 if data else None))
        return network
    network.master_where = Where(path, sec.line)
    network.options["netname"] = sec.get("netname") or ""
    nodes: dict[int, dict[str, tuple[str, int]]] = {}
    for low, k in sec.keys.items():
        m = _NODE_KEY.fullmatch(low)
        if m is None:
            if low not in _NET_KEYS:
                _add(diags, "NET058", f"[{shorten(sec.name)}] {shorten(k.name)}: not a key of "
                     "a CiA 306-3 network", Where(path, k.line))
            continue
        digits = m.group(1)
        if len(digits) > values.MAX_DIGITS:
            _add(diags, "NET053", f"[{shorten(sec.name)}] {shorten(k.name)}: node-ID "
                 f"{values.too_long(len(digits))}", Where(path, k.line))
            continue
        x = int(digits)
        if not 1 <= x <= 127:
            _add(diags, "NET053", f"[{shorten(sec.name)}] {shorten(k.name)}: node-ID {x} is "
                 "outside 1…127", Where(path, k.line))
            continue
        keys = nodes.setdefault(x, {})
        if m.group(2) in keys:               # Node1Present and Node01Present
            _add(diags, "NET050", f"[{shorten(sec.name)}] {shorten(k.name)} repeats "
                 f"{keys[m.group(2)][2]} (line {keys[m.group(2)][1]}; the first is used)",
                 Where(path, k.line))
            continue
        keys[m.group(2)] = (k.value, k.line, k.name)
    folder = os.path.dirname(path)
    present = 0
    for x in sorted(nodes):
        keys = nodes[x]
        if not _flag(diags, path, sec, keys, x, "present"):
            continue
        _flag(diags, path, sec, keys, x, "refd")
        present += 1
        line = keys["present"][1]
        node = Node(keys["name"][0] if keys.get("name", ("",))[0] else f"node{x}", x, SLAVE,
                    where=Where(path, line))
        dcf = keys.get("dcfname")
        if dcf is None or not dcf[0]:
            _add(diags, "NET054", f"node {x} is present but has no Node{x}DCFName",
                 Where(path, line))
            continue
        node.file = os.path.join(folder, dcf[0])
        try:
            node_data = read_node_file(node.file)
        except OSError as exc:
            _add(diags, "NET055", f"{dcf[2]}: cannot read '{shorten(dcf[0])}': "
                 f"{exc.strerror or exc}", Where(path, dcf[1]))
            continue
        wrong = wrong_kind(node.file, node_data)
        if wrong is not None:               # as a YAML network's node file (NET011)
            diags.error(wrong, Where(path, dcf[1]), rule="NET011")
            continue
        node.device = formats.load(node.file, node_id=x, data=node_data)
        network.files.setdefault(node.file, node_data)     # every command lints these
        own = _own_node_id(node.device)
        if own is not None and own != x:
            _add(diags, "NET059", f"node {x}: its DCF '{shorten(dcf[0])}' sets NodeID {own}; the "
                 f"project's node-ID {x} is used", Where(path, dcf[1]))
        # its PDOs as the file has them, the mapping rules every PDO of a network obeys
        # (the object is in the file and mappable that way), its heartbeat, SYNC, EMCY, TIME
        pdos.from_file(node)
        _check_mappings(node, diags)
        node_facts(node)
        network.nodes.append(node)
    count = sec.get("nodes")
    if count is not None:
        n = _int(diags, path, sec, "nodes")
        if n is not None and n != present:
            _add(diags, "NET056", f"[{shorten(sec.name)}] Nodes={shorten(count)} but {present} node"
                 f"{'' if present == 1 else 's'} {'is' if present == 1 else 'are'} present",
                 Where(path, sec.line_of("nodes")))
    if not present:
        _add(diags, "NET057", f"[{shorten(sec.name)}] marks no node present", Where(path, sec.line))
    return network


def _check_mappings(node: Node, diags: Diagnostics) -> None:
    """configure's mapping rules for a PDO kept from a file, over the objects that are not
    network variables: a PLC's 0xA000…0xAFFF variables are its process image, mapped both
    ways whatever their access (as validate checks a PLC's DCF)."""
    from dcf2bin.model import NV_FIRST, NV_LAST
    from dcf2bin.network import pdos
    whole = [p.mapping for p in node.pdos]
    for p in node.pdos:
        p.mapping = [m for m in p.mapping if not NV_FIRST <= m.index <= NV_LAST]
    try:
        pdos.check_kept(node, diags)
    finally:
        for p, mapping in zip(node.pdos, whole):
            p.mapping = mapping


def _own_node_id(dev) -> int | None:
    """The NodeID the DCF's [DeviceComissioning] gives (None: none, or not a number)."""
    sec = dev.ini.section("devicecomissioning") if dev.ini is not None else None
    text = sec.get("nodeid") if sec is not None else None
    try:
        return values.parse_int(values.split_numeric_comment(text)[0]) if text else None
    except values.ValueProblem:
        return None


def _int(diags: Diagnostics, path: str, sec, low: str) -> int | None:
    try:
        return values.parse_int(values.split_numeric_comment(sec.get(low) or "")[0])
    except values.ValueProblem as exc:
        _add(diags, "NET052", f"[{shorten(sec.name)}] {shorten(sec.keys[low].name)}: {exc}",
             Where(path, sec.line_of(low)))
        return None


def _flag(diags: Diagnostics, path: str, sec, keys, x: int, what: str) -> bool:
    """NodeXPresent / NodeXRefd: 0 or 1 (absent: 0)."""
    if what not in keys:
        return False
    text, line = keys[what][:2]
    try:
        v = values.parse_int(values.split_numeric_comment(text)[0])
    except values.ValueProblem as exc:
        v, why = None, str(exc)
    else:
        why = f"'{shorten(text)}' is neither 0 nor 1"
    if v not in (0, 1):
        _add(diags, "NET052", f"[{shorten(sec.name)}] {shorten(keys[what][2])}: "
                              f"{why}", Where(path, line))
        return False
    return v == 1

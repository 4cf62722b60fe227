"""dcf2bin network scan: which nodes answer on the bus, and is each the one the master
will accept."""
from __future__ import annotations

import json

import click

from dcf2bin.cli.common import (CONTEXT, COUNT, Failure, Seconds, check_output, debug_option,
                                emit, format_option, guarded, output_option, quiet_option,
                                rule_options, write_output)
from dcf2bin.cli.download import bus_options, open_bus
from dcf2bin.cli.network.show import check_rules, configured_network, net_option

#: what scan, lss and upload say of a network's errors that they do not depend on
GOING_ON = "which network {command} does not depend on: {done}, and the exit status is 1"
from dcf2bin.diagnostics import Diagnostic, ExitCode, Severity, Where

NO_SUCH_ENTRY = (0x06020000, 0x06090011)    # SDO aborts: object / sub-index does not exist
COLUMNS = [((0x1000, 0), "device type"), ((0x1018, 1), "vendor-ID"),
           ((0x1018, 2), "product code"), ((0x1018, 3), "revision"), ((0x1018, 4), "serial")]


@click.command("scan", context_settings=CONTEXT)
@click.argument("network_file", metavar="NETWORK", type=click.Path())
@bus_options
@click.option("--listen", type=Seconds(0), default=0.5, show_default=True,
              metavar="SECONDS",
              help="Seconds to listen for boot-up and heartbeat messages (the SDO requests "
              "go out at the same time).")
@click.option("--timeout", type=Seconds(0.001), default=0.3, show_default=True,
              metavar="SECONDS", help="Seconds to wait for the SDO responses of one round.")
@click.option("--retries", type=COUNT, default=0, show_default=True, metavar="N",
              help="Times an unanswered SDO request is sent again.")
@format_option(["text", "json"], "text", "text (a table) or json; the findings go to "
               "standard error.")
@output_option("The table or the JSON.")
@net_option
@rule_options
@quiet_option("No table; the findings that are errors.")
@debug_option
@guarded
def scan_cmd(network_file, interface, channel, bitrate, listen, timeout, retries, fmt, output,
             net, select_, ignore, strict, quiet, debug):
    """Find the nodes on the bus and compare them with a network.

    Listens for boot-up and heartbeat messages and asks every node-ID 1...127 for 0x1000
    (all requests at once), then reads 0x1018 sub 1...4 of every node that answered.
    Reports missing nodes, nodes the network does not have, and each present node's
    device type, vendor-ID, product code, revision and serial number that differ from what
    the master will enforce (0x1F84...0x1F88) -- the nodes the master would refuse to boot.
    The master's own node-ID is shown, never missing or unexpected. For a .cpj project
    (no master) each node is compared with its own DCF's 0x1000 and 0x1018.

    A scan takes at most max(LISTEN, (RETRIES+1) x TIMEOUT) + 4 x (RETRIES+1) x TIMEOUT
    seconds, 1.7 s with the defaults, plus the time to send 127 requests (about 30 ms at
    500 kbit/s); nodes that answer at once end each round early. Exit status 1 when a
    node is missing, silent or differs.

    The network's findings are those of 'network check' (validate's warnings about the
    node files left out), with --select/--ignore as there, and decide the exit status as
    there (--strict: warnings too); only those that make the scan unsound stop it before
    the bus (nothing scanned), whatever --ignore says: an error of the network file, a
    node-ID given twice, a node's file that cannot be read (NET0xx, NET200, NET201,
    DCF0xx-DCF3xx). The PDO plan and the configuration (NET1xx, NET2xx) do not stop it.
    """
    from dcf2bin.bus import link
    from dcf2bin.bus import scan as sc
    from dcf2bin.network.check import NODES
    from dcf2bin.network.show import identity_of
    check_rules(select_, ignore)
    check_output(output, [network_file])    # before the bus is opened
    network, verdict = configured_network(
        network_file, quiet, "nothing scanned", net, select=select_, ignore=ignore,
        strict=strict, need=NODES, going_on=GOING_ON.format(command="scan",
                                                            done="the bus is scanned"))
    expected = [sc.Expected(n.node_id, n.name, identity_of(network, n),
                            master=n.role == "master", from_file=network.kind == "cpj")
                for n in network.nodes]
    bus = open_bus(interface, channel, bitrate)
    try:
        result = sc.scan(bus, listen=listen, timeout=timeout, retries=retries)
    finally:
        link.close_network(bus)
    findings = sc.compare(result, expected)
    bound = sc.worst_case(listen, timeout, retries)
    # a node's finding names its line; an unexpected node, the master: line (or the .cpj
    # project's [Topology] line)
    top = network.master_where or Where(network_file)
    wheres = {n.node_id: n.where or top for n in network.nodes}
    diags = []
    for f in findings:
        w = wheres.get(f.node_id, top)
        diags.append(Diagnostic(Severity.WARNING if f.kind == "unexpected" else Severity.ERROR,
                                f.text, w.file, w.line))
    if fmt == "json":
        write_output(_json(network_file, result, expected, findings, bound), output,
                     [network_file], binary=False)
    elif not quiet:
        write_output(_text(network_file, result, expected, findings, bound), output,
                     [network_file], binary=False)
    emit(diags, quiet)
    if any(d.severity is Severity.ERROR for d in diags):
        raise Failure(ExitCode.FINDINGS)
    if verdict != ExitCode.OK:              # the network's own findings (said before)
        raise Failure(verdict)


def _cell(found, key) -> str:
    if found is None or not found.answered:
        return "-"
    a = found.entries.get(key)
    if a is None:
        return "-"
    if a.code in NO_SUCH_ENTRY:
        return "(none)"
    if a.code is not None:
        return f"abort {a.code:08X}"
    if a.problem is not None:
        return "bad answer"
    return f"0x{a.value:08X}" if a.value is not None else "no answer"


def _status(e, f) -> str:
    if f is None:
        return "master, not on the bus" if e is not None and e.master else "MISSING"
    if f.answered:
        state = "answers" + (f" ({f.heard})" if f.heard else "")
    else:
        state = f"heard ({f.heard}), no SDO answer"
    if e is None:
        return "UNEXPECTED, " + state
    return "master, " + state if e.master else state


def _rows(result, expected):
    by_id = {e.node_id: e for e in expected}
    for node_id in sorted(set(by_id) | set(result.found)):
        yield node_id, by_id.get(node_id), result.found.get(node_id)


def _text(path, result, expected, findings, bound) -> str:
    from dcf2bin.network.show import table
    answering = sum(1 for f in result.found.values() if f.answered)
    out = [f"{path}: node-IDs 1-127 scanned in {result.seconds:.2f} s (at most {bound:.2f} s): "
           f"{answering} answer, {len(findings)} finding{'s' if len(findings) != 1 else ''}"]
    rows = [[str(nid), e.name if e else "?", _status(e, f), *(_cell(f, k) for k, _ in COLUMNS)]
            for nid, e, f in _rows(result, expected)]
    out += table(["node", "name", "on the bus", *(h for _, h in COLUMNS)], rows)
    if result.virtual and any(f.kind == "missing" for f in findings):
        from dcf2bin.bus.link import VIRTUAL_NOTE
        out.append(f"(missing: {VIRTUAL_NOTE})")
    return "\n".join(out) + "\n"


def _hex32(v):
    return None if v is None else f"0x{v:08X}"


def _json(path, result, expected, findings, bound) -> str:
    """The JSON document (docs/options.md, "JSON outputs"; dcf2bin/schemas/network-scan.json):
    identity values and SDO abort codes "0x%08X", indexes "0x1018"."""
    nodes = []
    for nid, e, f in _rows(result, expected):
        d = {"node_id": nid, "name": e.name if e else None, "in_network": e is not None,
             "master": bool(e and e.master), "heard": f.heard if f else None,
             "answered": bool(f and f.answered), "entries": {}, "enforced": None}
        if f is not None:
            for (index, sub), a in f.entries.items():
                d["entries"][f"0x{index:04X}sub{sub}"] = (
                    {"value": _hex32(a.value)} if a.value is not None
                    else {"abort": _hex32(a.code)} if a.code is not None else {"answer": None})
        if e is not None and not e.master:
            d["enforced"] = {f"0x{k:04X}": _hex32(v) for k, v in sorted(e.identity.items())}
        nodes.append(d)
    out = []
    for f in findings:
        index, sub = f.entry if f.entry is not None else (None, None)
        out.append({"kind": f.kind, "node_id": f.node_id, "name": f.name, "text": f.text,
                    "index": None if index is None else f"0x{index:04X}", "subindex": sub,
                    "expected": _hex32(f.expected), "actual": _hex32(f.actual),
                    "code": _hex32(f.code)})
    return json.dumps({"format": "dcf2bin-network-scan", "version": 1, "file": path,
                       "seconds": round(result.seconds, 3),
                       "at_most_seconds": round(bound, 3), "nodes": nodes,
                       "findings": out}, indent=2) + "\n"

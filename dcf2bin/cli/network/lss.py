"""dcf2bin network lss: give every slave of a network its node-ID by LSS (CiA 305)."""
from __future__ import annotations

import json

import click

from dcf2bin.cli.common import (CONTEXT, Failure, Integer, Seconds, debug_option, emit, fail,
                                format_option, guarded, output_option, quiet_option,
                                rule_options, say, write_output)
from dcf2bin.cli.download import bus_options, open_bus
from dcf2bin.cli.network.scan import GOING_ON
from dcf2bin.cli.network.show import check_rules, configured_network, net_option
from dcf2bin.diagnostics import Diagnostic, ExitCode, Severity

# what the master enforces (0x1F85...0x1F88) -> the part of the LSS address
PARTS = {0x1F85: 0, 0x1F86: 1, 0x1F87: 2, 0x1F88: 3}
BIT_RATES = (1_000_000, 800_000, 500_000, 250_000, 125_000, 50_000, 20_000, 10_000)


def lss_options(fn):
    """--timeout, --scan-wait, --check-wait and --set-bitrate of network lss and lss set."""
    fn = click.option("--set-bitrate", "set_bitrate", type=Integer(1), metavar="BPS",
                      help="Also configure this bit rate (bit/s, one of the CiA table: "
                      "1000000, 800000, 500000, 250000, 125000, 50000, 20000, 10000); it "
                      "takes effect when the node starts again. --bitrate is the rate the "
                      "bus is opened at.")(fn)
    fn = click.option("--check-wait", "check_wait", type=Seconds(0.001), default=0.3,
                      show_default=True, metavar="SECONDS",
                      help="Seconds the check before any change waits for a node to answer "
                      "SDO at each node-ID to give: silence says the node-ID is free, so "
                      "every node must answer within it (as long as network scan waits).")(fn)
    return scan_wait_option(timeout_option(fn), again=True)


def timeout_option(fn):
    return click.option("--timeout", type=Seconds(0.001), default=0.5,
                        show_default=True, metavar="SECONDS",
                        help="Seconds to wait for an LSS answer, a boot-up message, or the "
                        "SDO answers of one scan round.")(fn)


def scan_wait_option(fn, again: bool = False):
    """``again``: the command also counts the answers where one is expected."""
    more = (" After the first answer to a selective switch, and to the SDO check at each "
            "new node-ID, the master listens this long again: a second answer is a second "
            "node of that identity." if again else "")
    return click.option("--scan-wait", "scan_wait", type=Seconds(0.001),
                        default=0.05, show_default=True, metavar="SECONDS",
                        help="Seconds each fastscan or identify step listens: there, "
                        "silence is the answer, and every node must answer within it."
                        + more)(fn)


def check_bitrate(value: int | None) -> None:
    if value is not None and value not in BIT_RATES:
        fail(f"--set-bitrate {value}: not a bit rate of the CiA bit timing table ("
             + ", ".join(str(b) for b in BIT_RATES) + ")", code=ExitCode.USAGE)


@click.command("lss", context_settings=CONTEXT)
@click.argument("network_file", metavar="NETWORK", type=click.Path())
@bus_options
@lss_options
@format_option(["text", "json"], "text", "text (a table) or json; the errors go to "
               "standard error.")
@output_option("The table or the JSON.")
@net_option
@rule_options
@quiet_option("No table; the errors.")
@debug_option
@guarded
def lss_cmd(network_file, interface, channel, bitrate, timeout, scan_wait, check_wait,
            set_bitrate, fmt, output, net, select_, ignore, strict, quiet, debug):
    """Give every slave of a network its node-ID by LSS, store it, and check it.

    A slave is found by its identity -- vendor-ID and product code from the network file
    (vendor_id, product_code) or its file's [DeviceInfo], revision_number and
    serial_number from the network file; a .cpj project's nodes by their DCF's 0x1018:
    with all four by switch state selective; else among the nodes without a node-ID by
    fastscan (the parts known are confirmed, the others scanned); else by identify remote
    slave (nodes that share a factory node-ID). Each is given its node-ID (and with
    --set-bitrate the bit rate), told to store them, and reset (a node without a node-ID
    does that itself); the boot-up message at the new node-ID ends the wait. Then a scan
    shows each node answering at its node-ID with the identity found.

    Before anything is changed, these are errors: two slaves of one identity, a slave
    without a serial number among several of one vendor-ID and product code, two nodes
    on the bus that match one slave, and a node-ID another node already answers at.
    Exit status 1 when a slave is not found, refuses, or does not answer afterwards.

    The network's findings are those of 'network check' (validate's warnings about the
    node files left out), with --select/--ignore as there, and decide the exit status as
    there (--strict: warnings too); only those that make the node-IDs unsound stop it
    before anything is changed, whatever --ignore says: an error of the network file, a
    node-ID given twice, a node's file that cannot be read (NET0xx, NET200, NET201,
    DCF0xx-DCF3xx). The PDO plan and the configuration (NET1xx, NET2xx) do not stop it.
    """
    from dcf2bin.bus import link, lssnet
    from dcf2bin.network.check import NODES
    check_rules(select_, ignore)
    check_bitrate(set_bitrate)
    network, verdict = configured_network(
        network_file, quiet, "nothing changed", net, select=select_, ignore=ignore,
        strict=strict, need=NODES, going_on=GOING_ON.format(command="lss",
                                                            done="the node-IDs are given"))
    wanted = wanted_of(network)
    serial_key = "its DCF's 0x1018 sub 4" if network.kind == "cpj" else "serial_number"
    stop_on(lssnet.file_problems(wanted, serial_key), network_file, quiet)
    bus = open_bus(interface, channel, bitrate)
    try:
        result = lssnet.commission(bus, wanted, lssnet.Options(
            timeout, scan_wait, set_bitrate, serial_key=serial_key, check_wait=check_wait))
    finally:
        link.close_network(bus)
    stop_on(result.problems, network_file, quiet)
    report(result, header=network_file, where=network_file, file=network_file, fmt=fmt,
           output=output, quiet=quiet, inputs=[network_file], bitrate=set_bitrate)
    if verdict != ExitCode.OK:              # the network's own findings (said before)
        raise Failure(verdict)


def wanted_of(network) -> list:
    """Each slave with what the network file knows of its identity (identity_of: what the
    master enforces; a .cpj project's nodes their own DCF's)."""
    from dcf2bin.bus.lssnet import Wanted
    from dcf2bin.network.show import identity_of
    out = []
    for n in sorted(network.slaves, key=lambda n: n.node_id):
        known = {PARTS[k]: v for k, v in identity_of(network, n).items() if k in PARTS}
        out.append(Wanted(n.name, n.node_id, known,
                          str(n.where) if n.where is not None else network.path))
    return out


def stop_on(problems, source: str, quiet: bool) -> None:
    """Errors found before anything was changed: printed, exit 1."""
    if not problems:
        return
    emit([Diagnostic(Severity.ERROR, p.message, p.where or source) for p in problems], quiet)
    n = len(problems)
    say(f"{source}: {n} error{'s' if n != 1 else ''}, nothing changed")
    raise Failure(ExitCode.FINDINGS)


def report(result, *, header: str, where: str, file: str | None, fmt: str, output: str,
           quiet: bool, inputs: list[str], bitrate: int | None) -> None:
    """The rows as a table (led by ``header``) or JSON (naming ``file``), each failure a
    diagnostic at the slave's line (else ``where``); exit 1 unless all is well."""
    from dcf2bin.bus import lssnet
    diags = []
    for r in result.rows:
        w = r.wanted
        if r.status == lssnet.SKIPPED:
            diags.append(Diagnostic(Severity.WARNING, f"{w.label}: not given a node-ID: "
                                    f"{r.text}", w.where or where))
        elif r.status not in lssnet.OK or r.answers is False:
            diags.append(Diagnostic(Severity.ERROR, f"{w.label}: {_failure(r)}",
                                    w.where or where))
    if fmt == "json":
        write_output(to_json(result, file, bitrate), output, inputs, binary=False)
    elif not quiet:
        write_output(to_text(result, header), output, inputs, binary=False)
    emit(diags, quiet)
    if not lssnet.ok(result):
        raise Failure(ExitCode.FINDINGS)


def _failure(r) -> str:
    from dcf2bin.bus import lssnet
    if r.status == lssnet.NOT_FOUND:
        return "not found by LSS (" + lssnet.known_text(r.wanted.known) + ")"
    if r.status == lssnet.REFUSED:
        return f"refused: {r.text}"
    return f"{r.status}: {r.text}" if r.status != lssnet.ASSIGNED else r.text


def _was(value: int | None) -> str:
    return "-" if value is None else "none" if value == 0xFF else str(value)


def _answers(value: bool | None) -> str:
    return "-" if value is None else "yes" if value else "no"


def to_text(result, source: str) -> str:
    from dcf2bin.bus import lssnet
    from dcf2bin.network.show import table
    counts = {s: sum(r.status == s for r in result.rows)
              for s in (lssnet.ASSIGNED, lssnet.ALREADY, lssnet.NOT_FOUND, lssnet.REFUSED,
                        lssnet.NO_ANSWER, lssnet.SKIPPED)}
    shown = [f"{n} {s}" for s, n in counts.items()
             if n or s in (lssnet.ASSIGNED, lssnet.ALREADY, lssnet.NOT_FOUND, lssnet.REFUSED)]
    out = [f"{source}: {', '.join(shown)} ({result.seconds:.2f} s)"]
    rows = []
    for r in result.rows:
        parts = ([f"0x{v:08X}" for v in r.identity.parts] if r.identity is not None else
                 [f"0x{r.wanted.known[k]:08X}" if k in r.wanted.known else "?"
                  for k in range(4)])
        rows.append([str(r.wanted.node_id), r.wanted.name or "-", r.status,
                     r.found_by or "-", _was(r.was), *parts, _answers(r.answers), r.text])
    out += table(["node", "name", "status", "found by", "was", "vendor-ID", "product code",
                  "revision", "serial", "answers", "note"], rows)
    return "\n".join(out) + "\n"


def _hex(v: int | None) -> str | None:
    return None if v is None else f"0x{v:08X}"


def to_json(result, file: str | None, bitrate: int | None) -> str:
    """The JSON document (dcf2bin/schemas/lss.json; docs/options.md, "JSON outputs")."""
    nodes = []
    for r in result.rows:
        i = r.identity
        nodes.append({
            "node_id": r.wanted.node_id, "name": r.wanted.name or None, "status": r.status,
            "found_by": r.found_by, "was": r.was,
            "known": {k: _hex(r.wanted.known.get(p)) for p, k in enumerate(_KEYS)},
            "identity": None if i is None else {k: _hex(v) for k, v in zip(_KEYS, i.parts)},
            "booted": r.booted, "answers": r.answers,
            "error": None if r.reply is None else {
                "command": r.reply.name, "code": r.reply.code,
                "spec": r.reply.spec},
            "text": r.text})
    return json.dumps({"format": "dcf2bin-lss", "version": 1, "file": file,
                       "seconds": round(result.seconds, 3), "bit_rate": bitrate,
                       "nodes": nodes}, indent=2) + "\n"


_KEYS = ("vendor_id", "product_code", "revision_number", "serial_number")

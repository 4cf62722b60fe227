"""dcf2bin lss scan: the identities of the nodes that have no node-ID (LSS fastscan)."""
from __future__ import annotations

import json
import time

import click

from dcf2bin.cli.common import (CONTEXT, Failure, debug_option, emit, format_option, guarded,
                                output_option, quiet_option, write_output)
from dcf2bin.cli.download import bus_options, open_bus
from dcf2bin.cli.network.lss import scan_wait_option
from dcf2bin.diagnostics import Diagnostic, ExitCode, Severity

HEAD = ["vendor-ID", "product code", "revision", "serial"]


@click.command("scan", context_settings=CONTEXT)
@bus_options
@scan_wait_option
@format_option(["text", "json"], "text", "text (a table) or json.")
@output_option("The table or the JSON.")
@quiet_option("No table.")
@debug_option
@guarded
def scan_cmd(interface, channel, bitrate, scan_wait, fmt, output, quiet, debug):
    """List the nodes that have no node-ID (0xFF): vendor-ID, product code, revision and
    serial number of each.

    LSS fastscan, repeated until no node without a node-ID answers: each finds the
    lowest identity left, which is confirmed by identify remote slave, and that node
    waits in the configuration state until the scan ends (so that the next fastscan
    passes it by); then every node is switched back to waiting, as it was. Nothing is
    changed on the nodes. A fastscan takes at most 134 steps of --scan-wait seconds (6.7 s
    with the default), so N nodes at most (N + 1) x 134 x SCAN_WAIT seconds. Exit status 1
    when nodes answer that no fastscan can single out (answers later than --scan-wait), and
    when several nodes answer to one identity found (nodes alike in all four parts, which
    LSS cannot tell apart; or a node that answers twice).
    """
    from dcf2bin.bus import link
    from dcf2bin.bus import lss as L
    bus = open_bus(interface, channel, bitrate)
    master = L.Master(bus, wait=scan_wait)
    try:
        start = time.monotonic()
        census = L.unconfigured(master)
        master.switch_global(configuration=False)
        seconds = time.monotonic() - start
    finally:
        master.close()
        link.close_network(bus)
    bound = L.census_bound(census.rounds, scan_wait)
    if fmt == "json":
        write_output(_json(census, seconds, bound), output, [], binary=False)
    elif not quiet:
        write_output(_text(census, seconds, bound), output, [], binary=False)
    diags = [Diagnostic(Severity.ERROR, f"{n} nodes share the identity {identity.text()} (or "
                        "a node answers twice): LSS cannot tell them apart (give them "
                        "distinct serial numbers)", "dcf2bin")
             for identity, n in census.shared.items()]
    if not census.complete:
        diags.append(Diagnostic(Severity.ERROR, "nodes without a node-ID answer, but fastscan "
                                f"singles out none of them after {len(census.identities)} "
                                f"found (do they answer within --scan-wait {scan_wait:g} s?)",
                                "dcf2bin"))
    if diags:
        emit(diags)
        raise Failure(ExitCode.FINDINGS)


def _text(census, seconds: float, bound: float) -> str:
    from dcf2bin.network.show import table
    n = len(census.identities)
    out = [f"lss scan: {n} node{'s' if n != 1 else ''} without a node-ID, found by fastscan "
           f"in {seconds:.2f} s (at most {bound:.2f} s)"]
    if n:
        out += table(HEAD, [[f"0x{v:08X}" for v in i.parts] for i in census.identities])
    return "\n".join(out) + "\n"


def _json(census, seconds: float, bound: float) -> str:
    """The JSON document (dcf2bin/schemas/lss-scan.json; docs/options.md, "JSON outputs")."""
    keys = ("vendor_id", "product_code", "revision_number", "serial_number")
    # answers: the nodes that answered to this identity (more than 1: nodes alike in all
    # four parts, which LSS cannot tell apart, or a node that answers twice)
    nodes = [{**{k: f"0x{v:08X}" for k, v in zip(keys, i.parts)},
              "answers": census.shared.get(i, 1)} for i in census.identities]
    return json.dumps({"format": "dcf2bin-lss-scan", "version": 1,
                       "seconds": round(seconds, 3), "at_most_seconds": round(bound, 3),
                       "complete": census.complete, "nodes": nodes}, indent=2) + "\n"

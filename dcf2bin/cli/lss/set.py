"""dcf2bin lss set: give one node, found by its identity, a node-ID by LSS."""
from __future__ import annotations

import click

from dcf2bin.cli.common import (CONTEXT, Integer, debug_option, fail, format_option, guarded,
                                node_id_option, output_option, quiet_option)
from dcf2bin.cli.download import bus_options, open_bus
from dcf2bin.cli.network.lss import check_bitrate, lss_options, report

U32 = Integer(0, 0xFFFFFFFF)


@click.command("set", context_settings=CONTEXT)
@click.option("--serial", type=U32, required=True, metavar="N",
              help="The node's serial number (0x1018 sub 4).")
@click.option("--vendor", type=U32, metavar="N", help="Its vendor-ID (0x1018 sub 1).")
@click.option("--product", type=U32, metavar="N", help="Its product code (0x1018 sub 2).")
@click.option("--revision", type=U32, metavar="N",
              help="Its revision number (0x1018 sub 3).")
@node_id_option("The node-ID to give it.", required=True)
@click.option("--store", is_flag=True,
              help="Have the node store its new node-ID (LSS store configuration), so that "
              "it keeps it when it starts again.")
@bus_options
@lss_options
@format_option(["text", "json"], "text", "text (a table) or json; the errors go to "
               "standard error.")
@output_option("The table or the JSON.")
@quiet_option("No table; the errors.")
@debug_option
@guarded
def set_cmd(serial, vendor, product, revision, node_id, store, interface, channel, bitrate,
            timeout, scan_wait, check_wait, set_bitrate, fmt, output, quiet, debug):
    """Give the node with this serial number (and vendor-ID, product code, revision) a
    node-ID by LSS.

    With all four parts the node is found by switch state selective; else among the
    nodes without a node-ID by fastscan (the parts given confirmed, the others scanned),
    else -- with --vendor and --product -- by identify remote slave. It is given the
    node-ID (and with --set-bitrate the bit rate), with --store told to store them, and
    reset (a node without a node-ID does that itself); then it must answer SDO at its
    node-ID with its identity. A node-ID another node answers at is an error, and nothing
    is changed. Exit status 1 when the node is not found, refuses, or does not answer.
    """
    from dcf2bin.bus import link, lssnet
    check_bitrate(set_bitrate)
    given = {0: vendor, 1: product, 2: revision, 3: serial}
    wanted = lssnet.Wanted("", node_id, {k: v for k, v in given.items() if v is not None})
    bus = open_bus(interface, channel, bitrate)
    try:
        result = lssnet.commission(bus, [wanted], lssnet.Options(
            timeout, scan_wait, set_bitrate, store, check_wait=check_wait))
    finally:
        link.close_network(bus)
    if result.problems:
        fail(result.problems[0].message + "; nothing changed")
    report(result, header="lss set", where="dcf2bin", file=None, fmt=fmt, output=output,
           quiet=quiet, inputs=[], bitrate=set_bitrate)


"""dcf2bin network show: the links of a network as text, JSON, an SVG picture or HTML."""
from __future__ import annotations

import click

from dcf2bin import argspec
from dcf2bin.cli.common import (CONTEXT, Failure, Integer, check_input, debug_option, emit,
                                fail, format_option, guarded, output_option, quiet_option, say,
                                write_output)
from dcf2bin.diagnostics import ExitCode


def configured_network(path: str, quiet: bool, outcome: str, net: int | None = None):
    """Read ``path`` (a YAML network, configured in memory, or a .cpj project, whose nodes
    are their DCFs as they are; ``net`` picks its network) ; its findings are printed and
    an error ends the command (exit 1) saying ``outcome``."""
    check_input(path)
    from dcf2bin.network.check import read_network
    try:
        network = read_network(path, net=net)
    except OSError as exc:
        fail(f"cannot read: {exc.strerror or exc}", path, code=ExitCode.UNREADABLE)
    if len(network.nodes) > 127:
        # more nodes than node-IDs: not one network (as network check says, naming the
        # node-IDs that repeat); nothing is configured
        from dcf2bin.network.rules import node_ids
        node_ids(network, network.diagnostics)
    elif network.kind != "cpj" and not network.diagnostics.has_errors:
        from dcf2bin.network import configure
        configure(network)
    emit(network.diagnostics, quiet)
    errors = network.diagnostics.errors
    if errors:
        n = len(errors)
        say(f"{path}: {n} error{'s' if n != 1 else ''}, {outcome}")
        raise Failure(exit_code(errors))
    return network


def exit_code(errors) -> ExitCode:
    """3 when a node's file could not be read (README's table: an input that cannot be
    read), else 1."""
    from dcf2bin.network.check import UNREADABLE
    return (ExitCode.UNREADABLE if any(d.rule in UNREADABLE for d in errors)
            else ExitCode.FINDINGS)


def net_option(fn):
    """--net N: the network of a .cpj project."""
    return click.option("--net", "net", type=Integer(spec=argspec.NET), metavar="N",
                        help="For a .cpj project: its N-th network ([TopologyN]; default "
                        "the first, [Topology]).")(fn)


@click.command("show", context_settings=CONTEXT)
@click.argument("network_file", metavar="NETWORK", type=click.Path())
@format_option(["text", "json", "svg", "html"], "text",
               "text or json (the tables), svg (the picture) or html (both).")
@output_option()
@click.option("--writes", "writes", is_flag=False, flag_value="all", default=None,
              metavar="[NODE]",
              help="Also the SDO writes that configure each slave (or only NODE, a name or "
              "node-ID): index, sub, name, value and why.")
@net_option
@quiet_option("No warnings about the network file.")
@debug_option
@guarded
def show_cmd(network_file, fmt, output, writes, net, quiet, debug):
    """Show what talks to what in a network (YAML network file or .cpj project).

    Per COB-ID the producer, consumers, bytes, rate and share of the estimated bus load;
    per PLC variable the node and object it comes from; per slave the identity the
    master will enforce. The svg format draws each node as a box and each PDO as a lane
    from its producer to its consumers; html adds the tables.
    """
    from dcf2bin.network import show, svg
    network = configured_network(network_file, quiet, "nothing shown", net)
    if writes not in (None, "all") and show.find_node(network, writes) is None:
        names = ", ".join(f"{n.name} ({n.node_id})" for n in network.slaves)
        fail(f"--writes {writes}: no such node in {network_file} (slaves: {names})",
             code=ExitCode.USAGE)
    view = show.build(network, writes)
    data = {"text": show.text, "json": show.as_json, "svg": svg.to_svg,
            "html": svg.to_html}[fmt](view)
    write_output(data, output, [network_file], binary=False)


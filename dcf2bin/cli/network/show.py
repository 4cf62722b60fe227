"""dcf2bin network show: the links of a network as text, JSON, an SVG picture or HTML."""
from __future__ import annotations

import click

from dcf2bin.cli.common import (CONTEXT, Failure, check_input, emit, fail, guarded, say,
                                write_output)
from dcf2bin.diagnostics import ExitCode


def configured_network(path: str, quiet: bool, outcome: str):
    """Read ``path`` (a YAML network or a .cpj project) and configure it in memory; its
    findings are printed; an error ends the command (exit 1) saying ``outcome``."""
    check_input(path)
    from dcf2bin.network import configure, load_network
    network = load_network(path)
    if not network.diagnostics.has_errors:
        configure(network)
    emit(network.diagnostics, quiet)
    n = len(network.diagnostics.errors)
    if n:
        say(f"{path}: {n} error{'s' if n != 1 else ''}, {outcome}")
        raise Failure(ExitCode.FINDINGS)
    return network


@click.command("show", context_settings=CONTEXT)
@click.argument("network_file", metavar="NETWORK", type=click.Path())
@click.option("-f", "--format", "fmt", type=click.Choice(["text", "json", "svg", "html"]),
              default="text", show_default=True, help="Output format.")
@click.option("-o", "--output", default="-", metavar="FILE",
              help="Output file ('-' = standard output, the default).")
@click.option("--writes", "writes", is_flag=False, flag_value="all", default=None,
              metavar="[NODE]",
              help="Also the SDO writes that configure each slave (or only NODE, a name or "
              "node-ID): index, sub, name, value and why.")
@click.option("-q", "--quiet", is_flag=True, help="Print errors only, no warnings.")
@guarded
def show_cmd(network_file, fmt, output, writes, quiet):
    """Show what talks to what in a network (YAML network file or .cpj project).

    Per COB-ID the producer, consumers, bytes, rate and share of the estimated bus load;
    per PLC variable the node and object it comes from; per slave the identity the
    master will enforce. The svg format draws each node as a box and each PDO as a lane
    from its producer to its consumers; html adds the tables.
    """
    from dcf2bin.network import show, svg
    network = configured_network(network_file, quiet, "nothing shown")
    if writes not in (None, "all") and show.find_node(network, writes) is None:
        names = ", ".join(f"{n.name} ({n.node_id})" for n in network.slaves)
        fail(f"--writes {writes}: no such node in {network_file} (slaves: {names})",
             code=ExitCode.USAGE)
    view = show.build(network, writes)
    data = {"text": show.text, "json": show.as_json, "svg": svg.to_svg,
            "html": svg.to_html}[fmt](view)
    write_output(data, output, [network_file], binary=False)


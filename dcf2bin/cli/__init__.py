"""The command line: the click group and one module per command (like cantools'
``subparsers/``). This package is the only place that exits or prints results.

Every command module imports only click and ``cli.common`` at module level; the real
work (construct, canopen, the model) is imported inside the commands, so that
``dcf2bin --help`` and ``--version`` stay fast.
"""
from __future__ import annotations

import click

from dcf2bin import __version__
from dcf2bin.cli.common import CONTEXT, Group


@click.group(cls=Group, context_settings=CONTEXT)
@click.version_option(__version__, "-V", "--version", prog_name="dcf2bin")
@click.option("--debug", is_flag=True, help="Show a traceback for internal errors.")
def main(debug: bool) -> None:
    """Compile CANopen DCF/EDS files into the SYS TEC binary DCF segment container,
    inspect containers, and turn them back into text."""


def _register() -> None:
    from dcf2bin.cli import bin2dcf, compile, dump, export, simulate, tunnel, validate
    from dcf2bin.cli import download, node
    from dcf2bin.cli import allocate, map as map_
    for command in (compile.compile_cmd, dump.dump_cmd, bin2dcf.bin2dcf_cmd,
                    validate.validate_cmd, export.export_cmd, tunnel.tunnel_cmd,
                    simulate.simulate_cmd, download.download_cmd, node.node_cmd,
                    map_.map_cmd, allocate.allocate_cmd):
        main.add_command(command)
    from dcf2bin.cli.network import network_group
    main.add_command(network_group)


_register()

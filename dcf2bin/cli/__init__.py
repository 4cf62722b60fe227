"""The command line: the click group and one module per command (like cantools'
``subparsers/``). This package is the only place that exits or prints results.

Every command module imports only click and ``cli.common`` at module level; the real
work (construct, canopen, the model) is imported inside the commands, so that
``dcf2bin --help`` and ``--version`` stay fast. The group itself imports a command's
module only when that command runs (or help lists them all): ``dcf2bin compile`` does not
import the other ten commands.
"""
from __future__ import annotations

import click

from dcf2bin import __version__
from dcf2bin.cli.common import CONTEXT, LazyGroup

#: name -> "module:attribute" of every command of the program
COMMANDS = {
    "compile": "dcf2bin.cli.compile:compile_cmd",
    "dump": "dcf2bin.cli.dump:dump_cmd",
    "bin2dcf": "dcf2bin.cli.bin2dcf:bin2dcf_cmd",
    "convert": "dcf2bin.cli.convert:convert_cmd",
    "validate": "dcf2bin.cli.validate:validate_cmd",
    "export": "dcf2bin.cli.export:export_cmd",
    "tunnel": "dcf2bin.cli.tunnel:tunnel_cmd",
    "simulate": "dcf2bin.cli.simulate:simulate_cmd",
    "download": "dcf2bin.cli.download:download_cmd",
    "upload": "dcf2bin.cli.upload:upload_cmd",
    "node": "dcf2bin.cli.node:node_cmd",
    "map": "dcf2bin.cli.map:map_cmd",
    "allocate": "dcf2bin.cli.allocate:allocate_cmd",
    "diff": "dcf2bin.cli.diff:diff_cmd",
    "network": "dcf2bin.cli.network:network_group",
    "lss": "dcf2bin.cli.lss:lss_group",
}


@click.group(cls=LazyGroup, lazy=COMMANDS, context_settings=CONTEXT)
@click.version_option(__version__, "-V", "--version", prog_name="dcf2bin")
@click.option("--debug", is_flag=True, help="Show a traceback for internal errors.")
def main(debug: bool) -> None:
    """Compile CANopen DCF/EDS files into the SYS TEC binary DCF segment container,
    inspect containers, and turn them back into text."""

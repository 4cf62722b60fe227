"""dcf2bin network: the click group of the network commands (one module per
subcommand: build, check, show, download, upload, scan, lss).

Subcommands are imported when they are run or listed, so that ``dcf2bin --help`` imports
none of them (nor yaml, canopen, construct); a subcommand whose module is not installed
is not listed.
"""
from __future__ import annotations

import importlib.util

import click

from dcf2bin.cli.common import CONTEXT, LazyGroup

SUBCOMMANDS = ("build", "check", "show", "download", "upload", "scan", "lss")


class NetworkGroup(LazyGroup):
    """Lists the subcommands whose modules exist, in the order above; imports one when it
    is asked for (and all of them when ``commands`` is read, as help and introspection
    do)."""

    def list_commands(self, ctx):
        return [name for name in SUBCOMMANDS
                if importlib.util.find_spec(f"dcf2bin.cli.network.{name}") is not None]


@click.group("network", cls=NetworkGroup, context_settings=CONTEXT,
             lazy={name: f"dcf2bin.cli.network.{name}:{name}_cmd" for name in SUBCOMMANDS})
def network_group() -> None:
    """Build and check a PLC's CANopen network from its network file (lely's dcfgen YAML,
    which ros2_canopen's bus.yml also is)."""

"""dcf2bin network: the click group of the network commands (one module per
subcommand: build, check, show, download, scan).

Subcommands are imported when they are run or listed, so that ``dcf2bin --help`` imports
none of them (nor yaml, canopen, construct); a subcommand whose module is not installed
is not listed.
"""
from __future__ import annotations

import importlib
import importlib.util

import click

from dcf2bin.cli.common import CONTEXT, Group

SUBCOMMANDS = ("build", "check", "show", "download", "scan")


class NetworkGroup(Group):
    """Lists the subcommands whose modules exist; imports one when it is asked for (and
    all of them when ``commands`` is read, as help and introspection do)."""

    @property
    def commands(self) -> dict:
        for name in self.list_commands(None):
            if name not in self._commands:
                self._commands[name] = self._load(name)
        return self._commands

    @commands.setter
    def commands(self, value) -> None:
        self._commands = dict(value or {})

    def list_commands(self, ctx):
        return [name for name in SUBCOMMANDS
                if importlib.util.find_spec(f"dcf2bin.cli.network.{name}") is not None]

    def get_command(self, ctx, name):
        if name not in self._commands:
            if name not in self.list_commands(ctx):
                return None
            self._commands[name] = self._load(name)
        return self._commands[name]

    @staticmethod
    def _load(name: str):
        module = importlib.import_module(f"dcf2bin.cli.network.{name}")
        return getattr(module, f"{name}_cmd")


@click.group("network", cls=NetworkGroup, context_settings=CONTEXT)
def network_group() -> None:
    """Build and check a PLC's CANopen network from its network file (lely's dcfgen YAML,
    which ros2_canopen's bus.yml also is)."""

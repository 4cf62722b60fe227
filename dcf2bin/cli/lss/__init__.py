"""dcf2bin lss: the click group of the LSS commands (CiA 305) for single nodes -- scan
(the nodes without a node-ID) and set (give one node its node-ID); `network lss` gives a
whole network its node-IDs.

Subcommands are imported when they are run or listed, as the network group's are."""
from __future__ import annotations

import importlib.util

import click

from dcf2bin.cli.common import CONTEXT, LazyGroup

SUBCOMMANDS = ("scan", "set")


class LssGroup(LazyGroup):
    """Lists the subcommands whose modules exist, in the order above."""

    def list_commands(self, ctx):
        return [name for name in SUBCOMMANDS
                if importlib.util.find_spec(f"dcf2bin.cli.lss.{name}") is not None]


@click.group("lss", cls=LssGroup, context_settings=CONTEXT,
             lazy={name: f"dcf2bin.cli.lss.{name}:{name}_cmd" for name in SUBCOMMANDS})
def lss_group() -> None:
    """Find nodes by their identity and give them node-IDs (LSS, CiA 305)."""

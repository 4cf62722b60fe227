"""The man pages stay honest: every command and every option is documented."""
from __future__ import annotations

import re

import click
import pytest

from conftest import ROOT
from dcf2bin.cli import main

MAN = ROOT / "man"


def _pages_for(command: str) -> str:
    text = (MAN / "dcf2bin.1").read_text()
    page = MAN / f"dcf2bin-{command}.1"
    if page.exists():
        text += page.read_text()
    return text.replace("\\-", "-")


def _options(cmd: click.Command):
    for p in cmd.params:
        if isinstance(p, click.Option):
            for opt in p.opts + p.secondary_opts:
                if opt not in ("-h", "--help"):
                    yield opt


@pytest.mark.parametrize("name", sorted(main.commands))
def test_every_option_is_in_the_man_page(name):
    text = _pages_for(name)
    missing = [o for o in _options(main.commands[name])
               if not re.search(r"(?<![\w-])" + re.escape(o) + r"(?![\w-])", text)]
    assert missing == [], f"{name}: not in man/: {missing}"


def _subcommands():
    """(group, subcommand) of every command group (dcf2bin network build, ...)."""
    ctx = click.Context(main)
    for name, cmd in sorted(main.commands.items()):
        if isinstance(cmd, click.Group):
            for sub in cmd.list_commands(ctx):
                yield name, sub


@pytest.mark.parametrize("group,name", list(_subcommands()))
def test_every_subcommand_option_is_in_its_man_page(group, name):
    page = MAN / f"dcf2bin-{group}-{name}.1"
    assert page.exists(), page
    text = page.read_text().replace("\\-", "-")
    cmd = main.commands[group].get_command(click.Context(main), name)
    missing = [o for o in _options(cmd)
               if not re.search(r"(?<![\w-])" + re.escape(o) + r"(?![\w-])", text)]
    assert missing == [], f"{group} {name}: not in man/: {missing}"


def test_every_command_is_listed_in_the_main_page():
    text = (MAN / "dcf2bin.1").read_text()
    for name in main.commands:
        assert f".B {name}" in text, name


def test_global_options_documented():
    text = _pages_for("")
    assert [o for o in _options(main) if o not in text] == []

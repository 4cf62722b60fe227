"""The command line: the click group and one module per command (like cantools'
``subparsers/``). This package is the only place that exits or prints results.

Every command module imports only click and ``cli.common`` at module level; the real
work (construct, canopen, the model) is imported inside the commands, so that
``dcf2bin --help`` and ``--version`` stay fast.
"""
from __future__ import annotations

import os
import sys

import click

from dcf2bin import __version__
from dcf2bin.cli.common import CONTEXT, Group


class _Entry(Group):
    """The program's group, as the console script and ``python -m dcf2bin`` call it.

    Called with no arguments (``main()``: click reads ``sys.argv`` and ends the process),
    a ``compile`` that ran to its exit code leaves without the interpreter's teardown: its
    output is written, fsynced and renamed by then, and freeing the tens of thousands of
    objects of a big file's model and the imported modules one by one would only add to
    the run's time (10-20 ms; nothing of it is observable). Every other way of calling
    it -- with arguments, ``CliRunner``, ``standalone_mode=False``, the Python API --, and
    every other command, exit as click does.
    """

    fast_exit = frozenset({"compile"})   # commands that leave nothing to finalise

    _ran: str | None = None      # the command this call ran

    def resolve_command(self, ctx, args):
        name, cmd, rest = super().resolve_command(ctx, args)
        self._ran = cmd.name if cmd is not None else None
        return name, cmd, rest

    def __call__(self, *args, **kwargs):
        if args or kwargs:
            return super().__call__(*args, **kwargs)
        self._ran = None
        try:
            return super().__call__()
        except SystemExit as exc:
            code = 0 if exc.code is None else exc.code
            if (type(code) is not int or self._ran not in self.fast_exit
                    or not _flushed() or "coverage" in sys.modules):
                raise
            os._exit(code)


def _flushed() -> bool:
    """Both standard streams flushed (what the interpreter does last); False if one fails,
    and the normal exit then reports it as it always did."""
    for stream in (sys.stdout, sys.stderr):
        if stream is None:
            continue
        try:
            stream.flush()
        except (OSError, ValueError):
            return False
    return True


@click.group(cls=_Entry, context_settings=CONTEXT)
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

"""dcf2bin dump: show a binary container as a report or as the lossless JSON form."""
from __future__ import annotations

import click

from dcf2bin.cli.common import (CONTEXT, debug_option, format_option, guarded, output_option,
                                quiet_option, read_container, read_eds, without_cyclic_gc,
                                write_output)

INPUT = click.argument("input", metavar="FILE.bin",
                       type=click.Path(allow_dash=True))
EDS = click.option("--eds", type=click.Path(), metavar="EDS",
                   help="EDS/DCF of the device: exact data types, access and names.")
QUIET = quiet_option()


# -- dump ---------------------------------------------------------------------------------------

@click.command("dump", context_settings=CONTEXT)
@INPUT
@format_option(["text", "json"], "text", "text = readable report; json = lossless form "
               "that 'compile' turns back into the same bytes.")
@output_option("Default: standard output.")
@click.option("--eds", type=click.Path(), metavar="EDS",
              help="EDS/DCF of the device: exact types and names in the text report.")
@click.option("--full", is_flag=True, help="Show long data in full (text format).")
@QUIET
@debug_option
@guarded
@without_cyclic_gc
def dump_cmd(input, fmt, output, eds, full, quiet, debug):
    """Show what a binary container holds: header, entries, attributes, process image.

    The text report decodes values and attribute bits; the JSON form records every
    byte as stored (repeated writes, undefined attribute bits, odd headers) and is
    turned back into the same container by 'dcf2bin compile FILE.json'.
    """
    from dcf2bin import dump
    c, name = read_container(input, quiet)
    if fmt == "json":
        text = dump.to_json(c)
    else:
        info, _ = read_eds(eds, quiet)
        text = dump.report(c, name, eds=info, full=full)
    write_output(text, output, [input] + ([eds] if eds else []), binary=False)

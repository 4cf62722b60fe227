"""dcf2bin allocate: place network variables from a CSV list in the CiA 405 ranges and
write them as DCF text (standalone, or merged into an existing DCF)."""
from __future__ import annotations

import os

import click

from dcf2bin.cli.common import (CONTEXT, emit, guarded, read_input, stop_on_errors,
                                write_output)


@click.command("allocate", context_settings=CONTEXT)
@click.argument("input", metavar="VARS.csv", type=click.Path(dir_okay=False, allow_dash=True))
@click.option("-o", "--output", type=click.Path(dir_okay=False, allow_dash=True), default="-",
              help="Output DCF ('-' for stdout, the default).")
@click.option("--into", type=click.Path(dir_okay=False), metavar="BASE.dcf",
              help="Merge into this DCF: its variables keep their places, its other lines "
              "stay as they are.")
@click.option("-v", "--verbose", is_flag=True, help="Print where each variable went.")
@guarded
def allocate_cmd(input, output, into, verbose):
    """Place network variables in the CiA 405 ranges and write them as a DCF.

    VARS.csv starts with the header row name,type,direction. Per area (input, output), the data types in order of first appearance; each type's
    variables take the first free elements of its CiA 405 range after the bytes already
    used, in the order of the list.
    """
    from dcf2bin.plc import allocate as alloc
    data = read_input(input)
    name = "<stdin>" if input == "-" else input
    kept = []
    try:
        variables = alloc.read_vars(data, name)
        if into is None:
            placed = alloc.allocate(variables, name)
            file_name = os.path.basename(output) if output != "-" else "allocated.dcf"
            text = alloc.standalone(placed, file_name).encode("utf-8")
        else:
            from dcf2bin.plc.merge import merge
            base = read_input(into)
            text, placed, kept = merge(base, into, variables, name)
    except alloc.AllocationError as exc:
        emit(exc.diagnostics)
        stop_on_errors(exc, name, "nothing written")
    write_output(text, output, [input] + ([into] if into else []), binary=False)
    if verbose:
        for v, idx, sub in kept:
            click.echo(f"{v.name}: 0x{idx:04X}sub{sub:X} (kept)", err=True)
        for p in placed:
            click.echo(f"{p.var.name}: 0x{p.index:04X}sub{p.sub:X}, {p.var.direction} "
                       f"offset {p.offset}", err=True)

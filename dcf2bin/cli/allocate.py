"""dcf2bin allocate: place network variables from a CSV list in the CiA 405 ranges and
write them as DCF text (standalone, or merged into an existing DCF)."""
from __future__ import annotations

import os

import click

from dcf2bin.cli.common import (CONTEXT, debug_option, emit, fail, guarded, input_kind,
                                output_option, quiet_option, read_input, stop_on_errors,
                                verbose_option, write_output)


@click.command("allocate", context_settings=CONTEXT)
@click.argument("input", metavar="VARS.csv", type=click.Path(allow_dash=True))
@output_option("Default: standard output.")
@click.option("--into", type=click.Path(), metavar="BASE.dcf",
              help="Merge into this DCF: its variables keep their places, its other lines "
              "stay as they are.")
@quiet_option()
@verbose_option("where each variable went.")
@debug_option
@guarded
def allocate_cmd(input, output, into, quiet, verbose, debug):
    """Place network variables in the CiA 405 ranges and write them as a DCF.

    VARS.csv starts with the header row name,type,direction. Per area (input, output), the data types in order of first appearance; each type's
    variables take the first free elements of its CiA 405 range after the bytes already
    used, in the order of the list.
    """
    from dcf2bin.plc import allocate as alloc
    data = read_input(input)
    name = "<stdin>" if input == "-" else input
    if b"\0" in data[:8192]:
        from dcf2bin import filekind
        kind = filekind.detect(data, input)
        fail(f"{filekind.what_it_is(name, kind)}, not a CSV list of variables; "
             f"{filekind.advice(kind)}", name)
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
            input_kind(into, base, ("dcf",), quiet=quiet, use="--into takes the DCF to merge "
                       "the variables into")
            text, placed, kept = merge(base, into, variables, name)
    except alloc.AllocationError as exc:
        emit(exc.diagnostics)
        stop_on_errors(exc, name, "nothing written")
    write_output(text, output, [input] + ([into] if into else []), binary=False)
    if verbose and not quiet:
        for v, idx, sub in kept:
            click.echo(f"{v.name}: 0x{idx:04X}sub{sub:X} (kept)", err=True)
        for p in placed:
            click.echo(f"{p.var.name}: 0x{p.index:04X}sub{p.sub:X}, {p.var.direction} "
                       f"offset {p.offset}", err=True)

"""dcf2bin map: the variable map of the process image (text, CSV, JSON, IEC 61131-3, C
header, SVG, HTML) from a DCF/EDS, a binary container or its lossless JSON form."""
from __future__ import annotations

import os

import click

from dcf2bin import argspec
from dcf2bin.cli.common import (CONTEXT, Choice, Failure, debug_option, decode_container, emit,
                                entries_option, fail, format_option, from_option, guarded,
                                input_kind, node_id_option, output_option, quiet_option,
                                read_eds, read_input, stop_on_errors, without_cyclic_gc,
                                write_output)
from dcf2bin.diagnostics import ExitCode

FORMATS = ["text", "csv", "json", "iec", "c", "svg", "html"]


@click.command("map", context_settings=CONTEXT)
@click.argument("input", metavar="FILE", type=click.Path(allow_dash=True))
@format_option(FORMATS, "text", "the map as a table, CSV, JSON, IEC 61131-3 declarations, "
               "a C header, an SVG picture or an HTML page.")
@output_option("Default: standard output.")
@from_option(["dcf", "bin", "json"], "dcf = DCF/EDS, bin = container, json = lossless dump.")
@click.option("--eds", type=click.Path(), metavar="EDS",
              help="Container input: the device's EDS/DCF for names, exact types and "
              "[DynamicChannels].")
@click.option("--address-base", type=Choice(argspec.ADDRESS_BASE), default="image",
              show_default=True, help="Container input: how its PI addresses were written "
              "(compile --address-base).")
@node_id_option("DCF input: used for $NODEID values.")
@entries_option("DCF input.")
@click.option("--pi-align", type=Choice(argspec.PI_ALIGN), default="8",
              show_default=True, help="DCF input: alignment of the output area's start.")
@click.option("--iec-addressing", type=click.Choice(["byte", "element"]), default="byte",
              show_default=True, help="iec: %I/%Q numbers count bytes, or units of the size "
              "prefix (W 2, D 4, L 8 bytes, as CODESYS counts).")
@click.option("--prefix", default="DCF_", show_default=True,
              help="c: prefix of every macro name.")
@quiet_option()
@debug_option
@guarded
@without_cyclic_gc
def map_cmd(input, fmt, output, from_, eds, address_base, node_id, entries, pi_align,
            iec_addressing, prefix, quiet, debug):
    """Show where every network variable lies in the process image.

    One row per network variable in image-address order: name (Denotation, else
    ParameterName), entry, data type, direction, offset in its area, image address,
    size; plus the complete PI size and the offset and size of both areas.
    """
    from dcf2bin.plc import varmap
    from dcf2bin.plc.cheader import prefix_problem
    if fmt == "c" and (problem := prefix_problem(prefix)):
        fail(f"--prefix: {problem}", code=ExitCode.USAGE)
    data = read_input(input)
    name = "<stdin>" if input == "-" else input
    kind = input_kind(input, data, ("dcf", "xdd", "bin", "json"), from_, quiet=quiet)
    inputs = [input] + ([eds] if eds else [])
    if kind in ("dcf", "xdd"):
        if eds:
            fail("--eds is for a container input; a DCF names its own variables",
                 code=ExitCode.USAGE)
        from dcf2bin.compiler import CompileOptions, compile_path
        res = compile_path(name, CompileOptions(node_id=node_id, select=entries,
                                                  pi_align=int(pi_align)),
                           data=data)
        emit(res.diagnostics, quiet)
        stop_on_errors(res, name, "no map")
        vm = varmap.from_result(res, os.path.basename(name))
    else:
        c = decode_container(data, name, quiet, json_input=kind == "json")
        info, dev = read_eds(eds, quiet)
        vm, diags = varmap.from_container(c, name, eds=info, eds_device=dev,
                                          address_base=address_base)
        emit(diags, quiet)
        if vm is None:
            raise Failure(ExitCode.FINDINGS)
        vm.source = os.path.basename(name)
    text = render(vm, fmt, iec_addressing, prefix)
    write_output(text, output, inputs, binary=False)


def render(vm, fmt: str, iec_addressing: str, prefix: str) -> str:
    if fmt in ("text", "csv", "json"):
        from dcf2bin.plc import tables
        return {"text": tables.to_text, "csv": tables.to_csv, "json": tables.to_json}[fmt](vm)
    if fmt == "iec":
        from dcf2bin.plc import iec
        text, diags = iec.render(vm, iec_addressing)
        emit(diags)
        if text is None:
            raise Failure(ExitCode.FINDINGS)
        return text
    if fmt == "c":
        from dcf2bin.plc import cheader
        return cheader.render(vm, prefix)
    from dcf2bin.plc import picture
    return picture.to_svg(vm) if fmt == "svg" else picture.to_html(vm)

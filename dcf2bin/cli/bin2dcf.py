"""dcf2bin bin2dcf (also installed as ``bin2dcf``): a container or a concise DCF back into a
DCF."""
from __future__ import annotations

import os

import click

from dcf2bin import __version__
from dcf2bin.cli.common import (CONTEXT, Command, Failure, debug_option, decode_concise,
                                decode_container, default_output, emit, fail, force_option,
                                guarded, input_kind, output_option, read_eds, read_input,
                                without_cyclic_gc, write_output)
from dcf2bin.cli.dump import EDS, INPUT, QUIET
from dcf2bin.diagnostics import Diagnostic, ExitCode, Severity

@without_cyclic_gc
def _bin2dcf(input, output, force, eds, strict, quiet) -> None:
    from dcf2bin import dcfwriter
    kind, c, name = _read(input, quiet)
    if strict and kind == "concise":
        fail(f"{name} is a concise DCF: --strict checks that compile gives a container's "
             "bytes back, and a DCF keeps no order of a concise DCF's writes; convert it "
             "without --strict", name, ExitCode.USAGE)
    if output is None:
        # beside plc.bin usually stands the plc.dcf it was compiled from: never clobber it
        output = default_output(input, ".dcf", force,
                                " (often the DCF this container was compiled from)")
    info, dev = read_eds(eds, quiet)
    if output != "-":
        dcf_name = os.path.basename(output)
    else:
        dcf_name = (os.path.splitext(os.path.basename(input))[0] if input != "-" else "stdin") \
            + ".dcf"
    if kind == "concise":
        res = dcfwriter.convert_concise(c, name, dcf_name=dcf_name, eds=info, eds_device=dev)
    else:
        res = dcfwriter.convert(c, name, dcf_name=dcf_name, eds=info, eds_device=dev)
    if strict and not res.roundtrip:
        emit([Diagnostic(Severity.ERROR if d.rule == dcfwriter.R_SUMMARY else d.severity,
                         d.message, d.file, d.line, d.column, d.offset, d.rule, d.hint)
              for d in res.diagnostics], quiet)
        click.echo(f"{name}: the DCF would not compile back to the same container "
                   "(--strict), nothing written", err=True)
        raise Failure(ExitCode.FINDINGS)
    emit(res.diagnostics, quiet)
    write_output(res.to_bytes(), output, [input] + ([eds] if eds else []), binary=False)


def _read(path: str, quiet: bool):
    """A container or a concise DCF, or the lossless JSON form of either (``dump -f json``:
    the bytes it records), each by its content: ``(kind, what, name)`` as
    ``common.read_binary`` gives them."""
    data = read_input(path)
    name = "<stdin>" if path == "-" else path
    kind = input_kind(path, data, ("bin", "concise", "json", "concise-json"), quiet=quiet,
                      use={"dcf": "it is a DCF already (dcf2bin compile makes a container "
                                  "of it)"})
    if kind == "concise-json":
        from dcf2bin.dump import from_json_bytes
        data, diags = from_json_bytes(data, name)
        emit(diags, quiet)
        if data is None:
            raise Failure(ExitCode.FINDINGS)
        return "concise", decode_concise(data, name, quiet), name
    if kind == "concise":
        return kind, decode_concise(data, name, quiet), name
    return "bin", decode_container(data, name, quiet, json_input=kind == "json"), name


def _bin2dcf_options(fn):
    for deco in reversed([
        INPUT,
        output_option("Default: FILE with the suffix .dcf, never over an existing file "
                      "unless --force.", default=None),
        force_option,
        EDS,
        click.option("--strict", is_flag=True,
                     help="Fail (exit 1, nothing written) when the DCF would not compile "
                          "back to the same bytes (a container only)."),
        QUIET,
    ]):
        fn = deco(fn)
    return fn


_BIN2DCF_HELP = """Turn a binary container or a concise DCF (or the JSON form of either,
from 'dcf2bin dump --format json') back into a DCF.

One object section per index; ParameterValue is the last value written, comments list
earlier writes (PDO sequences). Types come from the CiA 405 ranges and the attribute
bytes, or from --eds; a concise DCF has no attribute bytes: its types are CiA 301's
where it fixes them, else guessed from the size, unless --eds gives them. For a container,
a warning names everything that 'dcf2bin compile' would not turn back into the same bytes
(use 'dcf2bin dump --format json' for a lossless copy).
"""


@click.command("bin2dcf", context_settings=CONTEXT, help=_BIN2DCF_HELP)
@_bin2dcf_options
@debug_option
@guarded
def bin2dcf_cmd(input, output, force, eds, strict, quiet, debug):
    _bin2dcf(input, output, force, eds, strict, quiet)


@click.command("bin2dcf", cls=Command, context_settings=CONTEXT, help=_BIN2DCF_HELP)
@click.version_option(__version__, "-V", "--version", prog_name="bin2dcf")
@_bin2dcf_options
@debug_option
@guarded
def bin2dcf_main(input, output, force, eds, strict, quiet, debug):
    _bin2dcf(input, output, force, eds, strict, quiet)

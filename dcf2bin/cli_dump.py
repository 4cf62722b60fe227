"""Commands: dump and bin2dcf: containers to text (issue 3).

Only click and the shared CLI plumbing are imported here; the modules that do the
work (construct, the model) are imported inside the commands.
"""
from __future__ import annotations

import os

import click

from dcf2bin import __version__
from dcf2bin.clitools import CONTEXT, Failure, emit, fail, guarded, read_input, write_output
from dcf2bin.diagnostics import Diagnostic, ExitCode, Severity


def _read_container(path: str, quiet: bool):
    """Read and decode a container; a bad one ends with one line naming the byte offset."""
    from dcf2bin.dump import read_bytes
    data = read_input(path)
    name = "<stdin>" if path == "-" else path
    c, diags = read_bytes(data, name)
    emit(diags, quiet)
    if c is None:
        raise Failure(ExitCode.FINDINGS)
    return c, name


def _read_eds(path: str | None, quiet: bool):
    if path is None:
        return None, None
    from dcf2bin.dump import load_eds
    data = read_input(path)
    info, dev, errors = load_eds(path, data)
    if errors:
        emit([Diagnostic(Severity.WARNING, f"the EDS has {errors} error"
                         f"{'s' if errors != 1 else ''} (see 'dcf2bin validate'); types and "
                         "names are taken where they could be read", path)], quiet)
    return info, dev


_INPUT = click.argument("input", metavar="FILE.bin",
                        type=click.Path(dir_okay=False, allow_dash=True))
_EDS = click.option("--eds", type=click.Path(dir_okay=False), metavar="EDS",
                    help="EDS/DCF of the device: exact data types, access and names.")
_QUIET = click.option("-q", "--quiet", is_flag=True, help="Print errors only.")


# -- dump ---------------------------------------------------------------------------------------

@click.command("dump", context_settings=CONTEXT)
@_INPUT
@click.option("-f", "--format", "fmt", type=click.Choice(["text", "json"]), default="text",
              show_default=True, help="text: readable report; json: lossless form that "
              "'compile' turns back into the same bytes.")
@click.option("-o", "--output", type=click.Path(dir_okay=False, allow_dash=True), default="-",
              help="Output file ('-' for stdout, the default).")
@click.option("--eds", type=click.Path(dir_okay=False), metavar="EDS",
              help="EDS/DCF of the device: exact types and names in the text report.")
@click.option("--full", is_flag=True, help="Show long data in full (text format).")
@_QUIET
@guarded
def dump_cmd(input, fmt, output, eds, full, quiet):
    """Show what a binary container holds: header, entries, attributes, process image.

    The text report decodes values and attribute bits; the JSON form records every
    byte as stored (repeated writes, undefined attribute bits, odd headers) and is
    turned back into the same container by 'dcf2bin compile FILE.json'.
    """
    from dcf2bin import dump
    c, name = _read_container(input, quiet)
    if fmt == "json":
        text = dump.to_json(c)
    else:
        info, _ = _read_eds(eds, quiet)
        text = dump.report(c, name, eds=info, full=full)
    write_output(text, output, [input] + ([eds] if eds else []), binary=False)


# -- bin2dcf ------------------------------------------------------------------------------------

def _bin2dcf(input, output, eds, strict, quiet) -> None:
    from dcf2bin import dcfwriter
    if output is None:
        if input == "-":
            fail("reading stdin needs -o OUTPUT (or -o - for stdout)", code=ExitCode.USAGE)
        output = os.path.splitext(input)[0] + ".dcf"
        if os.path.exists(output):
            # beside plc.bin usually stands the plc.dcf it was compiled from: never clobber it
            fail(f"{output} exists (often the DCF this container was compiled from); "
                 "choose the output with -o", code=ExitCode.USAGE)
    c, name = _read_container(input, quiet)
    info, dev = _read_eds(eds, quiet)
    if output != "-":
        dcf_name = os.path.basename(output)
    else:
        dcf_name = (os.path.splitext(os.path.basename(input))[0] if input != "-" else "stdin") \
            + ".dcf"
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


def _bin2dcf_options(fn):
    for deco in reversed([
        _INPUT,
        click.option("-o", "--output", type=click.Path(dir_okay=False, allow_dash=True),
                     help="Output DCF ('-' for stdout). Default: FILE with the suffix .dcf."),
        _EDS,
        click.option("--strict", is_flag=True,
                     help="Fail (exit 1, nothing written) when the DCF would not compile "
                          "back to the same bytes."),
        _QUIET,
    ]):
        fn = deco(fn)
    return fn


_BIN2DCF_HELP = """Turn a binary container back into a DCF (SPEC §4).

One object section per index; ParameterValue is the last value written, comments list
earlier writes (PDO sequences). Types come from the CiA 405 ranges and the attribute
bytes, or from --eds. A warning names everything that 'dcf2bin compile' would not turn
back into the same bytes (use 'dcf2bin dump --format json' for a lossless copy).
"""


@click.command("bin2dcf", context_settings=CONTEXT, help=_BIN2DCF_HELP)
@_bin2dcf_options
@guarded
def bin2dcf_cmd(input, output, eds, strict, quiet):
    _bin2dcf(input, output, eds, strict, quiet)


@click.command("bin2dcf", context_settings=CONTEXT, help=_BIN2DCF_HELP)
@click.version_option(__version__, "-V", "--version", prog_name="bin2dcf")
@_bin2dcf_options
@click.option("--debug", is_flag=True, help="Show a traceback for internal errors.")
@guarded
def bin2dcf_main(input, output, eds, strict, quiet, debug):
    _bin2dcf(input, output, eds, strict, quiet)


COMMANDS: list = [dump_cmd, bin2dcf_cmd]

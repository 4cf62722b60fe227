"""dcf2bin dump: show a binary container or a concise DCF as a report or as the lossless
JSON form."""
from __future__ import annotations

import click

from dcf2bin.cli.common import (CONTEXT, debug_option, eds_option, emit, format_option,
                                guarded, output_option, quiet_option, read_binary, read_eds,
                                read_input, without_cyclic_gc, write_output)

INPUT = click.argument("input", metavar="FILE.bin",
                       type=click.Path(allow_dash=True))
EDS = eds_option()
QUIET = quiet_option()


# -- dump ---------------------------------------------------------------------------------------

@click.command("dump", context_settings=CONTEXT)
@INPUT
@format_option(["text", "json"], "text", "text = readable report; json = lossless form "
               "that 'compile' turns back into the same bytes.")
@output_option("Default: standard output.")
@eds_option("Text report: values decoded with them, names shown.")
@click.option("--full", is_flag=True, help="Show long data in full (text format).")
@click.option("--textconv", is_flag=True,
              help="The text for git's textconv filter: one line per entry with all its "
              "data, and no file name, entry number, byte offset or padding, so that "
              "git diff shows the entries that changed and nothing else.")
@QUIET
@debug_option
@guarded
@without_cyclic_gc
def dump_cmd(input, fmt, output, eds, full, textconv, quiet, debug):
    """Show what a binary container or a concise DCF holds.

    A container: header, entries, attributes, process image. A concise DCF (CiA 302-3,
    what 'network build' writes for a slave): its entries in the order they are written.
    The text report decodes values (a type guessed from the size alone ends in ?; --eds
    gives the device's types); the JSON form records every byte as stored (repeated
    writes, undefined attribute bits, odd headers) and is turned back into the same file
    by 'dcf2bin compile FILE.json'.
    """
    from dcf2bin import dump
    if textconv and fmt == "json":
        raise click.UsageError("--textconv is a text form of its own: give it without "
                               "-f json")
    if textconv:
        write_output(_textconv(input, eds, quiet), output, [input] + ([eds] if eds else []),
                     binary=False)
        return
    kind, what, name = read_binary(input, quiet)
    if fmt == "json":
        text = dump.concise_json.to_json(what) if kind == "concise" else dump.to_json(what)
    else:
        info, _ = read_eds(eds, quiet)
        if kind == "concise":
            text = dump.concise_report(what, name, eds=info, eds_name=eds or "", full=full)
        else:
            text = dump.report(what, name, eds=info, full=full)
    write_output(text, output, [input] + ([eds] if eds else []), binary=False)


def _textconv(path: str, eds, quiet: bool) -> str:
    """git's textconv filter must not fail on a file it can read: git would abort the whole
    diff. Bytes that are no whole container or concise DCF are text too, the error a line
    of it (exit 0); only a file that cannot be read at all (missing, a FIFO) is exit 3."""
    from dcf2bin import filekind
    from dcf2bin.concise import read_concise
    from dcf2bin.dump import read_bytes
    from dcf2bin.dump import textconv as tc
    data = read_input(path)
    info, _ = read_eds(eds, quiet)
    name = "<stdin>" if path == "-" else path
    kind = filekind.detect(data, "" if path == "-" else path)
    problem = filekind.mismatch("the file", kind, ("bin", "concise"))
    if problem:
        return tc.damaged(data, None, problem)
    if kind == "concise":
        entries, diags = read_concise(data, name)
        if entries is None:
            return tc.damaged(data, kind, diags[0], eds=info, eds_name=eds or "")
        return tc.concise_dcf(entries, eds=info, eds_name=eds or "")
    c, diags = read_bytes(data, name)
    if c is None:
        return tc.damaged(data, kind, diags[0])
    emit(diags, quiet)
    return tc.container(c, eds=info)

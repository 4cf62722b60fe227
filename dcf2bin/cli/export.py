"""dcf2bin export: other systems' object dictionaries (Lenze PLC Designer, port, CANopenNode)
and the documentation of one.

    dcf2bin export --format lenze-st|lenze-bin|port-c|markdown|html INPUT [-o OUT]
    dcf2bin export --format canopennode INPUT -o FOLDER [--od-name OD]

Only click and the shared CLI pieces are imported here; the work is imported inside the
commands so that ``dcf2bin --help`` stays fast.
"""
from __future__ import annotations

import click

from dcf2bin.cli.common import (CONTEXT, Integer, debug_option, emit, fail, format_option,
                                guarded, input_kind, node_id_option, output_option, quiet_option,
                                read_input, stop_on_errors, without_cyclic_gc, write_output)
from dcf2bin.diagnostics import ExitCode, shorten

# Kept literally here (module-level imports stay light); tests check it equals
# dcf2bin.export.FORMATS.
FORMATS = ("lenze-st", "lenze-bin", "port-c", "markdown", "html", "canopennode")
# the formats that write several files into the folder -o names
FOLDER_FORMATS = ("canopennode",)

# Options that only one family of formats uses: name -> the formats it applies to.
# (markdown, html and canopennode show or keep values as written: --node-id and
# --allow-external-files change nothing there)
_VALUES = ("lenze-st", "lenze-bin", "port-c")
_FORMAT_OPTIONS = {
    "node_id": _VALUES, "allow_external_files": _VALUES,
    "var_name": ("lenze-st",), "with_type": ("lenze-st",),
    "includes": ("port-c",), "symbol": ("port-c",), "prefix": ("port-c",),
    "max_object_size": ("port-c",), "od_name": ("canopennode",),
}
_OPTION_NAMES = {"node_id": "--node-id", "allow_external_files": "--allow-external-files",
                 "var_name": "--var-name", "with_type": "--with-type",
                 "includes": "--include", "symbol": "--symbol", "prefix": "--prefix",
                 "max_object_size": "--max-object-size", "od_name": "--od-name"}


def _identifier(kind: str):
    def check(ctx, param, value):
        import re
        if value is None:
            return value
        values = value if isinstance(value, tuple) else (value,)
        for v in values:
            if kind == "header":
                if not v or '"' in v or "\n" in v:
                    raise click.BadParameter(f"'{shorten(v)}' is not a header name")
            elif not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", v):
                raise click.BadParameter(f"'{shorten(v)}' is not {kind} identifier")
        return value
    return check


@click.command("export", context_settings=CONTEXT)
@click.argument("input", type=click.Path(allow_dash=True))
@format_option(FORMATS, None, "lenze-st = IEC 61131-3 text; lenze-bin = packed records; "
               "port-c = C source; markdown, html = documentation of the object dictionary; "
               "canopennode = OD.h and OD.c for CANopenNode v4.", required=True)
@output_option("Default: standard output (lenze-bin not to a terminal). canopennode: the "
               "folder OD.h and OD.c are written to (required; made when missing).")
@node_id_option("lenze-st, lenze-bin, port-c: used for $NODEID values (overrides "
                "[DeviceComissioning] NodeID).")
@click.option("--allow-external-files", is_flag=True,
              help="lenze-st, lenze-bin, port-c: allow DownloadFile paths that are absolute "
                   "or leave the file's folder.")
@click.option("--var-name", default="MasterOD", show_default=True,
              callback=_identifier("an IEC 61131-3"),
              help="lenze-st: name of the ARRAY variable.")
@click.option("--with-type", is_flag=True,
              help="lenze-st: also declare TYPE CanOpenODEntry (when no library provides it).")
@click.option("--include", "includes", multiple=True, callback=_identifier("header"),
              help="port-c: header to #include (repeatable; default co_acces.h).")
@click.option("--symbol", default="objDir", show_default=True, callback=_identifier("a C"),
              help="port-c: name of the LIST_ELEMENT_T array (its length: SYMBOLElements).")
@click.option("--prefix", default="od_", show_default=True, callback=_identifier("a C"),
              help="port-c: prefix of the data variables (od_1018).")
@click.option("--max-object-size", type=Integer(2), metavar="BYTES",
              help="port-c: split ARRAY/RECORD objects with more data bytes than this "
                   "over following indices (the port manual's limit is 255).")
@click.option("--od-name", default="OD", show_default=True, metavar="NAME",
              callback=_identifier("a C"),
              help="canopennode: the object dictionary's name: the files NAME.h and NAME.c "
                   "and the stem of their C names (NAME_RAM, NAME_ENTRY_H1000).")
@quiet_option()
@debug_option
@guarded
@without_cyclic_gc
def export_cmd(input, fmt, output, node_id, allow_external_files, var_name, with_type,
               includes, symbol, prefix, max_object_size, od_name, quiet, debug):
    """Export the object dictionary of a device description for another system, or
    document it.

    \b
    lenze-st     Lenze PLC Designer master OD: ARRAY OF CanOpenODEntry in structured text
    lenze-bin    the same records packed little-endian, 12 bytes each
    port-c       port CANopen Library OD: LIST_ELEMENT_T / VALUE_DESC_T C source
    markdown     documentation: every object with its entries, grouped by area
    html         the same documentation as one HTML page
    canopennode  OD.h and OD.c for CANopenNode v4's object dictionary (-o FOLDER)
    """
    ctx = click.get_current_context()
    from click.core import ParameterSource
    for param, formats in _FORMAT_OPTIONS.items():
        if fmt not in formats and ctx.get_parameter_source(param) is ParameterSource.COMMANDLINE:
            fail(f"{_OPTION_NAMES[param]} applies to --format {' / '.join(formats)} only",
                 code=ExitCode.USAGE)
    if fmt in FOLDER_FORMATS and output == "-":
        fail(f"--format {fmt} writes two files, {od_name}.h and {od_name}.c: give the folder "
             "with -o FOLDER", code=ExitCode.USAGE)
    from dcf2bin.export import run
    data = read_input(input)
    input_kind(input, data, ("dcf", "xdd"), quiet=quiet)
    name = "<stdin>" if input == "-" else input
    res = run(fmt, name, data=data, node_id=node_id, allow_external_files=allow_external_files,
              var_name=var_name, with_type=with_type,
              includes=list(includes) if includes else None, symbol=symbol, prefix=prefix,
              max_object_size=max_object_size, od_name=od_name)
    emit(res.diagnostics, quiet)
    stop_on_errors(res, name, "nothing written")
    if isinstance(res.output, dict):
        _write_files(res.output, output, input)
    else:
        write_output(res.output, output, [input], binary=(fmt == "lenze-bin"))


def _write_files(files: dict, folder: str, input: str) -> None:
    """Each file into ``folder`` (made when missing), through write_output: each one
    atomically, and none before all of them are made. Not yet all or none as a set: a
    disk that fills between the two renames leaves the first new beside the second old
    (fileio.OutputSet of the branch that moves the writing out of cli/common does that)."""
    import os
    if os.path.exists(folder) and not os.path.isdir(folder):
        fail("cannot write: Not a directory", folder, ExitCode.UNREADABLE)
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as exc:
        fail(f"cannot write: {exc.strerror or exc}", folder, ExitCode.UNREADABLE)
    paths = [os.path.join(folder, name) for name in files]
    for path in paths:                  # before the first file: none may be the input
        if input != "-" and os.path.exists(path) and os.path.samefile(path, input):
            fail(f"output '{path}' is the input file; refusing to overwrite it",
                 code=ExitCode.USAGE)
    for path, text in zip(paths, files.values()):
        write_output(text, path, [input], binary=False)

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
                                read_input, registered_inputs, say, stop_on_errors,
                                without_cyclic_gc, write_output)
from dcf2bin.diagnostics import Diagnostic, ExitCode, Severity, shorten

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
            raise click.UsageError(f"{_OPTION_NAMES[param]} applies to --format "
                                   f"{' / '.join(formats)} only", ctx)
    if fmt in FOLDER_FORMATS and output == "-":
        raise click.UsageError(f"--format {fmt} writes two files, {od_name}.h and "
                               f"{od_name}.c: give the folder with -o FOLDER", ctx)
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
        _write_files(res.output, output, quiet)
    else:
        write_output(res.output, output, [input], binary=(fmt == "lenze-bin"))


def _write_files(files: dict, folder: str, quiet: bool) -> None:
    """Each file into ``folder`` (made when missing) as one set (fileio.OutputSet): every
    file written and synced before the first is renamed into place, so that after an
    error or a signal both are new or both as they were -- never a new OD.h beside an old
    OD.c. Without a record (``record=False``): the folder holds the files and nothing else
    of the writer once the set is complete."""
    from dcf2bin.fileio import OutputIsInput, OutputSet, signals

    def waiting() -> None:
        if not quiet:
            say(f"export: waiting for another writer in {folder}")
    outputs = [(name, text.encode("utf-8", "surrogateescape")) for name, text in files.items()]
    try:
        with signals.raising():
            report = OutputSet(folder, outputs, inputs=registered_inputs(), on_wait=waiting,
                               record=False).write()
    except OutputIsInput as exc:
        fail(exc.reason, exc.path, ExitCode.USAGE)
    except OSError as exc:
        fail(f"cannot write: {exc.strerror or exc}", exc.filename or folder,
             ExitCode.UNREADABLE)
    if report.recovered:           # a run stopped by SIGKILL in this folder, undone first
        emit([Diagnostic(Severity.WARNING, report.recovered, folder)], quiet)

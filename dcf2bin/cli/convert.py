"""dcf2bin convert: a device description from one format into another (EDS, DCF, XDD, XDC).

    dcf2bin convert INPUT -o OUTPUT [-f eds|dcf|xdd|xdc] [-n N]

Only click and the shared CLI pieces are imported here; the work (``dcf2bin.formats``)
is imported inside the command, so that ``dcf2bin --help`` stays fast.
"""
from __future__ import annotations

import click

from dcf2bin.cli.common import (CONTEXT, Option, debug_option, emit, guarded, input_kind,
                                node_id_option, output_option, quiet_option, read_input,
                                stop_on_errors, without_cyclic_gc, write_output)
from dcf2bin.diagnostics import shorten

# Kept literally here (module-level imports stay light); tests check it equals
# dcf2bin.formats.TARGETS.
TARGETS = ("eds", "dcf", "xdd", "xdc")


@click.command("convert", context_settings=CONTEXT)
@click.argument("input", type=click.Path(allow_dash=True))
@output_option("Its suffix (.eds, .dcf, .xdd, .xpd, .xdc) names the format unless -f does.",
               default=None)
@click.option("-f", "--format", "--to", "fmt", cls=Option, hidden_names=("--to",),
              type=click.Choice(list(TARGETS)),
              help="Output format: eds, dcf (with the configured values), xdd (CiA 311), "
                   "xdc (CiA 311 with the configured values). Default: by the output's "
                   "suffix.")
@node_id_option("Written as the NodeID of a DCF's [DeviceComissioning] or an XDC's "
                "deviceCommissioning (overrides the input's NodeID, as compile's -n does).")
@quiet_option("Warnings about what the output format cannot say are left out too.")
@debug_option
@guarded
@without_cyclic_gc
def convert_cmd(input, output, fmt, node_id, quiet, debug):
    """Convert a device description between CiA 306 text (EDS, DCF) and CiA 311 XML
    (XDD, XDC).

    Every object, sub-object, type, access, value, limit, PDO mapping flag and ObjFlags
    is kept; what the output format cannot say is a warning naming the object (CNV0xx).

    An input with reading errors is not converted (exit 1): a line that is no key=value,
    a key given twice, an unknown DataType, AccessType or ObjectType, XML that is no CiA
    311 description. What 'dcf2bin validate' checks beyond that (a value out of range for
    its type, a PDO mapping whose sub 0 counts an entry that maps nothing) does not stop
    it: the file is converted as written, values as their text.
    """
    from dcf2bin import formats
    ctx = click.get_current_context()
    if output is None:
        raise click.MissingParameter("Its suffix, or -f, names the format (-o - for "
                                     "standard output).", ctx, _param(ctx, "output"))
    target = fmt or formats.target_of(output)
    if target is None:
        raise click.BadParameter(f"cannot tell the format of '{shorten(output)}' from its "
                                 f"suffix; give -f {'|'.join(TARGETS)}", ctx,
                                 _param(ctx, "output"))
    if node_id is not None and target not in ("dcf", "xdc"):
        raise click.UsageError(f"-n applies to a DCF or an XDC only (the output is "
                               f"{target.upper()}: it holds no configured values)", ctx)
    data = read_input(input)
    input_kind(input, data, ("dcf", "xdd"), quiet=quiet)
    name = "<stdin>" if input == "-" else input
    from dcf2bin.formats.ini_writer import output_name
    res = formats.convert(data, name, target, name=output_name(output), node_id=node_id)
    emit(res.diagnostics, quiet)
    stop_on_errors(res, name, "nothing written")
    write_output(res.data, output, [input], binary=False)


def _param(ctx: click.Context, name: str) -> click.Parameter:
    return next(p for p in ctx.command.params if p.name == name)

"""dcf2bin upload: read a node's configuration back by SDO into a DCF."""
from __future__ import annotations

import sys

import click

from dcf2bin.cli.common import (CONTEXT, COUNT, Failure, Integer, Seconds, check_output,
                                debug_option, emit,
                                fail, guarded, input_kind, node_id_option, output_option,
                                quiet_option, read_input, say, write_output)
from dcf2bin.cli.download import MAX_UPLOAD, bus_options, open_bus
from dcf2bin.diagnostics import Diagnostic, ExitCode, Severity


def upload_options(fn=None, *, network: bool = False):
    """--timeout/--retries/--max-upload/--node-timeout/--keep-going/--network-name, shared
    by upload and network upload (``network=True``: worded for several slaves)."""
    if fn is None:
        return lambda f: upload_options(f, network=network)
    fn = click.option("--network-name", metavar="NAME", callback=_one_line,
                      help="NetworkName in [DeviceComissioning]"
                      + (" of every DCF." if network else "."))(fn)
    keep_going = ("Write the files of the slaves that answered even when a slave failed"
                  if network else "Write the DCF even when an entry failed")
    fn = click.option("--keep-going", is_flag=True,
                      help=f"{keep_going}, each entry not read as a comment (the exit status "
                      "is 1 all the same).")(fn)
    fn = click.option("--node-timeout", type=Seconds(0.001), metavar="SECONDS",
                      help="The most seconds one node's upload may take, all entries "
                      "together (default: the sum of each entry's own bound).")(fn)
    fn = click.option("--max-upload", type=Integer(1), default=MAX_UPLOAD, show_default=True,
                      metavar="BYTES",
                      help="The most bytes an entry without a fixed size (DOMAIN, strings"
                      + ("" if network else ", the stored EDS in 0x1021") + ") may be read "
                      "as; a node that sends more fails.")(fn)
    fn = click.option("--retries", type=COUNT, default=2, show_default=True, metavar="N",
                      help="Times an unanswered SDO request is sent again.")(fn)
    return click.option("--timeout", type=Seconds(0.001), default=1.0,
                        show_default=True, metavar="SECONDS",
                        help="Seconds to wait for each SDO response.")(fn)


def _one_line(ctx, param, value):
    if value is not None and (not value.isprintable() or value != value.strip()):
        raise click.BadParameter("must be one line of printable text without blanks "
                                 "around it", ctx, param)
    return value


@click.command("upload", context_settings=CONTEXT)
@node_id_option("The node to read.", required=True)
@click.option("--eds", type=click.Path(allow_dash=True), metavar="FILE",
              help="The node's EDS, DCF or XDD/XDC: which entries to read and their types "
              "(default: the EDS the node stores in 0x1021).")
@output_option("The DCF.")
@bus_options
@upload_options
@click.option("--node-name", metavar="NAME", callback=_one_line,
              help="NodeName in [DeviceComissioning].")
@quiet_option("No progress bar and no summary line.")
@debug_option
@guarded
def upload_cmd(node_id, eds, output, interface, channel, bitrate, timeout, retries,
               max_upload, node_timeout, keep_going, network_name, node_name, quiet, debug):
    """Read every readable entry of a node by SDO and write a DCF of what it holds.

    Which entries, and how to decode each answer, come from the node's EDS (--eds), or
    else from the EDS the node stores in 0x1021 (0x1022 must say plain text): an SDO
    answer carries no data type. Each value read is a ParameterValue; an entry the node
    refuses, or whose bytes are no value of its type, is a warning and a comment in the
    DCF (the abort code, the raw bytes), never a guessed value. A node that stops
    answering halfway writes nothing (--keep-going: what was read).
    """
    from dcf2bin.bus import link
    from dcf2bin.bus import upload as up
    check_output(output, [eds] if eds else [])
    keys = commissioning(node_name, network_name, bitrate)
    desc = _eds(eds, node_id, quiet) if eds is not None else None
    if desc is not None:
        _check_keys(desc, keys)
    options = up.Options(timeout, retries, max_upload, node_timeout, keep_going)
    net = open_bus(interface, channel, bitrate)
    try:
        desc, result = _read(net, node_id, desc, options, quiet)
    finally:
        link.close_network(net)
    report(result, quiet)
    failed = result.status != up.UPLOADED
    if failed and not keep_going:
        say(f"node {node_id}: {phrase(result)}; nothing written")
        raise Failure(ExitCode.FINDINGS)
    _check_keys(desc, keys)             # a stored EDS is known only now
    text = up.dcf(desc, result, keys)
    write_output(text, output, [eds] if eds else [], binary=False)
    if not quiet:
        say(f"node {node_id}: {phrase(result)}; "
            f"written to {'<stdout>' if output == '-' else output}")
    if failed:
        raise Failure(ExitCode.FINDINGS)


def _check_keys(desc, keys: dict[str, str]) -> None:
    from dcf2bin.bus import upload as up
    try:
        up.check_keys(desc, keys)
    except up.UploadError as exc:
        fail(str(exc), code=ExitCode.USAGE)


def _eds(path: str, node_id: int, quiet: bool):
    from dcf2bin.bus import upload as up
    data = read_input(path)
    name = "<stdin>" if path == "-" else path
    input_kind(path, data, ("dcf", "xdd"), quiet=quiet,
               use="--eds takes the node's EDS, DCF or XDD")
    return described(up.description(data, name, node_id), quiet)


def described(desc, quiet: bool, whose: str = "the EDS"):
    """The description, its errors said in one warning; one without any object ends the
    command (its first error said)."""
    dev = desc.device
    errors = [p.diagnostic for p in dev.problems if p.diagnostic.severity is Severity.ERROR]
    if not any(i >= 0x1000 for i in dev.objects):
        emit(errors[:1])
        fail(f"{whose} lists no object to read", desc.path)
    if errors:
        n = len(errors)
        emit([Diagnostic(Severity.WARNING, f"{whose} has {n} error{'s' if n != 1 else ''} "
                         "(see 'dcf2bin validate'); the entries that could be read are "
                         "uploaded", desc.path)], quiet)
    return desc


def _read(net, node_id: int, desc, options, quiet: bool):
    """The description (given, or read from the node's 0x1021) and the node's values."""
    import time

    from dcf2bin.bus import sdo
    from dcf2bin.bus import upload as up
    deadline = (time.monotonic() + options.node_timeout
                if options.node_timeout is not None else None)
    with sdo.Channel(net, node_id, timeout=options.timeout, retries=options.retries) as ch:
        answered = False
        if desc is None:
            desc = _stored(ch, node_id, options, deadline, quiet)
            answered = True
        todo, infos = up.targets(desc.device, max_upload=options.max_upload)
        emit(infos, quiet)
        kw = dict(encoding=desc.ini.encoding, deadline=deadline, answered=answered)
        if not quiet and sys.stderr.isatty():
            with click.progressbar(length=len(todo), label=f"node {node_id}",
                                   file=sys.stderr) as bar:
                result = up.read_node(ch, todo, options, progress=lambda t: bar.update(1),
                                      **kw)
        else:
            result = up.read_node(ch, todo, options, **kw)
    return desc, result


def _stored(ch, node_id: int, options, deadline, quiet: bool):
    from dcf2bin.bus import sdo
    from dcf2bin.bus import upload as up
    name = f"<node {node_id} 0x1021>"
    try:
        data, warnings = up.stored_eds(ch, options, deadline)
    except up.UploadError as exc:
        fail(str(exc))
    except sdo.SdoError as exc:
        fail(f"{exc} (reading its stored EDS, 0x1021); nothing written")
    emit([Diagnostic(Severity.WARNING, w, name) for w in warnings], quiet)
    from dcf2bin import filekind
    if filekind.detect(data, "") not in ("dcf", "xdd"):
        fail(f"node {node_id}'s 0x1021 holds {len(data)} bytes that are no EDS text",
             name)
    return described(up.description(data, name, node_id), quiet,
                     f"the EDS node {node_id} stores")


def report(result, quiet: bool, label: str = "", where=None) -> None:
    """A warning for each entry the node answered without a value stated, an error for
    each failure, each at the entry's line in the description (a node that did not
    answer at all: at ``where``, when given)."""
    from dcf2bin.bus import upload as up
    lead = f"{label}: " if label else ""
    diags = []
    for n in result.notes:
        if n.kind == up.NOT_READ:
            continue
        severity = Severity.ERROR if n.kind == up.FAILED else Severity.WARNING
        w = where if result.status == up.SILENT and where is not None else n.target.where
        diags.append(Diagnostic(severity, lead + n.message, w.file if w else "dcf2bin",
                                w.line if w else None))
    emit(diags, quiet)


def phrase(result) -> str:
    """How far the upload of a node got, in a few words."""
    from dcf2bin.bus import upload as up
    if result.status == up.SILENT:
        return "did not answer"
    stated = len(result.values)
    parts = [f"{stated} of {result.total} entries read"
             if stated != result.total else f"{stated} entries read"]
    for kind, word in ((up.REFUSED, "refused"), (up.UNFIT, "kept as raw bytes"),
                       (up.FAILED, "failed"), (up.NOT_READ, "not read")):
        n = result.count(kind)
        if n:
            parts.append(f"{n} {word}")
    return ", ".join(parts)


def commissioning(node_name, network_name, bitrate) -> dict[str, str]:
    """The [DeviceComissioning] keys besides NodeID: Baudrate in kbit/s (only a whole
    number of them), NodeName and NetworkName when given."""
    keys = {}
    if node_name is not None:
        keys["NodeName"] = node_name
    if network_name is not None:
        keys["NetworkName"] = network_name
    if bitrate is not None and bitrate % 1000 == 0:
        keys["Baudrate"] = str(bitrate // 1000)
    return keys

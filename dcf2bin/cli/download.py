"""dcf2bin download: write a configuration to a node by SDO (canopen over python-can)."""
from __future__ import annotations

import sys

import click

from dcf2bin.cli.common import (CONTEXT, COUNT, NODE_ID, Failure, Integer, Seconds,
                                check_output, debug_option, decode_concise, decode_container,
                                emit, fail,
                                from_option, guarded, input_kind, node_id_option, quiet_option,
                                read_input, stop_on_errors, write_output)
from dcf2bin.diagnostics import Diagnostic, ExitCode, Severity

MAX_UPLOAD = 1 << 20          # = dcf2bin.bus.sdo.MAX_DOMAIN (not imported: --help stays light)


def bus_options(fn):
    """--interface/--channel/--bitrate, shared by download and node."""
    fn = click.option("--bitrate", type=Integer(1), metavar="BPS",
                      help="Bit rate in bit/s (default: python-can's configuration).")(fn)
    fn = click.option("--channel", metavar="CHANNEL",
                      help="Channel of the interface, e.g. can0, PCAN_USBBUS1, 0, a "
                      "virtual bus name (default: python-can's configuration).")(fn)
    fn = click.option("-i", "--interface", metavar="NAME",
                      help="python-can interface: socketcan, pcan, kvaser, ixxat, vector, "
                      "slcan, virtual, ... (default: python-can's configuration).")(fn)
    return fn


def sdo_options(fn):
    """--timeout/--retries of the SDO client and --max-upload of its read-back, shared by
    download and network download."""
    fn = click.option("--max-upload", type=Integer(1), default=MAX_UPLOAD, show_default=True,
                      metavar="BYTES",
                      help="With --verify: the most bytes an entry without a fixed size "
                      "(DOMAIN, strings) may be read back as; a node that sends more fails.")(fn)
    fn = click.option("--retries", type=COUNT, default=2, show_default=True, metavar="N",
                      help="Times an unanswered SDO request is sent again.")(fn)
    return click.option("--timeout", type=Seconds(0.001), default=1.0,
                        show_default=True, metavar="SECONDS",
                        help="Seconds to wait for each SDO response.")(fn)


def open_bus(interface, channel, bitrate):
    """The network on the bus of --interface/--channel/--bitrate, with the libraries'
    own logging quiet; a bus that cannot be opened is one line and exit 3."""
    from dcf2bin.bus import link
    link.quiet_libraries()
    try:
        return link.open_network(link.BusConfig(interface, channel, bitrate))
    except link.BusError as exc:
        fail(str(exc), code=ExitCode.UNREADABLE)


def _error(message: str, where: str = "dcf2bin") -> None:
    emit([Diagnostic(Severity.ERROR, message, where)])


def _count(n: int, word: str, plural: str | None = None) -> str:
    return f"{n} {word if n == 1 else plural or word + 's'}"


@click.command("download", context_settings=CONTEXT)
@click.argument("input", metavar="FILE", type=click.Path(allow_dash=True))
@node_id_option("The node to configure; also used for $NODEID values.", required=True)
@bus_options
@sdo_options
@from_option(["dcf", "json", "bin", "concise"], "dcf = DCF/EDS, bin = container, concise = "
             "concise DCF, json = lossless dump of either.")
@click.option("--dry-run", is_flag=True, help="Print the SDO writes; touch no bus.")
@click.option("--verify", is_flag=True,
              help="Read back every readable entry written and report each difference.")
@click.option("--keep-going", is_flag=True,
              help="Go on after an SDO abort and report every abort at the end.")
@click.option("--preop", is_flag=True,
              help="Send NMT 'enter pre-operational' to the node before writing.")
@click.option("--save", is_flag=True,
              help="Afterwards write \"save\" to 0x1010 sub 1 (store all parameters).")
@click.option("--reset-comm", is_flag=True,
              help="Afterwards send NMT 'reset communication' to the node.")
@click.option("--concise-dcf-to", "manager", type=NODE_ID, metavar="M",
              help="Write the whole index segment as one DOMAIN into node M's 0x1F22 sub N "
              "(the concise DCF a configuration manager applies) instead of the entries.")
@quiet_option("No progress bar and no summary.")
@debug_option
@guarded
def download_cmd(input, node_id, interface, channel, bitrate, timeout, retries, max_upload,
                 from_, dry_run, verify, keep_going, preop, save, reset_comm, manager, quiet,
                 debug):
    """Write the entries of a DCF/EDS, a container, a concise DCF or their JSON forms to
    a node by SDO.

    The entries are written in container order, exactly as the target would execute
    them (PDO reconfiguration sequences included) -- a concise DCF's in its own order, as a
    CiA 302 configuration manager writes them; each error names the DCF line (or the
    entry's byte offset in the file) it comes from.
    """
    from dcf2bin.bus import download as dl
    check_output("-")           # the summary's way out, before any bus work
    plan = _plan(input, from_, node_id, quiet)
    target = node_id
    if manager is not None:
        plan, target = plan.concise(node_id), manager
    if dry_run:
        write_output("\n".join(dl.render(plan, target)) + "\n", "-", [], binary=False)
        return
    from dcf2bin.bus import link
    net = open_bus(interface, channel, bitrate)
    try:
        _run(net, plan, target, timeout=timeout, retries=retries, verify=verify,
             keep_going=keep_going, preop=preop, save=save, reset_comm=reset_comm,
             max_upload=max_upload, quiet=quiet)
    finally:
        link.close_network(net)


def _plan(input: str, from_: str | None, node_id: int, quiet: bool):
    from dcf2bin.bus import download as dl
    data = read_input(input)
    name = "<stdin>" if input == "-" else input
    fmt = input_kind(input, data, ("dcf", "xdd", "json", "concise-json", "bin", "concise"),
                     from_, quiet=quiet)
    if fmt in ("dcf", "xdd"):
        from dcf2bin.compiler import CompileOptions, compile_path
        res = compile_path(name, CompileOptions(node_id=node_id), data=data)
        emit(res.diagnostics, quiet)
        stop_on_errors(res, name, "nothing sent")
        return dl.plan_from_result(res, name)
    if fmt == "concise":
        return dl.plan_from_concise(decode_concise(data, name, quiet), name)
    text = None
    if fmt in ("json", "concise-json"):
        text = data.decode("utf-8-sig", errors="replace")   # for the line of each entry
        data = _from_json(data, name, quiet)
        if _is_concise(data):     # a concise DCF's JSON form (never a container's bytes)
            return dl.plan_from_concise(decode_concise(data, name, quiet), name, text)
    c = decode_container(data, name, quiet)
    return dl.plan_from_container(c, name, text)


def _from_json(data: bytes, name: str, quiet: bool) -> bytes:
    """The bytes a lossless JSON form records (its errors end the command, exit 1)."""
    from dcf2bin.dump import from_json_bytes
    out, diags = from_json_bytes(data, name)
    emit(diags, quiet)
    if out is None:
        raise Failure(ExitCode.FINDINGS)
    return out


def _is_concise(data: bytes) -> bool:
    from dcf2bin.concise import fills
    return fills(data)


def _run(net, plan, node_id: int, *, timeout, retries, verify, keep_going, preop, save,
         reset_comm, max_upload, quiet) -> None:
    from dcf2bin.bus import download as dl
    total = len(plan.writes)
    if preop:
        dl.nmt(net, node_id, "PRE-OPERATIONAL")
    with dl.sdo_client(net, node_id, timeout=timeout, retries=retries) as ch:
        try:
            ok = _transfers(plan, ch, node_id, verify=verify, keep_going=keep_going,
                            after=save or reset_comm, save=save, max_upload=max_upload,
                            quiet=quiet)
        except dl.Stopped as exc:
            _error(exc.text(total), exc.write.where)
            raise Failure(ExitCode.FINDINGS) from None
    if not ok:
        raise Failure(ExitCode.FINDINGS)
    if reset_comm:
        dl.nmt(net, node_id, "RESET COMMUNICATION")
    if not quiet:
        done = [f"{plan.source}: {_count(total, 'entry', 'entries')} written to node {node_id}"]
        if verify:
            done.append("read back equal")
        if save:
            done.append("saved")
        if reset_comm:
            done.append("communication reset")
        write_output(", ".join(done) + "\n", "-", [], binary=False)


def _transfers(plan, ch, node_id, *, verify, keep_going, after, save, max_upload,
               quiet) -> bool:
    """The writes, the read-back and "save" on one SDO channel; False when the node
    refused one (each abort and difference reported here). A node that stops answering
    as SDO says raises ``Stopped``."""
    from dcf2bin.bus import download as dl
    total = len(plan.writes)
    if not quiet and sys.stderr.isatty():
        with click.progressbar(length=total, label=f"node {node_id}", file=sys.stderr) as bar:
            result = dl.execute(plan, ch, keep_going=keep_going,
                                progress=lambda w: bar.update(1))
    else:
        result = dl.execute(plan, ch, keep_going=keep_going)
    if result.aborts and not keep_going:
        a = result.aborts[0]
        _error(f"{a.write.label}: {a.text}; {a.written_before} of {total} entries written "
               "before it", a.write.where)
        return False
    for a in result.aborts:
        _error(f"{a.write.label}: {a.text}", a.write.where)
    diffs = dl.verify(result.written, ch, max_upload=max_upload) if verify else []
    for d in diffs:
        _error(d.text, d.write.where)
    if result.aborts or diffs:
        parts = [f"{len(result.written)} of {total} entries written"]
        if result.aborts:
            parts.append(_count(len(result.aborts), "SDO abort"))
        if diffs:
            parts.append(_count(len(diffs), "difference") + " on reading back")
        click.echo(f"{plan.source}: " + ", ".join(parts)
                   + ("; not saved, not reset" if after else ""), err=True)
        return False
    if save:
        abort = dl.store(ch, plan.source)
        if abort is not None:
            _error(f"{abort.write.label}: storing the parameters: {abort.text}", plan.source)
            return False
    return True

"""dcf2bin network upload: read every slave of a network back by SDO, one DCF each."""
from __future__ import annotations

import os

import click

from dcf2bin.cli.common import (CONTEXT, Failure, Integer, debug_option, emit, fail, guarded,
                                quiet_option, register_input, rule_options, say)
from dcf2bin.cli.download import bus_options, open_bus
from dcf2bin.cli.network.scan import GOING_ON
from dcf2bin.cli.network.show import check_rules, configured_network, net_option
from dcf2bin.cli.upload import commissioning, phrase, report, upload_options
from dcf2bin.diagnostics import Diagnostics, ExitCode

PLC_LINE = "not read (a PLC: its configuration goes with the PLC program)"


@click.command("upload", context_settings=CONTEXT)
@click.argument("network_file", metavar="NETWORK", type=click.Path())
@click.option("-o", "--output", required=True, metavar="DIR", type=click.Path(),
              help="Output folder (made when missing): one <slave>.dcf per slave, named as "
              "network build names them; every file is written, or none.")
@bus_options
@upload_options(network=True)
@click.option("-j", "--jobs", type=Integer(1), default=4, show_default=True, metavar="N",
              help="Read up to N slaves at a time, each with one SDO request in flight "
              "(1: one after the other).")
@net_option
@rule_options
@quiet_option("No progress lines and no summary.")
@debug_option
@guarded
def upload_cmd(network_file, output, interface, channel, bitrate, timeout, retries,
               max_upload, node_timeout, keep_going, network_name, jobs, net, select_, ignore,
               strict, quiet, debug):
    """Read every slave of a network back by SDO, each into <slave>.dcf in DIR.

    Each slave is read as 'dcf2bin upload' reads a node, with its file (dcf:) as its EDS:
    every readable entry becomes a ParameterValue of that file, [DeviceComissioning]
    gets its NodeID and NodeName. The files are named as 'network build' names its
    slaves' DCFs, so that the two folders compare file by file. One progress line per
    slave in node-ID order, then a summary row for each: uploaded, failed (the entry and
    the reason) or did not answer. The files are written only when every slave was read
    (--keep-going: those that were, each entry not read as a comment).

    The network's findings are those of 'network check' (validate's warnings about the
    node files left out), with --select/--ignore as there, and decide the exit status as
    there (--strict: warnings too); only those that make the upload unsound stop it
    before the bus (nothing read), whatever --ignore says: an error of the network file,
    a node-ID given twice, a node's file that cannot be read (NET0xx, NET200, NET201,
    DCF0xx-DCF3xx). The PDO plan and the configuration (NET1xx, NET2xx) do not stop it.
    """
    from dcf2bin.bus import link
    from dcf2bin.bus import upload as up
    from dcf2bin.network.check import NODES
    check_rules(select_, ignore)
    network, verdict = configured_network(
        network_file, quiet, "nothing read", net, select=select_, ignore=ignore,
        strict=strict, need=NODES, going_on=GOING_ON.format(
            command="upload", done="the slaves are read back"))
    if os.path.exists(output) and not os.path.isdir(output):
        fail("cannot write: Not a directory", output, ExitCode.UNREADABLE)
    work, plcs = _jobs(network, output, max_upload, quiet)
    for job in work:
        try:
            up.check_keys(job.desc, commissioning(job.name, network_name, bitrate))
        except up.UploadError as exc:
            fail(f"{job.label}: {exc}", str(job.where or network_file))
    inputs = [network_file] + sorted({j.desc.path for j in work})
    for path in inputs:
        register_input(path)            # no output may overwrite a node's file
    _refuse_inputs(output, [j.output for j in work], inputs)
    options = up.Options(timeout, retries, max_upload, node_timeout, keep_going)

    def progress(job, result) -> None:
        report(result, quiet, job.label, job.where)
        if not quiet:
            click.echo(f"{job.label}: {phrase(result)}")

    if not quiet:
        for n in plcs:
            click.echo(f"node {n.node_id} ({n.name}): {PLC_LINE}")
    bus = open_bus(interface, channel, bitrate)
    try:
        results = up.read_nodes(bus, work, options, parallel=jobs, on_node=progress)
    finally:
        link.close_network(bus)
    if not quiet:
        click.echo(_summary(network_file, work, results, plcs), nl=False)
    failed = sum(r.status != up.UPLOADED for r in results)
    if failed and not keep_going:
        say(f"{network_file}: {failed} slave{'s' if failed != 1 else ''} not uploaded, "
            "nothing written (--keep-going writes what was read)")
        raise Failure(ExitCode.FINDINGS)
    files = {}
    for job, r in zip(work, results):
        if r.status == up.SILENT:
            continue
        files[job.output] = up.dcf(job.desc, r, commissioning(job.name, network_name,
                                                              bitrate))
    write_files(output, files, inputs)
    if not quiet:
        say(f"network upload: {len(files)} file{'s' if len(files) != 1 else ''} in {output}")
    if failed:
        raise Failure(ExitCode.FINDINGS)
    if verdict != ExitCode.OK:              # the network's own findings (said before)
        raise Failure(verdict)


def _jobs(network, output: str, max_upload: int, quiet: bool):
    """Each slave to read (node-ID order), with its output name; the PLCs of a .cpj
    project, which are not read. A file several slaves share is spoken of once."""
    from dcf2bin.bus import upload as up
    from dcf2bin.bus.netconf import is_plc
    from dcf2bin.network.build import output_names
    from dcf2bin.network.files import cia306
    diags = Diagnostics()
    names = output_names(network, diags)
    if names is None:
        emit(diags)
        fail(f"{network.path}: nothing read")
    work, plcs, said = [], [], set()
    for n in sorted(network.slaves, key=lambda n: n.node_id):
        if is_plc(n):
            plcs.append(n)
            continue
        dev = n.device
        text, parsed = cia306(network, dev)       # an XDD/XDC: its sections as CiA 306 text
        desc = up.Description(dev, text, parsed, dev.path, n.node_id)
        todo, infos = up.targets(dev, max_upload=max_upload)
        if dev.path not in said:
            emit(infos, quiet)
            said.add(dev.path)
        work.append(up.Job(desc, todo, f"node {n.node_id} ({n.name})", n.name,
                           names[n.name] + ".dcf", n.where))
    return work, plcs


def _refuse_inputs(folder: str, names: list[str], inputs: list[str]) -> None:
    """Before the bus is touched: every output can be written and none is an input (the
    checks of the writer, fileio.OutputSet, made first)."""
    from dcf2bin.fileio import OutputIsInput, OutputSet
    try:
        OutputSet(folder, [(name, b"") for name in names], inputs=inputs).check()
    except OutputIsInput as exc:
        fail(exc.reason, exc.path, ExitCode.USAGE)
    except OSError as exc:
        fail(f"cannot write: {exc.strerror or exc}", exc.filename or folder,
             ExitCode.UNREADABLE)


def write_files(folder: str, files: dict[str, bytes], inputs: list[str]) -> None:
    """Write every file of ``files`` (name -> bytes) in ``folder`` (made when missing), all
    or none (fileio.OutputSet: temporaries renamed only when all are complete, rolled back
    on an error or a signal): the one place a network upload's outputs are written."""
    from dcf2bin.fileio import OutputIsInput, OutputSet, signals
    try:
        with signals.raising():
            OutputSet(folder, files.items(), inputs=inputs).write()
    except OutputIsInput as exc:
        fail(exc.reason, exc.path, ExitCode.USAGE)
    except OSError as exc:
        fail(f"cannot write: {exc.strerror or exc}", exc.filename or folder,
             ExitCode.UNREADABLE)


def _summary(path: str, work, results, plcs) -> str:
    from dcf2bin.bus import upload as up
    counts = {s: sum(r.status == s for r in results)
              for s in (up.UPLOADED, up.FAILED, up.SILENT)}
    out = [f"{path}: {counts[up.UPLOADED]} uploaded, {counts[up.FAILED]} failed, "
           f"{counts[up.SILENT]} did not answer"
           + (f", {len(plcs)} not read (PLC)" if plcs else "")]
    rows = [(n.node_id, "not read", f"node {n.node_id} ({n.name})",
             "a PLC: its configuration goes with the PLC program") for n in plcs]
    for job, r in zip(work, results):
        why = phrase(r) if r.status == up.UPLOADED else r.failures[0].text
        rows.append((job.node_id, r.status, job.label, why))
    width = max((len(s) for _, s, _, _ in rows), default=0)
    out += [f"  {s:<{width}}  {lab}  {why}" for _, s, lab, why in sorted(rows)]
    return "\n".join(out) + "\n"

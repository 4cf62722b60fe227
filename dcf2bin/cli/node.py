"""dcf2bin node: a software CANopen node on a python-can bus (canopen.LocalNode),
built from an EDS/DCF, or an emulated SYS TEC target built from a container."""
from __future__ import annotations

import time

import click

from dcf2bin import argspec
from dcf2bin.cli.common import (CONTEXT, COUNT, Choice, Failure, Integer, debug_option, emit,
                                fail, guarded, input_kind, load_static_od, node_id_option,
                                quiet_option, read_input, static_od_option,
                                target_stack_options, verbose_option)
from dcf2bin.cli.download import bus_options, open_bus
from dcf2bin.diagnostics import Diagnostic, ExitCode, Severity


@click.command("node", context_settings=CONTEXT)
@click.argument("input", metavar="[FILE]", required=False,
                type=click.Path(allow_dash=True))
@node_id_option("The node's own (default: NodeID in [DeviceComissioning] of FILE).")
@bus_options
@click.option("--container", type=click.Path(allow_dash=True),
              metavar="FILE.bin", help="Be an emulated SYS TEC target: build the object "
              "dictionary and process image the way DynBuildOd builds them from this "
              "container.")
@static_od_option("With --container only. Without it, what the container never writes is "
                  "not checked (a warning says so).")
@click.option("--pi-size", type=COUNT, metavar="N",
              help="With --container: PI memory of the target in bytes (default: the "
              "complete size the container gives).")
@target_stack_options(prefix="With --container: ")
@click.option("--address-base", type=Choice(argspec.ADDRESS_BASE), default="image",
              show_default=True, help="With --container: PI addresses count from the image "
              "start or from their area.")
@click.option("--show-pi", is_flag=True,
              help="With --container: print the process image whenever an RPDO changes it.")
@click.option("--operational", is_flag=True,
              help="Enter OPERATIONAL at once instead of waiting for an NMT start.")
@click.option("--duration", type=click.FloatRange(0), metavar="SECONDS",
              help="Stop after this many seconds (default: run until Ctrl-C).")
@click.option("--serial", type=Integer(0, 0xFFFFFFFF), metavar="N",
              help="The node's serial number: 0x1018 sub 4 and the last part of the "
              "identity LSS finds it by (default: its 0x1018 sub 4, else 0).")
@click.option("--lss-unconfigured", is_flag=True,
              help="Start without a node-ID (0xFF): answer LSS only -- no SDO, no boot-up, "
              "no heartbeat -- until LSS gives one (--node-id, default 1, then only "
              "resolves the file's $NODEID values).")
@quiet_option()
@verbose_option("NMT state changes and PDOs that cannot be used.")
@debug_option
@guarded
def node_cmd(input, node_id, interface, channel, bitrate, container, static_od, pi_size,
             tx_cobs, rx_cobs, granularity, no_bit_mapping, address_base, show_pi,
             operational, duration, serial, lss_unconfigured, quiet, verbose, debug):
    """Run a CANopen node on the bus until Ctrl-C: SDO server, NMT, heartbeat and PDOs.

    From an EDS/DCF FILE the node has that file's objects and values. With --container
    it is an emulated SYS TEC target: the container is applied as DynBuildOd applies it
    (the node does not start when that fails), the network variables live in a process
    image at their PI addresses, and PDOs move them on and off the bus.

    The node answers LSS (CiA 305) with the identity of its 0x1018 (vendor-ID, product
    code and revision; else its file's [DeviceInfo]) and --serial.
    """
    from dcf2bin.bus import link
    if (input is None) == (container is None):
        fail("give an EDS/DCF FILE or --container FILE.bin (one of them)",
             code=ExitCode.USAGE)
    target_only = {"--static-od": static_od, "--pi-size": pi_size, "--tx-cobs": tx_cobs,
                   "--rx-cobs": rx_cobs, "--show-pi": show_pi or None,
                   "--no-bit-mapping": no_bit_mapping or None}
    for opt, value in target_only.items():
        if value is not None and container is None:
            fail(f"{opt} needs --container", code=ExitCode.USAGE)
    if container is not None:
        if node_id is None:
            fail("--container needs --node-id N (a container has no node-ID)",
                 code=ExitCode.USAGE)
        node, name = _target(container, node_id, static_od, pi_size, tx_cobs, rx_cobs,
                             int(granularity), not no_bit_mapping, address_base, quiet)
    else:
        if lss_unconfigured and node_id is None:
            node_id = 1
        node, name = _from_file(input, node_id, quiet)
    _answer_lss(node, serial, lss_unconfigured, input)
    if show_pi:
        node.on_image_change = lambda image: click.echo(
            "\n".join([f"node {node.id}: process image ({len(image.data)} bytes)"]
                      + image.lines()))
    if verbose:
        node.on_event = lambda text: click.echo(f"node {node.id}: {text}", err=True)
        node.lss.on_event = node.on_event
    net = open_bus(interface, channel, bitrate)
    try:
        node.attach(net, operational=operational)
        if not quiet:
            who = (f"node {node.id}" if node.lss.configured else
                   f"node without a node-ID (LSS serial 0x{node.lss.identity.serial:08X})")
            where = link.BusConfig(interface, channel, bitrate).describe()
            if link.is_virtual(net):
                where += ": python-can's virtual bus reaches only this process"
            click.echo(f"{name}: {who} on the bus ({where}); Ctrl-C stops it", err=True)
        _wait(duration)
    except KeyboardInterrupt:
        pass          # Ctrl-C is how a node is meant to stop: exit 0
    finally:
        node.detach()
        link.close_network(net)
    if not quiet:
        click.echo(f"{name}: node {node.id} stopped", err=True)


def _answer_lss(node, serial: int | None, unconfigured: bool, path: str | None) -> None:
    """The node answers LSS: its identity from 0x1018 (else the file's [DeviceInfo]) and
    --serial."""
    from dcf2bin.bus import lss_slave
    lss_slave.attach_lss(node, serial=serial, unconfigured=unconfigured,
                         info_from=None if path in (None, "-") else path)


def _wait(duration: float | None) -> None:
    end = None if duration is None else time.monotonic() + duration
    while end is None or time.monotonic() < end:
        time.sleep(0.1 if end is None else max(0.0, min(0.1, end - time.monotonic())))


def _from_file(path: str, node_id: int | None, quiet: bool):
    from dcf2bin.bus import node as nodemod
    data = read_input(path)
    name = "<stdin>" if path == "-" else path
    run_it = f"run it with dcf2bin node --container {name} --node-id N"
    input_kind(path, data, ("dcf", "xdd"), quiet=quiet, use={"bin": run_it, "json": run_it})
    try:
        node, errors = nodemod.from_file(name, node_id, data=data)
    except nodemod.NodeError as exc:
        fail(str(exc), name)
    if errors:
        n, first = len(errors), errors[0]
        emit([Diagnostic(Severity.WARNING, f"the file has {n} error{'s' if n != 1 else ''}, "
                         f"the first here (see 'dcf2bin validate'); the node has the objects "
                         "that could be read", first.file or name, first.line,
                         rule=nodemod.FILE_ERRORS)], quiet)
    emit(node.warnings, quiet)
    return node, name


def _target(path, node_id, static_od, pi_size, tx_cobs, rx_cobs, granularity,
            bit_mapping, address_base, quiet):
    from dcf2bin.bus import node as nodemod
    from dcf2bin.cli.common import read_container
    from dcf2bin.dynod import StaticOD, TargetOptions, emulate
    c, name = read_container(path, quiet, json_ok=True)
    raw = load_static_od(static_od, quiet, "the node does not start")
    static = None if raw is None else StaticOD.from_eds(static_od, raw)
    opts = TargetOptions(pi_size=pi_size, tx_cobs=tx_cobs, rx_cobs=rx_cobs,
                         granularity=granularity, bit_mapping=bit_mapping,
                         address_base=address_base)
    outcome = emulate(c, opts, static=static)
    # what was not checked without --static-od: the same warnings as simulate's
    emit([Diagnostic(Severity.WARNING, w.message, name, rule=w.rule) for w in outcome.warnings],
         quiet)
    if not outcome.ok:
        where = name if outcome.offset is None else f"{name}:0x{outcome.offset:X}"
        entry = f"{outcome.label}: " if outcome.label else ""
        emit([Diagnostic(Severity.ERROR, f"{entry}DynBuildOd returns 0x{outcome.code:02X} "
                         f"{outcome.name}: {outcome.reason}; the node does not start",
                         where)])
        raise Failure(ExitCode.FINDINGS)
    try:
        return nodemod.from_outcome(outcome, node_id, pi_size), name
    except nodemod.NodeError as exc:
        fail(str(exc), name)

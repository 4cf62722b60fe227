"""dcf2bin network build: the PLC's DCF and each slave's configuration from a network
file (README "Networks", man/dcf2bin-network-build.1)."""
from __future__ import annotations

import os

import click

from dcf2bin.cli.common import (CONTEXT, Failure, debug_option, emit, fail, guarded, quiet_option,
                                read_input, register_input, say, stop_on_errors,
                                verbose_option, write_output)
from dcf2bin.diagnostics import ExitCode, Severity


@click.command("build", context_settings=CONTEXT)
@click.argument("network", metavar="NETWORK.yml", type=click.Path())
@click.option("-o", "--output", "output", required=True, metavar="DIR", type=click.Path(),
              help="Output folder (made when missing); its files are written atomically, "
                   "never over an input.")
@click.option("--master", "master_kind", type=click.Choice(["plc", "lely"]), default=None,
              help="The kind of master to build: plc (the master's dcf: is the PLC's file) "
                   "or lely (master.dcf as lely's dcfgen -r writes it). Default: plc when "
                   "the master has dcf:, else lely.")
@verbose_option("every link and every PLC variable, on standard error.")
@quiet_option()
@debug_option
@guarded
def build_cmd(network, output, master_kind, verbose, quiet, debug):
    """Configure the network of NETWORK.yml and write, in DIR, the master's DCF
    (<master>.dcf) and per slave its concise DCF (<slave>.bin).

    A PLC master (one with dcf:) mirrors every slave PDO that exists, its network
    variables are placed as 'allocate --into' places them, it gets its NMT master
    entries, and each slave also gets its DCF (<slave>.dcf). A lely master (one without
    dcf:) gets the master.dcf, and master.bin, that lely's 'dcfgen -r' writes. COB-IDs
    marked auto are assigned. Nothing is written when there is an error.
    """
    from dcf2bin.network import build_network
    data = read_input(network)
    if os.path.exists(output) and not os.path.isdir(output):
        fail("cannot write: Not a directory", output, ExitCode.UNREADABLE)
    res = build_network(network, data=data, master=master_kind)
    emit(res.diagnostics, quiet)
    try:
        stop_on_errors(res, "network build", "nothing written")
    except Failure:
        from dcf2bin.cli.network.show import exit_code
        raise Failure(exit_code(d for d in res.diagnostics if d.severity is Severity.ERROR))
    net = res.network
    for path in sorted({n.device.path for n in net.nodes if n.device is not None}):
        register_input(path)        # no output may overwrite a node's file
    try:
        os.makedirs(output, exist_ok=True)
    except OSError as exc:
        fail(f"cannot write: {exc.strerror or exc}", output, ExitCode.UNREADABLE)
    for name, blob in res.outputs.items():
        write_output(blob, os.path.join(output, name), [network], binary=True)
    if verbose and not quiet:
        for line in describe(net):
            say(line)
    if not quiet:
        slaves = len(net.slaves)
        links = sum(1 for p in net.master.pdos if p.mirror_of)
        files = f"network build: {len(res.outputs)} files in {output}: {net.master.name}.dcf"
        if res.mode == "lely":
            own = f"{net.master.name}.bin"
            say(f"{files}{', ' + own if own in res.outputs else ''} and {slaves} "
                f"slave{'s' if slaves != 1 else ''} for a lely master, {links} links")
        else:
            say(f"{files} and {slaves} slave{'s' if slaves != 1 else ''} for a PLC master, "
                f"{links} links, {len(net.variables)} variables")


def describe(net) -> list[str]:
    """-v: every link (the PLC PDO, its COB-ID, the slave PDO it mirrors) and every PLC
    variable (its object, where it comes from, its offset)."""
    import dcf2bin.datatypes as dt
    out = []
    names = {n.node_id: n.name for n in net.nodes}
    for p in net.master.pdos:
        src = p.mirror_of
        if src is None:
            continue
        out.append(f"link {p.label} COB-ID 0x{p.cob_id:03X}: {names[src.node_id]} "
                   f"{src.label}, {p.bits} bits")
    for v in net.variables:
        place = (f"0x{v.pi_index:04X}sub{v.pi_sub:X}" if v.pi_index is not None else "-")
        offset = f" offset {v.pi_offset}" if v.pi_offset is not None else ""
        dtype = dt.BY_CODE.get(v.datatype)
        out.append(f"variable {v.name}: {place}, {dtype.name if dtype else v.datatype} "
                   f"{v.direction}{offset}, from {names[v.node_id]} "
                   f"0x{v.index:04X}sub{v.sub:X}")
    return out

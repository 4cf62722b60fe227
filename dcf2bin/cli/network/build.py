"""dcf2bin network build: the PLC's DCF and each slave's configuration from a network
file (docs/network.md, man/dcf2bin-network-build.1)."""
from __future__ import annotations

import click

from dcf2bin.cli.common import (CONTEXT, Failure, OutputPath, debug_option, emit, fail, guarded,
                                quiet_option, register_input, registered_inputs,
                                rule_options, say, verbose_option)
from dcf2bin.cli.network.show import master_option
from dcf2bin.diagnostics import Diagnostic, ExitCode, Severity


@click.command("build", context_settings=CONTEXT)
@click.argument("network", metavar="NETWORK.yml", type=click.Path())
@click.option("-o", "--output", "output", required=True, metavar="DIR",
              type=OutputPath(), help="Output folder (made when missing); its files are "
              "written all or none, never over an input.")
@master_option
@rule_options
@verbose_option("every link and every PLC variable, on standard error.")
@quiet_option()
@debug_option
@guarded
def build_cmd(network, output, master_kind, select_, ignore, strict, verbose, quiet, debug):
    """Configure the network of NETWORK.yml and write, in DIR, the master's DCF
    (<master>.dcf) and per slave its concise DCF (<slave>.bin).

    A PLC master (one with dcf:) mirrors every slave PDO that exists, its network
    variables are placed as 'allocate --into' places them, it gets its NMT master
    entries, and each slave also gets its DCF (<slave>.dcf). A lely master (one without
    dcf:) gets the master.dcf, and master.bin, that lely's 'dcfgen -r' writes. COB-IDs
    marked auto are assigned. The findings are those of 'network check' (validate's
    warnings about the node files left out): nothing is written when there is an error.
    --ignore cannot leave out an error of the network file, of the configuration or of
    reading a node's file, nor a node-ID given twice (NET0xx, NET1xx, NET200, NET201,
    DCF0xx-DCF3xx). NETWORK is YAML (a .cpj project has nothing to build).

    The files are written all or none: nothing is written when there is an error, and
    an error, Ctrl-C or SIGTERM while they are written leaves the folder as it was.
    """
    from dcf2bin.cli.network.show import (check_rules, counts, exit_code, failing,
                                          read_network_file)
    from dcf2bin.network import build_network
    check_rules(select_, ignore)
    data = read_network_file(network)       # unreadable: IO001, as check says it
    _check_folder(output)
    res = build_network(network, data=data, master=master_kind, select=select_,
                        ignore=ignore)
    emit(res.diagnostics, quiet)
    bad = failing(res.diagnostics, strict)
    if bad:
        click.echo(f"network build: {counts(bad)}, nothing written", err=True)
        raise Failure(exit_code(bad))
    net = res.network
    for path in sorted({n.device.path for n in net.nodes if n.device is not None}):
        register_input(path)        # no output may overwrite a node's file
    report = _write(output, res.outputs, quiet)
    from dcf2bin.network.build import write_warnings
    from dcf2bin.network.check import resolve
    active = resolve(select_, ignore)       # (the files are written: --strict cannot stop it)
    emit([d for d in write_warnings(report, output) if d.rule in active], quiet)
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


def _check_folder(output: str) -> None:
    """-o is a folder, or nothing yet: a file there is exit 3 before any work."""
    import os
    if os.path.exists(output) and not os.path.isdir(output):
        fail("cannot write: Not a directory", output, ExitCode.UNREADABLE)


def _write(output: str, outputs: dict[str, bytes], quiet: bool):
    """Every output, all or none (fileio.OutputSet); a problem with any of them is one
    line naming that file and exit 2 (over an input) or 3, with nothing written."""
    from dcf2bin.fileio import OutputIsInput, OutputSet, signals
    from dcf2bin.network.build import write_all

    def waiting() -> None:
        if not quiet:
            say(f"network build: waiting for another build writing in {output}")
    try:
        OutputSet(output, outputs.items(), inputs=registered_inputs()).check()
        with signals.raising():
            return write_all(output, outputs, registered_inputs(), on_wait=waiting)
    except OutputIsInput as exc:
        emit([Diagnostic(Severity.ERROR, exc.reason, exc.path)])
        code = ExitCode.USAGE
    except OSError as exc:
        emit([Diagnostic(Severity.ERROR, f"cannot write: {exc.strerror or exc}",
                         exc.filename or output)])
        code = ExitCode.UNREADABLE
    say(f"network build: nothing written (the files in {output} are as they were)")
    raise Failure(code)


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

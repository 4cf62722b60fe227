"""dcf2bin network download: configure every slave of a network by SDO."""
from __future__ import annotations

import click

from dcf2bin.cli.common import (CONTEXT, Failure, check_output, debug_option, emit, guarded,
                                quiet_option, rule_options, write_output)
from dcf2bin.cli.download import bus_options, open_bus, sdo_options
from dcf2bin.cli.network.show import check_rules, configured_network, net_option
from dcf2bin.diagnostics import Diagnostic, ExitCode, Severity


@click.command("download", context_settings=CONTEXT)
@click.argument("network_file", metavar="NETWORK", type=click.Path())
@bus_options
@sdo_options
@click.option("--dry-run", is_flag=True,
              help="Print each slave's identity check and SDO writes; touch no bus.")
@click.option("--verify", is_flag=True,
              help="Read back every readable entry written and report each difference.")
@click.option("--keep-going", is_flag=True,
              help="Go on after an SDO abort or a node that fails (the next entries, the "
              "next nodes) and report every failure at the end.")
@click.option("--save", is_flag=True,
              help="After a slave is configured, write \"save\" to its 0x1010 sub 1 (store "
              "all parameters).")
@net_option
@rule_options
@quiet_option("No progress lines and no summary.")
@debug_option
@guarded
def download_cmd(network_file, interface, channel, bitrate, timeout, retries, max_upload,
                 dry_run, verify, keep_going, save, net, select_, ignore, strict, quiet,
                 debug):
    """Configure every slave of a network by SDO, in node-ID order.

    Each slave's identity is checked first: its device type (0x1000) and 0x1018 sub 1...4
    are read and compared with what the master will enforce (0x1F84...0x1F88); a slave
    the master would refuse is an error, and nothing is written to it. Then its
    configuration is written: its PDOs (each disabled while it is changed), heartbeat and
    guarding entries and the `sdo` list of the network file, in that order. The master
    (the PLC) is not written: its container goes with the PLC program. One progress line
    per slave; a summary names every slave configured, failed or skipped.

    A .cpj project has no master: each node's DCF is written as `download` writes it,
    after the check of the identity its DCF states; a PLC (a file with network variables)
    is not written.

    The findings are those of 'network check' (validate's warnings about the node files
    left out), with --select/--ignore as there: an error, or with --strict a warning,
    sends nothing. --ignore cannot leave out an error of the network file, of the
    configuration or of reading a node's file (NET0xx, NET1xx, NET200, NET201,
    DCF0xx-DCF3xx).
    """
    from dcf2bin.bus import netconf
    check_rules(select_, ignore)
    check_output("-")           # the summary's way out, before any bus work
    network, _ = configured_network(network_file, quiet, "nothing sent", net,
                                    select=select_, ignore=ignore, strict=strict)
    plans = _plans(network, network_file, quiet)
    if dry_run:
        write_output(_dry(network, plans), "-", [], binary=False)
        return
    from dcf2bin.bus import link
    bus = open_bus(interface, channel, bitrate)
    options = netconf.Options(timeout, retries, verify, keep_going, save, max_upload)

    def progress(out: netconf.Outcome) -> None:
        emit([Diagnostic(Severity.ERROR, f"{out.label}: {p.message}", p.where or network_file)
              for p in out.problems])
        if not quiet:
            click.echo(_line(out))

    try:
        from dcf2bin.network.show import identity_of
        identities = {n.node_id: identity_of(network, n) for n in network.slaves}
        outcomes = netconf.configure_slaves(bus, network, options, source=network_file,
                                            plans=plans, identities=identities,
                                            from_file=network.kind == "cpj",
                                            progress=progress)
    finally:
        link.close_network(bus)
    if not quiet:
        write_output(_summary(network_file, outcomes, keep_going), "-", [], binary=False)
    if any(o.status in (netconf.FAILED, netconf.SKIPPED) for o in outcomes):
        raise Failure(ExitCode.FINDINGS)


def _plans(network, source: str, quiet: bool) -> dict:
    """Each node's writes by node-ID: a YAML network's slaves their D-18 lists; a .cpj
    project's nodes their DCFs compiled (a PLC has none; a DCF with errors ends the run
    before anything is sent)."""
    from dcf2bin.bus import netconf
    slaves = sorted(network.slaves, key=lambda n: n.node_id)
    if network.kind != "cpj":
        return {n.node_id: netconf.plan_of(n, source) for n in slaves}
    plans, errors = {}, 0
    for n in slaves:
        if netconf.is_plc(n):
            continue
        plan, diags = netconf.cpj_plan(n)
        emit(diags, quiet)
        if plan is None:
            errors += sum(d.severity is Severity.ERROR for d in diags)
        else:
            plans[n.node_id] = plan
    if errors:
        click.echo(f"{source}: {errors} error{'s' if errors != 1 else ''}, nothing sent",
                   err=True)
        raise Failure(ExitCode.FINDINGS)
    return plans


def _count(n: int, word: str, plural: str) -> str:
    return f"{n} {word if n == 1 else plural}"


def _line(out) -> str:
    from dcf2bin.bus import netconf
    if out.status == netconf.PLC:
        return f"{out.label}: not written (a PLC: its container goes with the PLC program)"
    if out.status == netconf.CONFIGURED:
        done = [f"{_count(out.total, 'entry', 'entries')} written"]
        if out.verified:
            done.append("read back equal")
        if out.saved:
            done.append("saved")
        return f"{out.label}: identity checked, " + ", ".join(done)
    if out.written == 0 and not out.aborts:
        return f"{out.label}: failed, nothing written"
    return f"{out.label}: failed, {out.written} of {out.total} entries written"


def _summary(path: str, outcomes, keep_going: bool) -> str:
    from dcf2bin.bus import netconf
    counts = {s: sum(o.status == s for o in outcomes)
              for s in (netconf.CONFIGURED, netconf.FAILED, netconf.SKIPPED, netconf.PLC)}
    out = [f"{path}: {counts['configured']} configured, {counts['failed']} failed, "
           f"{counts['skipped']} skipped"
           + (f", {counts[netconf.PLC]} not written (PLC)" if counts[netconf.PLC] else "")]
    for o in outcomes:
        if o.status == netconf.CONFIGURED:
            why = _count(o.total, "entry", "entries")
        elif o.status == netconf.FAILED:
            why = "; ".join(p.message for p in o.problems)
        elif o.status == netconf.PLC:
            why = "a PLC: its container goes with the PLC program"
        else:
            why = "not written: an earlier node failed (--keep-going goes on)"
        out.append(f"  {o.status:<10}  {o.label}  {why}")
    return "\n".join(out) + "\n"


def _dry(network, plans: dict) -> str:
    from dcf2bin.bus.scan import ENFORCED
    from dcf2bin.network import show
    from dcf2bin.network.show import identity_of
    out = []
    for n in sorted(network.slaves, key=lambda n: n.node_id):
        if n.node_id not in plans:
            out.append(f"node {n.node_id} ({n.name}): not written (a PLC: its container goes "
                       "with the PLC program)")
            continue
        plan = plans[n.node_id]
        checks = [f"0x{ENFORCED[k][0]:04X}"
                  + (f" sub {ENFORCED[k][1]}" if ENFORCED[k][0] != 0x1000 else "")
                  + f" = 0x{v:08X}" for k, v in sorted(identity_of(network, n).items())]
        out.append(f"node {n.node_id} ({n.name}): "
                   + (f"checks {', '.join(checks)}; " if checks else "no identity check; ")
                   + f"{_count(len(plan.writes), 'SDO write', 'SDO writes')} (dry run, "
                   "nothing sent)")
        named = {k: w for k, w in enumerate(n.writes)} if network.kind != "cpj" else {}
        rows = []
        for k, w in enumerate(plan.writes):
            m = named.get(k)
            value = (show.value_text(show.WriteRow(m.index, m.sub, m.name, m.value, m.data,
                                                   m.why, "")) if m is not None else "")
            rows.append([str(k + 1), w.label, w.data.hex(" ").upper() or "(0 bytes)", value,
                         m.name if m is not None else "", m.why if m is not None else "",
                         w.where])
        out += ["  " + line for line in
                show.table(["#", "entry", "data", "value", "name", "why", "source"], rows)]
    return "\n".join(out) + "\n"

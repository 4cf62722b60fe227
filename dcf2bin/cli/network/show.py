"""dcf2bin network show: the links of a network as text, JSON, an SVG picture, HTML or a
CAN database (DBC)."""
from __future__ import annotations

import click

from dcf2bin import argspec
from dcf2bin.cli.common import (CONTEXT, Failure, Integer, debug_option, emit, fail,
                                format_option, guarded, output_option, quiet_option,
                                read_input, register_input, rule_options, say, write_output)
from dcf2bin.diagnostics import ExitCode, Severity


def check_rules(select_, ignore) -> None:
    """--select/--ignore as network check reads them: a selector that names no rule is a
    usage error, before anything is read."""
    from dcf2bin.network.check import SelectorError, resolve
    try:
        resolve(select_, ignore)
    except SelectorError as exc:
        raise click.BadParameter(str(exc), param_hint="'--select' / '--ignore'")


def read_network_file(path: str) -> bytes:
    """The network file's bytes (the one bounded reader); one that cannot be read is
    network check's finding (IO001) and exit 3, as in every network command."""
    if path == "-":
        return read_input(path)
    register_input(path)
    from dcf2bin.fileio import read_file
    try:
        return read_file(path)
    except OSError as exc:
        from dcf2bin.network.check import unreadable
        emit([unreadable(path, exc)])
        raise Failure(ExitCode.UNREADABLE)


def master_option(fn):
    """--master plc|lely: the kind of master, the same in build, check and show, so that
    what build makes in a mode is what check checks and show draws."""
    return click.option(
        "--master", "master_kind", type=click.Choice(["plc", "lely"]), default=None,
        help="The kind of master: plc (the master's dcf: is the PLC's file) or lely "
             "(master.dcf as lely's dcfgen -r writes it). Default: plc when the master "
             "has dcf:, else lely.")(fn)


def examined(path: str, quiet: bool, net: int | None = None, *, select=None, ignore=None,
             need: str = "file", master: str | None = None):
    """``network check``'s findings of ``path`` (a YAML network, configured in memory, or a
    .cpj project, whose nodes are their DCFs as they are; ``net`` picks its network), with
    validate's warnings about each node's file left out, ``select``/``ignore`` as check
    reads them but for the errors that make the work of a command with this ``need``
    unsound (``network.check.is_binding``): printed, and returned with the network
    (``CheckResult``). Every network command reads a network through this, so that they
    all find the same errors and exit alike (issue 26). A network file that cannot be read
    is IO001 and exit 3, as check says it."""
    from dcf2bin.network.check import ERRORS, examine
    data = read_network_file(path)
    res = examine(path, net=net, lint=ERRORS, select=select, ignore=ignore, binding=need,
                  data=data, master=master)
    emit(res.diagnostics, quiet)
    return res


def failing(diags, strict: bool = False) -> list:
    """The findings that fail a run: its errors, and with --strict its warnings too."""
    bad = (Severity.ERROR, Severity.WARNING) if strict else (Severity.ERROR,)
    return [d for d in diags if d.severity in bad]


def counts(diags) -> str:
    """'2 errors', '0 errors, 3 warnings (--strict)' (the findings of ``failing``)."""
    e = sum(d.severity is Severity.ERROR for d in diags)
    w = sum(d.severity is Severity.WARNING for d in diags)
    return f"{e} error{'s' if e != 1 else ''}" + (
        f", {w} warning{'s' if w != 1 else ''} (--strict)" if w else "")


def configured_network(path: str, quiet: bool, outcome: str, net: int | None = None, *,
                       select=None, ignore=None, strict: bool = False,
                       need: str = "configures", going_on: str = ""):
    """The network of ``path`` read as :func:`examined` reads it, and the exit status its
    findings earn (``ExitCode.OK`` when none fails the run). With ``need`` CONFIGURES
    (download) every error, and with ``strict`` every warning, ends the command before its
    work, saying ``outcome``; with NODES (scan, lss, upload) only the errors that make its
    work unsound do (``is_binding``): the others are said with ``going_on``, the work is
    done, and the command exits with the status returned (1, as check would)."""
    from dcf2bin.network.check import CONFIGURES, is_binding
    res = examined(path, quiet, net, select=select, ignore=ignore, need=need)
    bad = failing(res.diagnostics, strict)
    if not bad:
        return res.network, ExitCode.OK
    if need == CONFIGURES or any(is_binding(d, need) for d in bad):
        say(f"{path}: {counts(bad)}, {outcome}")
        raise Failure(exit_code(bad))
    say(f"{path}: {counts(bad)}, {going_on}")
    return res.network, exit_code(bad)


def exit_code(errors) -> ExitCode:
    """3 when a node's file could not be read (docs/options.md, "Exit codes": an input that
    cannot be read), 70 for an internal error in a rule, else 1 (as network check)."""
    from dcf2bin.network.check import UNREADABLE
    if any(d.rule == "INT001" for d in errors):
        return ExitCode.INTERNAL
    return (ExitCode.UNREADABLE if any(d.rule in UNREADABLE for d in errors)
            else ExitCode.FINDINGS)


def net_option(fn):
    """--net N: the network of a .cpj project."""
    return click.option("--net", "net", type=Integer(spec=argspec.NET), metavar="N",
                        help="For a .cpj project: its N-th network ([TopologyN]; default "
                        "the first, [Topology]).")(fn)


class ShowCommand(click.Command):
    """``--writes`` takes a value only when it is attached, ``--writes=NODE`` (issue 26: an
    optional value must never swallow the NETWORK argument, as ``--writes net/bus.yml``
    did). Before click parses them, ``--writes=NODE`` becomes ``--writes`` and NODE is
    kept aside; everything after ``--`` is left as it is."""

    def parse_args(self, ctx, args):
        rest, node = [], None
        for k, arg in enumerate(args):
            if arg == "--":
                rest += args[k:]
                break
            if arg.startswith("--writes="):
                node = arg[len("--writes="):]
                if not node:
                    raise click.BadParameter("give the node after '=' (--writes=NODE), or "
                                             "--writes alone for every slave",
                                             ctx=ctx, param_hint="'--writes'")
                arg = "--writes"
            rest.append(arg)
        ctx.meta["dcf2bin.writes_node"] = node
        return super().parse_args(ctx, rest)


class WritesOption(click.Option):
    """``--writes[=NODE]`` in the help (see ShowCommand)."""

    def get_help_record(self, ctx):
        record = super().get_help_record(ctx)
        return ("--writes[=NODE]", record[1]) if record else record


@click.command("show", cls=ShowCommand, context_settings=CONTEXT)
@click.argument("network_file", metavar="NETWORK", type=click.Path())
@format_option(["text", "json", "svg", "html", "dbc"], "text",
               "text or json (the tables), svg (the picture), html (both) or dbc (the PDOs "
               "as a CAN database for loggers; needs cantools).")
@output_option()
@click.option("--writes", "writes", cls=WritesOption, is_flag=True,
              help="Also the SDO writes that configure each slave; --writes=NODE (with '=') "
              "those of one slave, NODE its name or node-ID: index, sub, name, value and "
              "why.")
@net_option
@master_option
@rule_options
@quiet_option("No warnings about the network file.")
@debug_option
@guarded
def show_cmd(network_file, fmt, output, writes, net, master_kind, select_, ignore, strict,
             quiet, debug):
    """Show what talks to what in a network (YAML network file or .cpj project).

    Per COB-ID the producer, consumers, bytes, rate and share of the estimated bus load;
    per PLC variable the node and object it comes from; per slave the identity the
    master will enforce. The svg format draws each node as a box and each PDO as a lane
    from its producer to its consumers; html adds the tables. The dbc format writes the
    PDOs as a CAN database: a message per COB-ID, a signal per mapped object.

    The findings are those of 'network check' (validate's warnings about the node files
    left out), with --select/--ignore as there, on standard error; a network with errors
    is shown as it is configured, and the exit status is 1 (3 when a node's file cannot be
    read; --strict: warnings too). A network file that cannot be configured (errors in
    it, which --ignore cannot leave out) is not shown.
    """
    from dcf2bin.network import show, svg
    if fmt == "dbc":
        from dcf2bin.network import dbc
        try:
            dbc.require()                  # before the network is read: at once
        except dbc.CantoolsMissing:
            fail(dbc.MISSING, code=ExitCode.USAGE)
    check_rules(select_, ignore)
    ctx = click.get_current_context()
    node = ctx.meta.get("dcf2bin.writes_node")
    writes = node if node is not None else ("all" if writes else None)
    res = examined(network_file, quiet, net, select=select_, ignore=ignore, master=master_kind)
    network = res.network
    errors = [d for d in res.diagnostics if d.severity is Severity.ERROR]
    drawable = network.configured or network.kind == "cpj"
    if errors and not drawable:
        n = len(errors)
        say(f"{network_file}: {n} error{'s' if n != 1 else ''}, nothing shown (the network "
            "file cannot be configured)")
        raise Failure(exit_code(errors))
    if writes not in (None, "all") and show.find_node(network, writes) is None:
        names = ", ".join(f"{n.name} ({n.node_id})" for n in network.slaves)
        fail(f"--writes={writes}: no such node in {network_file} (slaves: {names})",
             code=ExitCode.USAGE)
    view = show.build(network, writes)
    if fmt == "dbc":
        data = dbc.dump(network, view)
    else:
        data = {"text": show.text, "json": show.as_json, "svg": svg.to_svg,
                "html": svg.to_html}[fmt](view)
    write_output(data, output, [network_file], binary=False)
    bad = failing(res.diagnostics, strict)
    if bad:
        say(f"{network_file}: {counts(bad)}; shown as configured")
        raise Failure(exit_code(bad))

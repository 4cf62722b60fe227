"""Commands: network check: a network (YAML or .cpj) checked as a whole (issue 20).

Findings are the command's result, so they go to stdout (or ``-o FILE``), in validate's
formats; usage errors go to stderr. Exit codes: see ``ExitCode`` and
man/dcf2bin-network-check.1.
"""
from __future__ import annotations

import click

from dcf2bin import argspec
from dcf2bin.cli.common import (CONTEXT, Failure, Integer, Number, check_output, debug_option,
                                format_option, guarded, lint_report, output_option,
                                quiet_option, rule_options, write_output)
from dcf2bin.cli.network.show import master_option
from dcf2bin.diagnostics import ExitCode

FORMATS = ("text", "json", "sarif", "github")


@click.command("check", context_settings=CONTEXT)
@click.argument("network", required=False, type=click.Path(dir_okay=True))
@format_option(FORMATS, "text", "the report as text, JSON, SARIF or GitHub annotations.")
@output_option("Default: standard output.")
@rule_options
@click.option("--max-load", type=Number(argspec.MAX_LOAD), default=80.0, show_default=True,
              metavar="PERCENT", help="Warn when the estimated bus load is above this.")
@click.option("--net", "net", type=Integer(spec=argspec.NET), metavar="N",
              help="For a .cpj project: check its N-th network ([TopologyN]; default the "
                   "first, [Topology]).")
@master_option
@click.option("--list-rules", is_flag=True, help="Print every rule and exit.")
@click.option("--hints", is_flag=True, help="Text format: print each finding's hint below it.")
@quiet_option("Text format: no summary line either.")
@debug_option
@guarded
def check_cmd(network, fmt, output, select_, ignore, strict, max_load, net, master_kind,
              list_rules, hints, quiet, debug):
    """Check a network as a whole: every node's file as validate checks it, then the
    rules between nodes (node-IDs, COB-IDs, PDO mappings, SYNC, heartbeats, bus load).

    NETWORK is a lely/ros2_canopen bus.yml or a CiA 306-3 .cpj project. Exit status:
    0 no errors (warnings allowed unless --strict), 1 findings, 2 usage error, 3 the
    network or a node's file could not be read (or the report could not be written),
    70 internal error.
    """
    from dcf2bin import report
    from dcf2bin.network.check import SelectorError, check_network, resolve, rule_table

    table = rule_table()
    rules = list(table.values())
    if list_rules:
        if fmt == "json":
            text = report.rules_json([r.as_dict() for r in rules])
        else:
            width = max(len(r.name) for r in rules)
            text = "".join(f"{r.id:<7} {r.severity.value:<8} {r.name:<{width}}  "
                           f"{r.description}\n" for r in rules)
        write_output(text, output, [], binary=False)
        return
    if network is None:
        raise click.UsageError("give the NETWORK file (a bus.yml or a .cpj project)")
    check_output(output, [network])     # before every node's file is read and checked
    if net is not None and not network.lower().endswith(".cpj"):
        raise click.BadParameter("only a .cpj project has several networks",
                                 param_hint="'--net'")
    try:
        resolve(select_, ignore, table)
    except SelectorError as exc:
        raise click.BadParameter(str(exc), param_hint="'--select' / '--ignore'")
    result = check_network(network, select=select_, ignore=ignore, max_load=max_load, net=net,
                           master=master_kind)
    diags = result.diagnostics
    code = result.exit_code(strict)
    text = lint_report(fmt, diags, result.files, rules, code, output=output, quiet=quiet,
                       hints=hints, read=len(result.files))
    write_output(text, output, [network] + [p for p, _ in result.files], binary=False)
    if code != ExitCode.OK:
        raise Failure(code)

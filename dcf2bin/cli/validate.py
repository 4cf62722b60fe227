"""Commands: validate: lint DCF/EDS files and containers (issue 4).

Findings are the command's result, so they go to stdout (or ``-o FILE``); usage errors
and tracebacks (``--debug``) go to stderr. Exit codes: see ``ExitCode`` and
man/dcf2bin-validate.1.
"""
from __future__ import annotations

import click

from dcf2bin import argspec
from dcf2bin.cli.common import (CONTEXT, COUNT, Choice, Failure, Integer, check_output,
                                debug_option, eds_option, format_option, guarded, lint_report,
                                load_static_od, node_id_option, output_option, quiet_option,
                                read_eds, read_input, rule_options, static_od_option,
                                target_stack_options, write_output)
from dcf2bin.diagnostics import ExitCode

FORMATS = ("text", "json", "sarif", "github")


@click.command("validate", context_settings=CONTEXT)
@click.argument("paths", nargs=-1, type=click.Path(allow_dash=True))
@format_option(FORMATS, "text", "the report as text, JSON, SARIF or GitHub annotations.")
@output_option("Default: standard output.")
@rule_options
@click.option("--list-rules", is_flag=True, help="Print every rule and exit.")
@click.option("--profile", type=Choice(argspec.PROFILE), default="cia301",
              show_default=True, help="Device profile for the PDO checks (dis2: Metronix DIS-2).")
@node_id_option("Used for $NODEID values (overrides [DeviceComissioning] NodeID).")
@click.option("--pi-size", type=COUNT, metavar="N", help="PI memory of the target in bytes.")
@click.option("--pi-align", type=Choice(argspec.PI_ALIGN), default="8",
              show_default=True,
              help="Alignment in bytes of the output area's start in the process image.")
@click.option("--address-base", type=Choice(argspec.ADDRESS_BASE), default="image",
              show_default=True, help="PI addresses count from the start of the whole "
              "process image, or from the start of the variable's area.")
@click.option("--allow-external-files", is_flag=True,
              help="Allow DownloadFile paths that are absolute or leave the DCF's folder.")
@click.option("--no-target-check", is_flag=True,
              help="Do not run the model of the target's DynBuildOd() (the TGT rules).")
@target_stack_options
@static_od_option("Objects absent from it are created (as compile creates them); on a "
                  "container, what it never writes is then checked against it too.")
@eds_option("Concise DCFs are checked against it (without it: each against the .dcf, else "
            "the .eds, of its own name beside it, if there is one).")
@click.option("--stdin-filename", default="<stdin>", show_default=True, metavar="NAME",
              help="File name to report for '-' (stdin).")
@click.option("--hints", is_flag=True, help="Text format: print each finding's hint below it.")
@click.option("-j", "--jobs", type=Integer(1), metavar="N",
              help="Check up to N files at a time, in this process and N-1 worker processes "
                   "(default: one per usable CPU core; 1: one after the other). The report "
                   "is the same.")
@quiet_option("Text format: no summary line either.")
@debug_option
@guarded
def validate_cmd(paths, fmt, output, select_, ignore, strict, list_rules, profile, node_id,
                 pi_size, pi_align, address_base, allow_external_files, no_target_check,
                 tx_cobs, rx_cobs, granularity, no_bit_mapping, static_od, eds,
                 stdin_filename, hints, jobs, quiet, debug):
    """Lint DCF/EDS files, binary containers and concise DCFs: every problem, with rule ids.

    PATHS are files, directories (searched recursively for *.eds, *.dcf, *.bin in any
    case) and '-' for stdin. Text output shows at most 20 findings per rule and file (the
    other formats all). Exit status: 0 no errors (warnings allowed unless --strict),
    1 findings, 2 usage error, 3 an input could not be read (or a directory holds no such
    file) or the report could not be written, 70 internal error.
    """
    from dcf2bin import report
    from dcf2bin.lint import Options, SelectorError, all_rules, resolve, run

    rules = all_rules()
    if list_rules:
        if fmt == "json":
            text = report.rules_json([r.as_dict() for r in rules])
        else:
            width = max(len(r.name) for r in rules)
            text = "".join(f"{r.id:<7} {r.severity.value:<8} {r.name:<{width}}  "
                           f"{r.description}\n" for r in rules)
        _write(text, output, paths)
        return
    if not paths:
        raise click.UsageError("give at least one PATH (file, directory or '-')")
    check_output(output, [p for p in paths if p != "-"])    # before a folder's worth of work
    try:
        active = resolve(select_, ignore)
    except SelectorError as exc:
        raise click.BadParameter(str(exc), param_hint="'--select' / '--ignore'")
    load_static_od(static_od, quiet, "nothing checked")
    read_eds(eds, quiet)        # DCF/EDS text or XML that reads (exit 3, 1 otherwise)
    stdin = read_input("-") if "-" in paths else None
    opts = Options(node_id=node_id, pi_size=pi_size, pi_align=int(pi_align),
                   address_base=address_base, profile=profile,
                   allow_external_files=allow_external_files, active=active, strict=strict,
                   target_check=not no_target_check, tx_cobs=tx_cobs, rx_cobs=rx_cobs,
                   granularity=int(granularity), bit_mapping=not no_bit_mapping,
                   static_od=static_od, eds=eds)
    if jobs is None:
        from dcf2bin.lint.parallel import usable_cores
        jobs = usable_cores()
    result = run(list(paths), opts, stdin=stdin, stdin_name=stdin_filename, jobs=jobs)
    diags = result.diagnostics
    code = result.exit_code(strict)
    read = sum(1 for f in result.files if f.kind != "unreadable")
    text = lint_report(fmt, diags, [(f.path, f.kind) for f in result.files], rules, code,
                       output=output, quiet=quiet, hints=hints, read=read)
    _write(text, output, list(paths) + [f.path for f in result.files])
    root = click.get_current_context().find_root().params or {}
    if result.tracebacks and (debug or root.get("debug")):
        for tb in result.tracebacks:
            click.echo(tb, err=True, nl=False)
    if code != ExitCode.OK:
        raise Failure(code)


def _write(text: str, output: str, paths) -> None:
    write_output(text, output, [p for p in paths if p != "-"], binary=False)

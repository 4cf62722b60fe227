"""dcf2bin diff: compare two configurations by meaning (docs/diff.md)."""
from __future__ import annotations

import os
import sys

import click

from dcf2bin.cli.common import (CONTEXT, COUNT, Failure, Seconds, check_output, debug_option,
                                emit, fail, format_option, guarded, node_id_option,
                                output_option, quiet_option, read_input, say, write_output)
from dcf2bin.cli.download import bus_options, open_bus
from dcf2bin.diagnostics import Diagnostic, ExitCode, Severity

# = compare.KINDS (not imported: --help)
KINDS = ("dcf", "xdd", "bin", "json", "concise", "concise-json")


def _ignore(ctx, param, value):
    if not value:
        return []
    from dcf2bin.compare import BadIgnore, parse_ignore
    spans = []
    for text in value:
        try:
            spans += parse_ignore(text)
        except BadIgnore as exc:
            raise click.BadParameter(str(exc), ctx, param) from None
    return spans


@click.command("diff", context_settings=CONTEXT)
@click.argument("a", metavar="A", type=click.Path(allow_dash=True))
@click.argument("b", metavar="[B]", required=False, type=click.Path(allow_dash=True))
@node_id_option("With one input: the node on the bus to compare it with. With two: the "
                "node-ID of $NODEID values (default: each file's [DeviceComissioning] "
                "NodeID, else the other file's).")
@bus_options
@click.option("--timeout", type=Seconds(0.001), default=1.0, show_default=True,
              metavar="SECONDS", help="Seconds to wait for each SDO response (a node).")
@click.option("--retries", type=COUNT, default=2, show_default=True, metavar="N",
              help="Times an unanswered SDO request is sent again (a node).")
@click.option("--all", "all_", is_flag=True,
              help="Compare the node's state too (0x1001-0x1003, 0x1010, 0x1011, read-only "
              "entries from 0x2000 on), which is left out by default.")
@click.option("--ignore", multiple=True, metavar="ENTRY|RANGE", callback=_ignore,
              help="Leave out these entries: 0x1017, 0x1018sub4, 0x2000-0x2FFF; "
              "comma-separated or repeated.")
@click.option("--values-only", is_flag=True,
              help="Compare values only, not data types, access or PDO mapping flags.")
@format_option(["text", "json"], "text", "text = like diff -u; json = every difference "
               "as data.")
@output_option("Default: standard output.")
@quiet_option("No summary line.")
@debug_option
@guarded
def diff_cmd(a, b, node_id, interface, channel, bitrate, timeout, retries, all_, ignore,
             values_only, fmt, output, quiet, debug):
    """Compare two configurations entry by entry: DCF, EDS, XDD/XDC, containers, concise
    DCFs, the JSON form of either, two network build (or upload) folders, or with -n and one
    file a node on the bus.

    Values are compared by type and meaning ($NODEID worked out, 0x10 equals 16); a
    container or concise DCF by what the node holds after it. Exit 0 when equal and both
    read without errors, 1 when they differ or an input has errors (compared as read, each
    error printed), 2 for a usage error, 3 when an input cannot be read.
    """
    from dcf2bin import compare
    check_output(output)
    scope = compare.Scope(state=not all_, ignore=list(ignore), values_only=values_only)
    bus = interface is not None or channel is not None or bitrate is not None
    if b is None:
        if node_id is None:
            _usage("give two inputs to compare, or one and -n N to compare it with that "
                   "node on the bus")
        if os.path.isdir(a):
            _usage(f"{a} is a folder: with -n, diff compares one file (a DCF, EDS, XDD/XDC, "
                   "container or concise DCF) with that node on the bus; two folders are "
                   "compared with each other")
        result = _with_node(a, node_id, scope, interface, channel, bitrate, timeout,
                            retries, quiet)
    elif bus:
        _usage("-i/--interface, --channel and --bitrate are for a node: give one input "
               "and -n N")
    elif os.path.isdir(a) or os.path.isdir(b):
        if not (os.path.isdir(a) and os.path.isdir(b)):
            folder, other = (a, b) if os.path.isdir(a) else (b, a)
            _usage(f"{folder} is a folder and {other} is not: diff compares a folder with "
                   "a folder, a file with a file")
        if node_id is not None:
            _usage("-n names one node: with two folders each file's own node-ID is taken")
        result = _folders(a, b, scope, quiet)
    else:
        diff = _files(a, b, node_id, scope, quiet)
        result = compare.Result(diff.a.label, diff.b.label, [diff])
    _report(result, scope, fmt, output, quiet)
    if not result.equal:
        raise Failure(ExitCode.FINDINGS)


def _usage(message: str) -> None:
    ctx = click.get_current_context()
    raise click.UsageError(message, ctx)


def _load(path: str, node_id, quiet: bool):
    """An input read for comparing; one that cannot be (missing, another kind, damaged)
    ends the command with exit 3."""
    from dcf2bin import compare, filekind
    data = read_input(path)
    name = "<stdin>" if path == "-" else path
    kind = filekind.detect(data, "" if path == "-" else path)
    problem = filekind.mismatch(name, kind, KINDS, use="dcf2bin diff compares DCF/EDS "
                                "text, CiA 311 XML, containers, concise DCFs and the JSON "
                                "form of either")
    if problem:          # not a file of a kind diff reads (DCF008, as validate says it)
        emit([Diagnostic(Severity.ERROR, problem, name, rule="DCF008")])
        raise Failure(ExitCode.UNREADABLE)
    # the content wins, as in every command (a concise DCF is a .bin as a container is)
    note = filekind.misnamed(name, kind)
    if note:
        emit([Diagnostic(Severity.WARNING, note, name)], quiet)
    try:
        return compare.load(data, name, kind, node_id=node_id)
    except compare.Unreadable as exc:
        emit(exc.diagnostics)
        raise Failure(ExitCode.UNREADABLE) from None


def _files(a: str, b: str, node_id, scope, quiet: bool):
    from dcf2bin import compare
    diff, warnings = compare.compare_sources(_load(a, node_id, quiet),
                                             _load(b, node_id, quiet), scope)
    emit(warnings, quiet)
    return diff


def _folders(a: str, b: str, scope, quiet: bool):
    from dcf2bin import compare
    from dcf2bin.compare import folders
    names = []
    for folder in (a, b):
        try:
            found = folders.listing(folder)
        except OSError as exc:
            fail(f"cannot read: {exc.strerror or exc}", folder, ExitCode.UNREADABLE)
        emit([Diagnostic(Severity.WARNING, f"{kind}, not a regular file: not compared",
                         os.path.join(folder, name)) for name, kind in found.others.items()],
             quiet)
        names.append(found.files)
    p = folders.pair(*names)
    result = compare.Result(a, b, only_a=p.only_a, only_b=p.only_b,
                            not_compared=p.not_compared, folders=True)
    for name in p.common:
        pa, pb = os.path.join(a, name), os.path.join(b, name)
        result.files.append(_files(pa, pb, None, scope, quiet))
    return result


def _with_node(path: str, node_id: int, scope, interface, channel, bitrate, timeout,
               retries, quiet: bool):
    from dcf2bin import compare
    from dcf2bin.bus import link
    from dcf2bin.compare import node
    src = _load(path, node_id, quiet)
    side, warnings = compare.side(src, node_id)
    emit(src.warnings + warnings, quiet)
    net = open_bus(interface, channel, bitrate)
    try:
        other = _read_node(net, node_id, side, scope, timeout, retries, quiet)
    except node.NodeStopped as exc:
        fail(str(exc), f"node {node_id}", ExitCode.UNREADABLE)
    finally:
        link.close_network(net)
    result = compare.Result(side.label, other.label)
    result.files.append(compare.compare(side, other, scope))
    emit(result.files[0].diagnostics(), quiet)
    return result


def _read_node(net, node_id, side, scope, timeout, retries, quiet: bool):
    from dcf2bin.compare import node
    if quiet or not sys.stderr.isatty():
        return node.node_side(net, node_id, side, scope, timeout=timeout, retries=retries)
    with click.progressbar(length=node.total(side, scope), label=f"node {node_id}",
                           file=sys.stderr) as bar:
        return node.node_side(net, node_id, side, scope, timeout=timeout, retries=retries,
                              progress=lambda: bar.update(1))


def _report(result, scope, fmt: str, output: str, quiet: bool) -> None:
    from dcf2bin.compare import jsonform, text
    from dcf2bin.report import use_colour
    if fmt == "json":
        out = jsonform.render(result, scope)
    else:
        out = text.render(result, colour=output == "-" and _colour(use_colour))
    if out:
        write_output(out, output, [], binary=False)
    elif output != "-":
        write_output("", output, [], binary=False)
    if not quiet:
        say(text.summary(result))


def _colour(use_colour) -> bool:
    try:
        return use_colour(sys.stdout)
    except (OSError, ValueError):
        return False

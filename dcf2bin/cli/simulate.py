"""dcf2bin simulate: what the target's DynBuildOd() returns for a container (SPEC §8, D-11).

Only click and the shared CLI pieces are imported here; the work is imported inside the
command so that ``dcf2bin --help`` stays fast.
"""
from __future__ import annotations

import click

from dcf2bin.cli.common import (CONTEXT, Failure, emit, guarded, read_input, stop_on_errors,
                                target_stack_options, write_output)
from dcf2bin.diagnostics import Diagnostic, ExitCode, Severity

_DCF_SUFFIXES = (".dcf", ".eds", ".ini")


def _kind(path: str, data: bytes, forced: str | None) -> str:
    if forced:
        return forced
    low = path.lower()
    if low.endswith(".json"):
        return "json"
    if low.endswith(".bin"):
        return "bin"
    if low.endswith(_DCF_SUFFIXES):
        return "dcf"
    if len(data) >= 40 and (int.from_bytes(data[:4], "little") == len(data)
                            or b"\x00" in data[:512]):
        return "bin"
    return "json" if data.lstrip()[:1] == b"{" else "dcf"


@click.command("simulate", context_settings=CONTEXT)
@click.argument("input", type=click.Path(allow_dash=True))
@click.option("--from", "from_", type=click.Choice(["bin", "dcf", "json"]),
              help="Input kind (default: by extension: .bin container, .json lossless dump, "
              ".dcf/.eds compiled first).")
@click.option("--static-od", type=click.Path(), metavar="EDS",
              help="EDS of the objects the target's firmware already has. Without it, a "
              "container's entries are all created from their attributes, and what the "
              "container never writes is not checked (a warning says so).")
@click.option("--pi-size", type=click.IntRange(0), metavar="N",
              help="PI memory the target gives, in bytes (default: unlimited).")
@target_stack_options
@click.option("--address-base", type=click.Choice(["image", "area"]), default="image",
              show_default=True, help="PI addresses count from the image start or their area.")
@click.option("-f", "--format", "fmt", type=click.Choice(["text", "json"]), default="text",
              show_default=True, help="Report format (stdout).")
@click.option("--emit-od", type=click.Path(dir_okay=False), metavar="FILE.dcf",
              help="Also write the object dictionary after DynBuildOd as a DCF.")
@click.option("--node-id", type=click.IntRange(1, 127),
              help="DCF input: node-ID for $NODEID values.")
@click.option("--select", "select_", type=click.Choice(["auto", "all"]), default="auto",
              show_default=True, help="DCF input: which entries compile writes.")
@click.option("--pdo-sequence", type=click.Choice(["cia301", "none"]), default="cia301",
              show_default=True, help="DCF input: how compile writes a PDO block.")
@click.option("--no-process-image", is_flag=True,
              help="DCF input: compile without the PI segments.")
@click.option("--pi-align", type=click.Choice(["1", "2", "4", "8"]), default="8",
              show_default=True, help="DCF input: alignment of the output area's start.")
@click.option("--profile", type=click.Choice(["cia301", "dis2"]), default="cia301",
              show_default=True, help="DCF input: device profile for PDO writes.")
@click.option("--append", "append", multiple=True, type=click.Path(),
              metavar="FILE", help="DCF input: extra-writes file added after all entries.")
@click.option("--allow-external-files", is_flag=True,
              help="DCF input: allow DownloadFile paths outside the DCF's folder.")
@click.option("-q", "--quiet", is_flag=True, help="Print errors only on stderr.")
@guarded
def simulate_cmd(input, from_, static_od, pi_size, tx_cobs, rx_cobs, granularity,
                 no_bit_mapping, address_base, fmt, emit_od, node_id, select_, pdo_sequence,
                 no_process_image, pi_align, profile, append, allow_external_files, quiet):
    """Run a model of the target's DynBuildOd() on a container and print its return code.

    INPUT is a binary container, its lossless JSON form, or a DCF/EDS (compiled first,
    with the compile options below; its own objects, minus those the container creates,
    are then the target's static object dictionary). The report starts with the return
    code (0x00 kCopSuccessful, or the code and the entry that fails), then the process
    image and every valid PDO with what it carries. Exit status: 0 when the code is
    0x00, 1 when it is not, 2 usage error, 3 an input could not be read.
    """
    from dcf2bin.dynod import StaticOD, TargetOptions, emulate, emulate_bytes, report
    data = read_input(input)
    name = "<stdin>" if input == "-" else input
    kind = _kind(name, data, from_)
    topts = TargetOptions(pi_size=pi_size, tx_cobs=tx_cobs, rx_cobs=rx_cobs,
                          granularity=int(granularity), bit_mapping=not no_bit_mapping,
                          address_base=address_base)
    names = None
    if kind == "dcf":
        from dcf2bin.compiler import CompileOptions, compile_path
        from dcf2bin.dynod import check
        for path in append:
            read_input(path)
        if static_od:
            read_input(static_od)
        opts = CompileOptions(node_id=node_id, select=select_, pdo_sequence=pdo_sequence,
                              static_od=static_od, process_image=not no_process_image,
                              pi_align=int(pi_align), pi_size=pi_size,
                              address_base=address_base,
                              allow_external_files=allow_external_files, profile=profile,
                              append=tuple(append), target_check="off")
        res = compile_path(name, opts, data=data)
        emit(res.diagnostics, quiet)
        stop_on_errors(res, name, "no container to simulate")
        out = check.run(res.device, res.selection, res.container, topts, res.extra)
        names = _names(res.device)
    else:
        static = None
        if static_od:
            raw = read_input(static_od)
            static = StaticOD.from_eds(static_od, raw)
            bad = sum(1 for p in static.dev.problems
                      if p.diagnostic.severity is Severity.ERROR)
            if bad:
                emit([Diagnostic(Severity.WARNING, f"the static OD has {bad} error"
                                 f"{'s' if bad != 1 else ''} (see 'dcf2bin validate'); its "
                                 "objects are used where they could be read", static_od)],
                     quiet)
            names = _names(static.dev)
        if kind == "json":
            from dcf2bin.dump import from_json_bytes
            data, diags = from_json_bytes(data, name)
            emit(diags, quiet)
            if data is None:
                raise Failure(ExitCode.FINDINGS)
        if static is None:
            out = emulate_bytes(data, topts)
        else:
            from dcf2bin.container import ContainerError, read
            try:
                c, _ = read(data)
            except ContainerError:
                out = emulate_bytes(data, topts)
            else:
                out = emulate(c, topts, static)
    emit([Diagnostic(Severity.WARNING, w.message, name, rule=w.rule) for w in out.warnings],
         quiet)
    text = report.to_json(out, name) if fmt == "json" else report.text(out, name)
    write_output(text, "-", [], binary=False)   # a full disk or closed stdout: exit 3
    if emit_od:
        write_output(report.emit_od(out, name, names), emit_od,
                     [input] + ([static_od] if static_od else []) + list(append), binary=False)
    if not out.ok:
        raise Failure(ExitCode.FINDINGS)


def _names(dev):
    def name(index: int, sub):
        obj = dev.objects.get(index)
        if obj is None:
            return None
        if sub is None:
            return obj.name or None
        e = obj.entries.get(sub)
        return (e.name or None) if e is not None else None
    return name

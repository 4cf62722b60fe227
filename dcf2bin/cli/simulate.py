"""dcf2bin simulate: what the target's DynBuildOd() returns for a container (SPEC §8, D-11).

Only click and the shared CLI pieces are imported here; the work is imported inside the
command so that ``dcf2bin --help`` stays fast.
"""
from __future__ import annotations

import click

from dcf2bin import argspec
from dcf2bin.cli.common import (CONTEXT, COUNT, Choice, Failure, debug_option, emit, entries_option,
                                format_option, from_option, guarded, input_kind,
                                load_static_od, node_id_option, output_option, quiet_option,
                                read_input, static_od_option, stop_on_errors,
                                target_stack_options, without_cyclic_gc, write_output)
from dcf2bin.diagnostics import Diagnostic, ExitCode, Severity


@click.command("simulate", context_settings=CONTEXT)
@click.argument("input", type=click.Path(allow_dash=True))
@from_option(["bin", "dcf", "json"], "bin = container, json = lossless dump, dcf = "
             "DCF/EDS compiled first.")
@static_od_option("Without it, a container's entries are all created from their "
                  "attributes, and what the container never writes is not checked (a "
                  "warning says so).")
@click.option("--pi-size", type=COUNT, metavar="N",
              help="PI memory the target gives, in bytes (default: unlimited).")
@target_stack_options
@click.option("--address-base", type=Choice(argspec.ADDRESS_BASE), default="image",
              show_default=True, help="PI addresses count from the image start or their area.")
@format_option(["text", "json"], "text", "the report as text or JSON.")
@output_option("Default: standard output.")
@click.option("--emit-od", type=click.Path(), metavar="FILE.dcf",
              help="Also write the object dictionary after DynBuildOd as a DCF.")
@node_id_option("DCF input: used for $NODEID values.")
@entries_option("DCF input.")
@click.option("--pdo-sequence", type=Choice(argspec.PDO_SEQUENCE), default="cia301",
              show_default=True, help="DCF input: how compile writes a PDO block.")
@click.option("--no-process-image", is_flag=True,
              help="DCF input: compile without the PI segments.")
@click.option("--pi-align", type=Choice(argspec.PI_ALIGN), default="8",
              show_default=True, help="DCF input: alignment of the output area's start.")
@click.option("--profile", type=Choice(argspec.PROFILE), default="cia301",
              show_default=True, help="DCF input: device profile for PDO writes.")
@click.option("--append", "append", multiple=True, type=click.Path(),
              metavar="FILE", help="DCF input: extra-writes file added after all entries.")
@click.option("--allow-external-files", is_flag=True,
              help="DCF input: allow DownloadFile paths outside the DCF's folder.")
@quiet_option()
@debug_option
@guarded
@without_cyclic_gc
def simulate_cmd(input, from_, static_od, pi_size, tx_cobs, rx_cobs, granularity,
                 no_bit_mapping, address_base, fmt, output, emit_od, node_id, entries,
                 pdo_sequence, no_process_image, pi_align, profile, append,
                 allow_external_files, quiet, debug):
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
    kind = input_kind(input, data, ("bin", "dcf", "xdd", "json"), from_, quiet=quiet)
    static_raw = load_static_od(static_od, quiet, "nothing simulated")
    topts = TargetOptions(pi_size=pi_size, tx_cobs=tx_cobs, rx_cobs=rx_cobs,
                          granularity=int(granularity), bit_mapping=not no_bit_mapping,
                          address_base=address_base)
    names = None
    if kind in ("dcf", "xdd"):
        from dcf2bin.compiler import CompileOptions, compile_path
        from dcf2bin.dynod import check
        for path in append:
            read_input(path)
        opts = CompileOptions(node_id=node_id, select=entries, pdo_sequence=pdo_sequence,
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
            static = StaticOD.from_eds(static_od, static_raw)
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
    inputs = [input] + ([static_od] if static_od else []) + list(append)
    write_output(text, output, inputs, binary=False)   # a full disk or closed stdout: exit 3
    if emit_od:
        write_output(report.emit_od(out, name, names), emit_od, inputs, binary=False)
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

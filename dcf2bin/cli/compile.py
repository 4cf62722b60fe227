"""dcf2bin compile: DCF/EDS (or the lossless JSON form) -> binary container.

Only click and the shared CLI pieces are imported here; the work is imported inside
the command so that ``dcf2bin --help`` stays fast.
"""
from __future__ import annotations

import os

import click

from dcf2bin import argspec
from dcf2bin.cli.common import (CONTEXT, COUNT, Choice, Failure, Integer, check_input,
                                debug_option, default_output, emit, entries_option, fail,
                                force_option,
                                format_option, from_option, guarded, input_kind,
                                load_static_od, node_id_option, output_option, quiet_option,
                                read_input, static_od_option, stop_on_errors,
                                target_stack_options, verbose_option, without_cyclic_gc,
                                write_output)
from dcf2bin.diagnostics import ExitCode

# -- compile ------------------------------------------------------------------------------------

@click.command("compile", context_settings=CONTEXT)
@click.argument("input", type=click.Path(allow_dash=True))
@output_option("Default: INPUT with the suffix .bin (.c with --format c), never over an "
               "existing file unless --force.", default=None)
@force_option
@node_id_option("Used for $NODEID values (overrides [DeviceComissioning] NodeID).")
@entries_option()
@click.option("--pdo-sequence", type=Choice(argspec.PDO_SEQUENCE), default="cia301",
              show_default=True,
              help="How a PDO block is written: CiA 301 reconfiguration, or as configured.")
@static_od_option("Objects absent from it are created.")
@click.option("--no-process-image", is_flag=True,
              help="Omit the PI address and PI parameter segments.")
@click.option("--pi-align", type=Choice(argspec.PI_ALIGN), default="8",
              show_default=True,
              help="Alignment in bytes of the output area's start in the process image.")
@click.option("--pi-size", type=COUNT, metavar="N", help="PI memory of the target in bytes.")
@click.option("--address-base", type=Choice(argspec.ADDRESS_BASE), default="image",
              show_default=True, help="PI addresses count from the start of the whole "
              "process image, or from the start of the variable's area.")
@click.option("--container-version", type=Integer(spec=argspec.CONTAINER_VERSION), default=1,
              metavar="N", show_default=True, help="Value of the container header's version field.")
@click.option("--allow-external-files", is_flag=True,
              help="Allow DownloadFile paths that are absolute or leave the DCF's folder.")
@click.option("--profile", type=Choice(argspec.PROFILE), default="cia301", show_default=True,
              help="Device profile for PDO writes (dis2: Metronix DIS-2).")
@click.option("--append", "append", multiple=True, type=click.Path(),
              metavar="FILE", help="Extra-writes file added after all other entries "
              "(repeatable; see dcf2bin-tunnel(1)).")
@click.option("--no-target-check", is_flag=True,
              help="Report what the target's DynBuildOd() would refuse as a warning and "
              "write the container anyway.")
@click.option("--limit-check", type=Choice(argspec.LIMIT_CHECK), default="warning",
              show_default=True, help="A written value outside its LowLimit..HighLimit: a "
              "warning (the value is written as it is), or an error (nothing is written).")
@click.option("--no-limit-check", is_flag=True,
              help="The same as --limit-check warning (the default), for older scripts.")
@target_stack_options
@from_option(["dcf", "json"], "json = lossless dump.")
@quiet_option()
@verbose_option("a summary of what was written.")
@format_option(["bin", "c"], "bin", "bin: the container; c: the container as C source "
               "(an array and a <NAME>_PI_SIZE define).")
@click.option("--c-name", metavar="NAME", help="c: name of the array (default: the input's "
              "base name).")
@click.option("--c-decl", metavar="DECL", default="const unsigned char", show_default=True,
              help="c: the declaration before the array's name, e.g. 'static CONST BYTE ROM'.")
@debug_option
@guarded
@without_cyclic_gc
def compile_cmd(input, output, force, node_id, entries, pdo_sequence, static_od,
                no_process_image, pi_align, pi_size, address_base, container_version,
                allow_external_files, profile, append, no_target_check, limit_check,
                no_limit_check, tx_cobs, rx_cobs, granularity, no_bit_mapping, from_, quiet,
                verbose, fmt, c_name, c_decl, debug):
    """Compile a DCF/EDS file (or a lossless JSON dump) into a binary container."""
    from dcf2bin.compiler import CompileOptions, compile_path
    out_format = fmt
    data_in = read_input(input)
    fmt = input_kind(input, data_in, ("dcf", "xdd", "json", "concise-json"), from_,
                     quiet=quiet)
    if output is None:
        output = default_output(input, ".c" if out_format == "c" else ".bin", force)
    write = _writer(out_format, c_name, c_decl, input)
    name = "<stdin>" if input == "-" else input
    if fmt in ("json", "concise-json"):      # the bytes of a container or a concise DCF
        from dcf2bin.dump import from_json_bytes
        data, diags = from_json_bytes(data_in, name)
        emit(diags, quiet)
        if data is None:
            raise Failure(ExitCode.FINDINGS)
        write(data, output, [input])
        return
    opts = CompileOptions(node_id=node_id, select=entries, pdo_sequence=pdo_sequence,
                          static_od=static_od, process_image=not no_process_image,
                          pi_align=int(pi_align), pi_size=pi_size, address_base=address_base,
                          container_version=container_version,
                          allow_external_files=allow_external_files, profile=profile,
                          append=tuple(append),
                          target_check="warning" if no_target_check else "error",
                          limit_check=_limit_check(limit_check, no_limit_check),
                          tx_cobs=tx_cobs, rx_cobs=rx_cobs, granularity=int(granularity),
                          bit_mapping=not no_bit_mapping)
    for path in append:
        check_input(path)  # missing, a directory, unreadable: exit 3 like any input
    load_static_od(static_od, quiet, "nothing written")
    res = compile_path(name, opts, data=data_in)
    emit(res.diagnostics, quiet)
    stop_on_errors(res, name, "nothing written")
    write(res.data, output, [input])
    if verbose:
        c = res.container
        msg = f"{name} -> {output}: {len(res.data)} bytes, {len(c.entries)} entries"
        if c.pi is not None:
            msg += (f", {len(c.addresses)} network variables, PI {c.pi[0]} bytes "
                    f"(in {c.pi[2]} @ {c.pi[1]}, out {c.pi[4]} @ {c.pi[3]})")
        click.echo(msg, err=True)


def _limit_check(limit_check: str, no_limit_check: bool) -> str:
    """--no-limit-check is the old spelling of --limit-check warning; with --limit-check
    error it contradicts itself."""
    if no_limit_check and limit_check == "error":
        raise click.UsageError("--no-limit-check and --limit-check error contradict each "
                               "other; give one")
    return "warning" if no_limit_check else limit_check


def _writer(out_format: str, c_name: str | None, c_decl: str, input: str):
    """How the container leaves: as bytes, or (``--format c``) as C source."""
    if out_format != "c":
        return lambda data, output, inputs: write_output(data, output, inputs, binary=True)
    from dcf2bin.plc import csource
    name = c_name or csource.default_name("container" if input == "-" else input)
    problem = csource.name_problem(name) if c_name else None
    problem = problem or csource.decl_problem(c_decl)
    if problem:
        fail(problem, code=ExitCode.USAGE)
    source = "<stdin>" if input == "-" else os.path.basename(input)
    return lambda data, output, inputs: write_output(
        csource.render(data, name, decl=c_decl, source=source), output, inputs, binary=False)

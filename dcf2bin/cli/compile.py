"""dcf2bin compile: DCF/EDS (or the lossless JSON form) -> binary container.

Only click and the shared CLI pieces are imported here; the work is imported inside
the command so that ``dcf2bin --help`` stays fast.
"""
from __future__ import annotations

import os

import click

from dcf2bin.cli.common import (CONTEXT, Failure, check_input, emit, fail, guarded, read_input,
                                stop_on_errors, target_stack_options, write_output)
from dcf2bin.diagnostics import ExitCode

# -- compile ------------------------------------------------------------------------------------

_SELECT = click.Choice(["auto", "all"])
_SEQ = click.Choice(["cia301", "none"])


def _profile_choice():
    return click.Choice(["cia301", "dis2"])


@click.command("compile", context_settings=CONTEXT)
@click.argument("input", type=click.Path(allow_dash=True))
@click.option("-o", "--output", type=click.Path(dir_okay=False, allow_dash=True),
              help="Output file ('-' for stdout). Default: INPUT with the suffix .bin.")
@click.option("--node-id", type=click.IntRange(1, 127),
              help="Node-ID for $NODEID values (overrides [DeviceComissioning] NodeID).")
@click.option("--select", "select_", type=_SELECT, default="auto", show_default=True,
              help="Which entries to write: auto = configured entries (ParameterValue or "
                   "DownloadFile); all = every entry that has a value, DefaultValue included.")
@click.option("--pdo-sequence", type=_SEQ, default="cia301", show_default=True,
              help="How a PDO block is written: CiA 301 reconfiguration, or as configured.")
@click.option("--static-od", type=click.Path(),
              help="EDS of the target's static OD: objects absent from it are created.")
@click.option("--no-process-image", is_flag=True,
              help="Omit the PI address and PI parameter segments.")
@click.option("--pi-align", type=click.Choice(["1", "2", "4", "8"]), default="8",
              show_default=True,
              help="Alignment in bytes of the output area's start in the process image.")
@click.option("--pi-size", type=click.IntRange(0), help="PI memory of the target in bytes.")
@click.option("--address-base", type=click.Choice(["image", "area"]), default="image",
              show_default=True, help="PI addresses count from the start of the whole "
              "process image, or from the start of the variable's area.")
@click.option("--container-version", type=click.IntRange(0, 0xFFFF), default=1,
              show_default=True, help="Value of the container header's version field.")
@click.option("--allow-external-files", is_flag=True,
              help="Allow DownloadFile paths that are absolute or leave the DCF's folder.")
@click.option("--profile", type=_profile_choice(), default="cia301", show_default=True,
              help="Device profile for PDO writes (dis2: Metronix DIS-2).")
@click.option("--append", "append", multiple=True, type=click.Path(),
              metavar="FILE", help="Extra-writes file added after all other entries "
              "(repeatable; see dcf2bin-tunnel(1)).")
@click.option("--no-target-check", is_flag=True,
              help="Report what the target's DynBuildOd() would refuse as a warning and "
              "write the container anyway.")
@click.option("--no-limit-check", is_flag=True,
              help="Report a written value outside its LowLimit..HighLimit as a warning.")
@target_stack_options
@click.option("--from", "from_", type=click.Choice(["dcf", "json"]),
              help="Input format (default: by extension; .json = lossless dump).")
@click.option("-q", "--quiet", is_flag=True, help="Print errors only.")
@click.option("-v", "--verbose", is_flag=True, help="Print a summary of what was written.")
@click.option("--format", "out_format", type=click.Choice(["bin", "c"]), default="bin",
              show_default=True, help="bin: the container; c: the container as C source "
              "(an array and a <NAME>_PI_SIZE define).")
@click.option("--c-name", metavar="NAME", help="c: name of the array (default: the input's "
              "base name).")
@click.option("--c-decl", metavar="DECL", default="const unsigned char", show_default=True,
              help="c: the declaration before the array's name, e.g. 'static CONST BYTE ROM'.")
@guarded
def compile_cmd(input, output, node_id, select_, pdo_sequence, static_od, no_process_image,
                pi_align, pi_size, address_base, container_version, allow_external_files,
                profile, append, no_target_check, no_limit_check, tx_cobs, rx_cobs, granularity,
                no_bit_mapping, from_, quiet, verbose, out_format, c_name, c_decl):
    """Compile a DCF/EDS file (or a lossless JSON dump) into a binary container."""
    from dcf2bin.compiler import CompileOptions, compile_path
    data_in = read_input(input)
    if output is None:
        if input == "-":
            fail("reading stdin needs -o OUTPUT (or -o - for stdout)", code=ExitCode.USAGE)
        output = os.path.splitext(input)[0] + (".c" if out_format == "c" else ".bin")
    write = _writer(out_format, c_name, c_decl, input)
    fmt = from_ or ("json" if input.lower().endswith(".json") else "dcf")
    name = "<stdin>" if input == "-" else input
    if fmt == "json":
        from dcf2bin.dump import from_json_bytes
        data, diags = from_json_bytes(data_in, name)
        emit(diags, quiet)
        if data is None:
            raise Failure(ExitCode.FINDINGS)
        write(data, output, [input])
        return
    opts = CompileOptions(node_id=node_id, select=select_, pdo_sequence=pdo_sequence,
                          static_od=static_od, process_image=not no_process_image,
                          pi_align=int(pi_align), pi_size=pi_size, address_base=address_base,
                          container_version=container_version,
                          allow_external_files=allow_external_files, profile=profile,
                          append=tuple(append),
                          target_check="warning" if no_target_check else "error",
                          limit_check="warning" if no_limit_check else "error",
                          tx_cobs=tx_cobs, rx_cobs=rx_cobs, granularity=int(granularity),
                          bit_mapping=not no_bit_mapping)
    for path in (static_od, *append):
        check_input(path)  # missing, a directory, unreadable: exit 3 like any input
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

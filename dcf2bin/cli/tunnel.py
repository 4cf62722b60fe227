"""dcf2bin tunnel: extra-writes files for the Metronix DIS-2 communication-object tunnel.

    dcf2bin tunnel KO=VALUE ... [--read KO ...] [-o FILE.writes]
"""
from __future__ import annotations

import os

import click

from dcf2bin.cli.common import (CONTEXT, debug_option, guarded, output_option, quiet_option,
                                write_output)
from dcf2bin.diagnostics import shorten


def _int(text: str, what: str, hint: str) -> int:
    from dcf2bin import values
    try:
        return values.parse_int(text)
    except values.ValueProblem as exc:
        raise click.BadParameter(f"{what} '{shorten(text)}': {exc}", param_hint=hint) from None


@click.command("tunnel", context_settings=CONTEXT)
@click.argument("assignments", nargs=-1, metavar="[KO=VALUE]...")
@click.option("-r", "--read", "reads", multiple=True, metavar="KO",
              help="Select KO for reading through 0x2204 (repeatable; the last one stays "
                   "selected).")
@click.option("--read-mode", type=click.Choice(["value", "min", "max"]), default="value",
              show_default=True, help="What 0x2204 returns for --read: the current value, "
                                      "the lower or the upper limit.")
@output_option("Default: standard output.")
@quiet_option("No line that counts the writes.")
@debug_option
@guarded
def tunnel_cmd(assignments, reads, read_mode, output, quiet, debug):
    """Write an extra-writes file for the Metronix DIS-2 communication-object tunnel.

    Each KO=VALUE writes 0x2200 sub 0 := KO (select the communication object), then
    0x2214 sub 0 := VALUE (32 bits). Each --read KO writes 0x2200 sub 0 := KO so that an
    SDO upload of 0x2204 sub 0 returns it. Numbers take the DCF forms (12, 0x1A, 012).
    Append the file with: dcf2bin compile DRIVE.dcf --profile dis2 --append FILE
    """
    from dcf2bin.writes import READ_MODES, tunnel_writes
    if not assignments and not reads:
        raise click.UsageError("give at least one KO=VALUE or --read KO")
    pairs = []
    for a in assignments:
        ko_text, sep, value_text = a.partition("=")
        if not sep or not ko_text.strip() or not value_text.strip():
            raise click.BadParameter(f"'{shorten(a)}' is not KO=VALUE", param_hint="KO=VALUE")
        ko = _int(ko_text, "KO number", "KO=VALUE")
        value = _int(value_text, "value", "KO=VALUE")
        if not 0 <= ko <= 0xFFFF:
            raise click.BadParameter(f"KO number {ko_text} is outside 0..0xFFFF",
                                     param_hint="KO=VALUE")
        if not -0x80000000 <= value <= 0xFFFFFFFF:
            raise click.BadParameter(f"value {value_text} does not fit 32 bits",
                                     param_hint="KO=VALUE")
        pairs.append((ko, value))
    read_kos = []
    for r in reads:
        ko = _int(r, "KO number", "--read")
        if not 0 <= ko <= 0xFFFF:
            raise click.BadParameter(f"KO number {r} is outside 0..0xFFFF", param_hint="--read")
        read_kos.append(ko)
    words = ["dcf2bin tunnel"] + [f"0x{k:04X}=0x{v & 0xFFFFFFFF:08X}" for k, v in pairs]
    words += [f"--read 0x{k:04X}" for k in read_kos]
    if read_mode != "value" and read_kos:
        words.append(f"--read-mode {read_mode}")
    text = tunnel_writes(pairs, read_kos, read_mode=READ_MODES[read_mode],
                         source=" ".join(words))
    write_output(text, output, [], binary=False)
    if output != "-" and not quiet:
        n = 2 * len(pairs) + len(read_kos)
        click.echo(f"{os.path.basename(output)}: {n} write{'s' if n != 1 else ''}", err=True)

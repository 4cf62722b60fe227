"""Shared pieces of the command line: exiting, reading inputs, writing outputs.

Every command module of this package uses these, so errors look and exit the same
everywhere. Only click is imported here.
"""
from __future__ import annotations

import functools
import os
import sys
import tempfile

import click

from dcf2bin.diagnostics import Diagnostic, ExitCode, Severity

CONTEXT = dict(help_option_names=["-h", "--help"], max_content_width=100)


class Failure(Exception):
    """End the command with diagnostics already printed and this exit code."""

    def __init__(self, code: ExitCode):
        self.code = code


def emit(diags, quiet: bool = False) -> None:
    from dcf2bin.report import render_text
    shown = [d for d in diags if not (quiet and d.severity is not Severity.ERROR)]
    render_text(shown, sys.stderr, hints=True)


def fail(message: str, where: str = "", code: ExitCode = ExitCode.FINDINGS):
    emit([Diagnostic(Severity.ERROR, message, where or "dcf2bin")])
    raise Failure(code)


def guarded(fn):
    """Turn Failure into its exit code and any bug into one line plus exit 70."""
    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        ctx = click.get_current_context()
        debug = (ctx.find_root().params or {}).get("debug", False) or ctx.params.get("debug")
        try:
            return fn(*args, **kwargs)
        except Failure as f:
            ctx.exit(int(f.code))
        except (click.exceptions.Exit, click.ClickException, click.Abort):
            raise
        except KeyboardInterrupt:
            click.echo("dcf2bin: interrupted", err=True)
            ctx.exit(130)
        except BrokenPipeError:
            ctx.exit(int(ExitCode.OK))
        except Exception as exc:  # a bug: never a traceback unless asked
            if debug or os.environ.get("DCF2BIN_DEBUG"):
                raise
            click.echo(f"dcf2bin: internal error: {type(exc).__name__}: {exc} "
                       "(run with --debug for the traceback, and please report it)", err=True)
            ctx.exit(int(ExitCode.INTERNAL))
    return wrapper


def read_input(path: str) -> bytes:
    """Read a file or '-' (stdin); an unreadable input ends with exit 3."""
    try:
        if path == "-":
            return sys.stdin.buffer.read()
        with open(path, "rb") as f:
            return f.read()
    except OSError as exc:
        fail(f"cannot read: {exc.strerror}", path, ExitCode.UNREADABLE)


def write_output(data: bytes | str, output: str, inputs: list[str], *, binary: bool) -> None:
    """Write atomically (temp file + rename); never over an input; no binary to a terminal."""
    if isinstance(data, str):
        data = data.encode("utf-8")
    if output == "-":
        if binary and sys.stdout.isatty():
            fail("refusing to write binary data to a terminal; use -o FILE or a pipe",
                  code=ExitCode.USAGE)
        sys.stdout.buffer.write(data)
        sys.stdout.buffer.flush()
        return
    out_abs = os.path.realpath(output)
    for inp in inputs:
        if inp != "-" and os.path.exists(inp) and os.path.realpath(inp) == out_abs:
            fail(f"output '{output}' is the input file; refusing to overwrite it",
                  code=ExitCode.USAGE)
    folder = os.path.dirname(out_abs) or "."
    try:
        fd, tmp = tempfile.mkstemp(prefix=".dcf2bin-", suffix=".tmp", dir=folder)
    except OSError as exc:
        fail(f"cannot write: {exc.strerror}", output, ExitCode.UNREADABLE)
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.replace(tmp, output)
    except OSError as exc:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        fail(f"cannot write: {exc.strerror}", output, ExitCode.UNREADABLE)


def read_container(path: str, quiet: bool):
    """Read and decode a container; a bad one ends with one line naming the byte offset."""
    from dcf2bin.dump import read_bytes
    data = read_input(path)
    name = "<stdin>" if path == "-" else path
    c, diags = read_bytes(data, name)
    emit(diags, quiet)
    if c is None:
        raise Failure(ExitCode.FINDINGS)
    return c, name


def read_eds(path: str | None, quiet: bool):
    if path is None:
        return None, None
    from dcf2bin.dump import load_eds
    data = read_input(path)
    info, dev, errors = load_eds(path, data)
    if errors:
        emit([Diagnostic(Severity.WARNING, f"the EDS has {errors} error"
                         f"{'s' if errors != 1 else ''} (see 'dcf2bin validate'); types and "
                         "names are taken where they could be read", path)], quiet)
    return info, dev

"""Shared pieces of the command line: exiting, the option vocabulary, and the thin layer
over ``dcf2bin.fileio`` that turns its errors into one ``file: error:`` line and an exit
code (``read_input``, ``check_output``, ``write_output``, ``guarded``).

Every command module of this package uses these, so errors look and exit the same
everywhere. Only click is imported here at module level.
"""
from __future__ import annotations

import functools
import gc
import importlib
import io
import os
import re
import signal
import sys

import click

from dcf2bin import argspec
from dcf2bin.diagnostics import Diagnostic, ExitCode, Severity, bounded, shorten

CONTEXT = dict(help_option_names=["-h", "--help"], max_content_width=100)


class _SafeMain:
    """click's own output (--help, --version, usage errors) into a full disk: one line and
    exit 3, like any output; into a closed pipe: the code click chose, quietly."""

    def main(self, *args, **kwargs):
        try:
            return super().main(*args, **kwargs)
        except OSError as exc:
            _silence(1)
            say(f"<stdout>: error: cannot write: {exc.strerror or exc}")
            sys.exit(int(ExitCode.UNREADABLE))


class Group(_SafeMain, click.Group):
    """The program's click group (``cls=Group``)."""


class LazyGroup(Group):
    """A group that imports a command's module only when that command is run or asked
    for (``lazy``: name -> ``"module:attribute"``), so that running one command imports
    neither the other commands nor what they import. ``list_commands`` names them all
    without importing any; reading ``commands`` (help's listing, introspection, the tests)
    imports every one."""

    def __init__(self, *args, lazy: dict[str, str] | None = None, **kwargs):
        self._lazy = dict(lazy or {})
        super().__init__(*args, **kwargs)

    @property
    def commands(self) -> dict:
        for name in self.list_commands(None):
            self.get_command(None, name)
        return self._commands

    @commands.setter
    def commands(self, value) -> None:
        self._commands = dict(value or {})

    def list_commands(self, ctx) -> list[str]:
        return sorted(set(self._commands) | set(self._lazy))

    def get_command(self, ctx, name: str):
        if name not in self._commands:
            if name not in self.list_commands(ctx):
                return None
            module, _, attr = self._lazy[name].partition(":")
            self._commands[name] = getattr(importlib.import_module(module), attr)
        return self._commands[name]


class Command(_SafeMain, click.Command):
    """A command that is a program of its own, such as ``bin2dcf`` (``cls=Command``)."""


class Failure(Exception):
    """End the command with diagnostics already printed and this exit code."""

    def __init__(self, code: ExitCode):
        self.code = code


class _State:
    """What this invocation did so far (reset by ``guarded``)."""
    inputs: list[str] = []          # every input read or registered: never overwritten
    errors_emitted = False          # an error diagnostic was printed (a broken pipe's code)


def _reset() -> None:
    _State.inputs = []
    _State.errors_emitted = False


def register_input(path: str | None) -> None:
    """Name a file this command reads, so that no output is ever written over it."""
    if path and path != "-":
        _State.inputs.append(path)


def registered_inputs() -> list[str]:
    """Every input this run has read or registered so far."""
    return list(_State.inputs)


def _silence(fd: int) -> None:
    """After EPIPE or an error on a standard stream, point it at /dev/null so that later
    writes and the interpreter's final flush cannot fail again (the Python docs' advice
    for SIGPIPE). Only when the stream really is that descriptor (not a test's capture)."""
    stream = sys.stdout if fd == 1 else sys.stderr
    try:
        if stream is None or stream.fileno() != fd:
            return      # closed at start: the descriptor may be one of our own files now
    except (OSError, ValueError, AttributeError):
        return
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, fd)
        os.close(devnull)
    except OSError:
        pass


def _write_stderr(text: str) -> None:
    stream = sys.stderr
    if stream is None:           # started with standard error closed
        return
    try:
        stream.write(text)
        stream.flush()
    except (OSError, ValueError):
        # a reader that went away (2>&1 | head) or a full disk: diagnostics are lost, but
        # the run goes on and ends with the exit code it earned
        _silence(2)


def say(message: str) -> None:
    """One line to standard error (status lines such as 'nothing written'), bounded as
    every diagnostic is (an exception's text may quote an input)."""
    _write_stderr(bounded(message) + "\n")


def emit(diags, quiet: bool = False) -> None:
    """Print diagnostics on standard error in the one text form of report.py; -q keeps the
    errors only."""
    diags = list(diags)
    if any(d.severity is Severity.ERROR for d in diags):
        _State.errors_emitted = True
    shown = [d for d in diags if not (quiet and d.severity is not Severity.ERROR)]
    if not shown or sys.stderr is None:
        return
    from dcf2bin.report import render_text     # not imported by a run that prints nothing
    buf = io.StringIO()
    render_text(shown, buf, hints=True, colour=_colour(sys.stderr))
    _write_stderr(buf.getvalue())


def _colour(stream) -> bool:
    from dcf2bin.report import use_colour
    try:
        return use_colour(stream)
    except (OSError, ValueError):
        return False


def fail(message: str, where: str = "", code: ExitCode = ExitCode.FINDINGS, rule: str = ""):
    emit([Diagnostic(Severity.ERROR, message, where or "dcf2bin", rule=rule)])
    raise Failure(code)


def stop_on_errors(res, name: str, outcome: str) -> None:
    """After ``res``'s diagnostics are printed: when it failed, one line counts its errors
    and says what the command does not do (``outcome``), and the command ends (exit 1)."""
    if res.ok:
        return
    n = sum(d.weight for d in res.diagnostics if d.severity is Severity.ERROR)
    click.echo(f"{name}: {n} error{'s' if n != 1 else ''}, {outcome}", err=True)
    raise Failure(ExitCode.FINDINGS)


def _earned() -> int:
    return int(ExitCode.FINDINGS if _State.errors_emitted else ExitCode.OK)


def guarded(fn):
    """Turn Failure into its exit code and any bug into one line plus exit 70.

    A broken pipe never hides a failure: the run ends with the code it had earned so far
    (1 once an error was reported). A caught signal ends with 128 + its number, after the
    temporary output files are removed (``fileio.signals``)."""
    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        from dcf2bin.fileio.signals import Interrupted, temporaries
        ctx = click.get_current_context()
        debug = (ctx.find_root().params or {}).get("debug", False) or ctx.params.get("debug")
        _reset()
        try:
            return fn(*args, **kwargs)
        except Failure as f:
            ctx.exit(int(f.code))
        except (click.exceptions.Exit, click.ClickException, click.Abort):
            raise
        except KeyboardInterrupt:
            temporaries.remove_all()
            say("dcf2bin: interrupted")
            ctx.exit(128 + signal.SIGINT)
        except Interrupted as sig:
            temporaries.remove_all()
            say(f"dcf2bin: stopped by signal {signal.Signals(sig.signum).name}")
            ctx.exit(128 + sig.signum)
        except BrokenPipeError:
            # a write outside write_output/emit met a closed pipe (say, click.echo)
            _silence(1)
            _silence(2)
            ctx.exit(_earned())
        except Exception as exc:  # a bug: never a traceback unless asked
            if debug or os.environ.get("DCF2BIN_DEBUG"):
                raise
            say(f"dcf2bin: internal error: {type(exc).__name__}: {exc} "
                "(run with --debug for the traceback, and please report it)")
            ctx.exit(int(ExitCode.INTERNAL))
        finally:
            temporaries.remove_all()
            _reset()
    return wrapper


def without_cyclic_gc(fn):
    """Run a command that builds a large model with the cyclic garbage collector off, and
    turn it back on only after the command has returned (its locals, the model and the
    result, are freed by then). Put it under ``guarded``.

    ``compile_path`` turns the collector off for its own run and back on at its end; the
    next allocation then started a collection that scanned every object the result still
    held (about 250,000 for 60,000 variables: 27 ms), although the command was about to
    drop them all, and none is in a cycle worth collecting."""
    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        was_enabled = gc.isenabled()
        gc.disable()
        try:
            return fn(*args, **kwargs)
        finally:
            if was_enabled:
                gc.enable()
    return wrapper


def read_input(path: str) -> bytes:
    """Read a file or '-' (stdin) through the one bounded reader (``fileio.read_file``: a
    regular file or an open descriptor, at most 64 MiB); an unreadable input (missing, a
    directory, a FIFO or a device, too large, no permission) ends with exit 3. The file is
    registered as an input: no output of this run may overwrite it."""
    from dcf2bin.fileio import read_file, read_stream
    register_input(path)
    try:
        if path == "-":
            if sys.stdin is None or getattr(sys.stdin, "buffer", None) is None:
                fail("cannot read: standard input is closed", "<stdin>", ExitCode.UNREADABLE,
                     rule="IO001")
            return read_stream(sys.stdin.buffer, "<stdin>")
        return read_file(path)
    except OSError as exc:
        # IO001, as validate and the network commands name an unreadable input
        fail(f"cannot read: {exc.strerror or exc}", "<stdin>" if path == "-" else path,
             ExitCode.UNREADABLE, rule="IO001")


def check_input(path: str | None) -> None:
    """An input file that a command hands on by name (--static-od, --append, --eds):
    missing, a directory or unreadable is exit 3 like the main input, not a usage error."""
    if path is not None and path != "-":
        read_input(path)


def check_output(path: str, inputs=(), *, binary: bool = False) -> None:
    """Say before any slow work (a bus scan, a download) whether ``path`` can be written:
    '' is a usage error (exit 2), so is an output over an input; a directory there, a
    missing or read-only folder, a closed standard output is exit 3. write_output checks
    the same again when it writes."""
    from dcf2bin.fileio import writing
    if path == "":
        fail("-o: an empty name is not a file (use '-' for standard output)",
             code=ExitCode.USAGE)
    if path == "-":
        stream = sys.stdout
        if stream is None or getattr(stream, "buffer", None) is None:
            fail("cannot write: standard output is closed", "<stdout>", ExitCode.UNREADABLE)
        if binary and _isatty(stream):
            fail("refusing to write binary data to a terminal; use -o FILE or a pipe",
                 code=ExitCode.USAGE)
        return
    try:
        writing.check_output(path, list(inputs) + _State.inputs)
    except writing.OutputIsInput as exc:
        fail(exc.reason, path, ExitCode.USAGE)
    except OSError as exc:
        fail(f"cannot write: {exc.strerror or exc}", path, ExitCode.UNREADABLE)


def _isatty(stream) -> bool:
    try:
        return stream.isatty()
    except (OSError, ValueError, AttributeError):
        return False


def _write_stdout(data: bytes, binary: bool) -> None:
    stream = sys.stdout
    if stream is None or getattr(stream, "buffer", None) is None:
        fail("cannot write: standard output is closed", "<stdout>", ExitCode.UNREADABLE)
    try:
        if binary and stream.isatty():
            fail("refusing to write binary data to a terminal; use -o FILE or a pipe",
                 code=ExitCode.USAGE)
        stream.flush()
        stream.buffer.write(data)
        stream.buffer.flush()
    except BrokenPipeError:
        _silence(1)        # the reader went away (| head): not a failure of this run
    except (OSError, ValueError) as exc:
        _silence(1)
        reason = getattr(exc, "strerror", None) or "standard output is closed"
        fail(f"cannot write: {reason}", "<stdout>", ExitCode.UNREADABLE)


def write_output(data: bytes | str, output: str, inputs: list[str], *, binary: bool) -> None:
    """Write an output file, the one way every command does it (``fileio.write_file``):
    '-' is standard output (binary data refused on a terminal; a reader that goes away is
    not an error, a full disk or a closed stdout is exit 3); a file is written atomically,
    never over an input (``inputs`` and every file read through read_input or named with
    register_input: exit 2); a device or FIFO directly. SIGTERM, SIGHUP or SIGINT while it
    is written removes the temporary file and ends the run with 128 + N."""
    from dcf2bin.fileio import signals, writing
    if isinstance(data, str):
        data = data.encode("utf-8", "surrogateescape")
    if output == "-":
        _write_stdout(data, binary)
        return
    if output == "":
        check_output(output)
    try:
        with signals.raising():
            writing.write_file(output, data, list(inputs) + _State.inputs)
    except writing.OutputIsInput as exc:
        fail(exc.reason, output, ExitCode.USAGE)
    except OSError as exc:
        fail(f"cannot write: {exc.strerror or exc}", output, ExitCode.UNREADABLE)


def read_container(path: str, quiet: bool, *, json_ok: bool = False, use=None):
    """Read and decode a container (``json_ok``: or its JSON form); a bad one ends with one
    line naming the byte offset, a file of another kind with one naming its command."""
    data = read_input(path)
    name = "<stdin>" if path == "-" else path
    kind = input_kind(path, data, ("bin", "json") if json_ok else ("bin",), quiet=quiet,
                      use=use)
    return decode_container(data, name, quiet, json_input=kind == "json"), name


def decode_container(data: bytes, name: str, quiet: bool, *, json_input: bool = False):
    """Decode a container (``json_input``: a ``dump --format json`` document first);
    its diagnostics are printed, and one that cannot be read ends the command (exit 1)."""
    from dcf2bin.dump import from_json_bytes, read_bytes
    if json_input:
        data, diags = from_json_bytes(data, name)
        emit(diags, quiet)
        if data is None:
            raise Failure(ExitCode.FINDINGS)
    c, diags = read_bytes(data, name)
    emit(diags, quiet)
    if c is None:
        raise Failure(ExitCode.FINDINGS)
    return c


def read_binary(path: str, quiet: bool, *, use=None):
    """Read a container or a concise DCF, each by its content: ``(kind, what, name)`` with
    ``kind`` "bin" and a container, or "concise" and the concise DCF's entries; a bad one
    ends with one line naming the byte offset, a file of another kind with one naming its
    command."""
    data = read_input(path)
    name = "<stdin>" if path == "-" else path
    kind = input_kind(path, data, ("bin", "concise"), quiet=quiet, use=use)
    if kind == "concise":
        return kind, decode_concise(data, name, quiet), name
    return kind, decode_container(data, name, quiet), name


def decode_concise(data: bytes, name: str, quiet: bool):
    """A concise DCF's entries; its one error (an entry past the end, a count that
    disagrees, ...) is printed and ends the command (exit 1)."""
    from dcf2bin.concise import read_concise
    entries, diags = read_concise(data, name)
    emit(diags, quiet)
    if entries is None:
        raise Failure(ExitCode.FINDINGS)
    return entries


def read_eds(path: str | None, quiet: bool):
    if path is None:
        return None, None
    from dcf2bin.dump import eds_warnings, load_eds
    data = read_input(path)
    input_kind(path, data, ("dcf", "xdd"), quiet=quiet,
               use="--eds takes the device's EDS or DCF")
    info, dev, errors = load_eds(path, data)
    emit(eds_warnings(path, errors), quiet)
    return info, dev


# -- one vocabulary of options (issue 19) -------------------------------------------------------
#
# Every command takes its shared options from here, so that a name, its short form, its value
# syntax and the first sentence of its help are the same wherever it appears (a test walks
# every command's parameters and checks). A command may add a sentence after the shared one.

class Integer(click.ParamType):
    """An integer option written as a DCF value is written: decimal, 0x hex or octal with a
    leading 0 (the DCF reader's own syntax, ``values.parse_int``), checked against
    ``min``..``max`` or a ``spec`` of dcf2bin.argspec (the API's words; click's IntRange
    wording)."""
    name = "integer"

    def __init__(self, min: int | None = None, max: int | None = None, *,
                 spec: argspec.Range | None = None):
        self.spec = spec or argspec.Range(min, max)
        self.min, self.max = self.spec.min, self.spec.max

    def convert(self, value, param, ctx):
        if isinstance(value, int) and not isinstance(value, bool):
            n = value
        else:
            from dcf2bin import values
            try:
                n = values.parse_int(str(value))
            except values.ValueProblem as exc:
                self.fail(f"'{values.shorten(str(value))}' is not an integer ({exc}; decimal, 0x hex or 0 octal "
                          "as in a DCF)", param, ctx)
        problem = self.spec.problem(n, str(value))
        if problem:
            self.fail(problem, param, ctx)
        return n

    def __repr__(self) -> str:
        return f"Integer({self.min}, {self.max})"


class Choice(click.Choice):
    """One of the values of a dcf2bin.argspec ``Choice``, returned as the spec's type ('8'
    -> 8), a wrong one worded as the API words it."""

    def __init__(self, spec: argspec.Choice):
        self.spec = spec
        super().__init__([str(v) for v in spec.values])

    def convert(self, value, param, ctx):
        if self.spec.type_problem(value) is None and value in self.spec.values:
            return value
        return self.spec.parse(super().convert(value, param, ctx))

    def get_invalid_choice_message(self, value, ctx) -> str:
        return self.spec.problem(self.spec.parse(value))


class Number(click.FloatRange):
    """A number in the range of a dcf2bin.argspec float ``Range``."""

    def __init__(self, spec: argspec.Range):
        self.spec = spec
        super().__init__(spec.min, spec.max)


NODE_ID = Integer(spec=argspec.NODE_ID)
COUNT = Integer(spec=argspec.COUNT)


_DECIMAL = re.compile(r"([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?")


class Seconds(click.ParamType):
    """A time in seconds, written as a decimal number (``0.3``, ``2``, ``1.5e-3``), at least
    ``min`` and at most ``max`` (a day: longer is a typo, and would overflow a timer);
    hex, ``inf`` and ``nan`` are refused, saying what a time accepts."""
    name = "seconds"

    def __init__(self, min: float = 0.0, max: float = 86400.0):
        self.min, self.max = min, max

    def convert(self, value, param, ctx):
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            t = float(value)
        else:
            text = str(value).strip()
            if len(text) > 40 or not _DECIMAL.fullmatch(text):
                self.fail(f"'{shorten(str(value))}' is not a time in seconds (a decimal "
                          "number such as 0.5 or 2)", param, ctx)
            t = float(text)
        if not self.min <= t <= self.max:
            self.fail(f"{shorten(str(value))} is not in the range "
                      f"{self.min:g}<=x<={self.max:g} seconds", param, ctx)
        return t

    def __repr__(self) -> str:
        return f"Seconds({self.min}, {self.max})"


class OutputPath(click.Path):
    """-o's value: a path, '-' for standard output where ``allow_dash``; an empty name is a
    usage error here, before any work, not a file that cannot be written."""

    def convert(self, value, param, ctx):
        if isinstance(value, str) and value == "":
            self.fail("an empty name is not a file (use '-' for standard output)"
                      if self.allow_dash else "an empty name is not a folder (use '.' for "
                      "this one)", param, ctx)
        return super().convert(value, param, ctx)


class Option(click.Option):
    """A click option with hidden alias names (``hidden_names``): accepted on the command
    line so that old scripts keep running, left out of --help and the man pages."""

    def __init__(self, *args, hidden_names: tuple[str, ...] = (), **kwargs):
        super().__init__(*args, **kwargs)
        self.hidden_names = tuple(hidden_names)

    def get_help_record(self, ctx):
        saved = self.opts
        self.opts = [o for o in saved if o not in self.hidden_names]
        try:
            return super().get_help_record(ctx)
        finally:
            self.opts = saved

    def get_error_hint(self, ctx) -> str:
        return " / ".join(f"'{o}'" for o in self.shown_names())

    def shown_names(self) -> list[str]:
        return [o for o in self.opts + self.secondary_opts if o not in self.hidden_names]


#: The first sentence of each shared option's help, word for word in every command.
SHARED_HELP = {
    "node_id": "Node-ID, 1..127.",
    "quiet": "Print errors only.",
    "verbose": "Print more about what was done:",
    "debug": "Show a traceback for internal errors.",
    "output": "Output file ('-' for standard output).",
    "format": "Output format:",
    "entries": "Which entries compile writes: auto = configured entries (ParameterValue "
               "or DownloadFile); all = every entry that has a value, DefaultValue included.",
    "static_od": "EDS of the objects the target's firmware already has (its static OD); "
                 "it must read without errors.",
    "force": "Replace an existing file at the default output name.",
    "from_": "Input kind (default: by its content; by the name's suffix where the content is "
             "not clear).",
    "select": "Check only these rules: codes, code prefixes (DCF4, CNT, NET2), names, or ALL; "
              "comma-separated or repeated.",
    "ignore": "Skip these rules (codes, code prefixes or names).",
    "strict": "Warnings fail the run too (exit 1).",
}

#: --eds of dump, bin2dcf and validate (map's says what map takes it for)
EDS_HELP = "EDS/DCF of the device: exact data types, access and names."


def _help(key: str, more: str = "") -> str:
    return SHARED_HELP[key] + (" " + more if more else "")


def node_id_option(more: str = "", required: bool = False):
    """-n/--node-id N (--node is a hidden alias: download's old name)."""
    return click.option("-n", "--node-id", "--node", "node_id", cls=Option,
                        hidden_names=("--node",), type=NODE_ID, metavar="N",
                        required=required, help=_help("node_id", more))


def rule_options(fn):
    """--select/--ignore RULES and --strict, as validate and network check read them."""
    fn = click.option("--strict", is_flag=True, help=_help("strict"))(fn)
    fn = click.option("--ignore", multiple=True, metavar="RULES", help=_help("ignore"))(fn)
    return click.option("--select", "select_", multiple=True, metavar="RULES",
                        help=_help("select"))(fn)


def lint_report(fmt: str, diags, files, rules, code, *, output: str, quiet: bool,
                hints: bool, read: int) -> str:
    """validate's and network check's report in one of their formats: ``files`` is the
    (path, kind) list the JSON names, ``read`` the count the text summary gives."""
    from dcf2bin import __version__, report
    table = {r.id: r.as_dict() for r in rules}
    if fmt == "json":
        return report.json_report(diags, files, table, exit_code=int(code),
                                  tool_version=__version__)
    if fmt == "sarif":
        return report.sarif_report(diags, [r.as_dict() for r in rules], exit_code=int(code),
                                   tool_version=__version__)
    if fmt == "github":
        return report.github_report(diags, table)
    colour = output == "-" and report.use_colour(sys.stdout)
    shown = [d for d in diags if not quiet or d.severity is Severity.ERROR]
    return report.text_report(shown, read, colour=colour, hints=hints, show_summary=not quiet)


def quiet_option(more: str = ""):
    return click.option("-q", "--quiet", is_flag=True, help=_help("quiet", more))


def verbose_option(more: str):
    return click.option("-v", "--verbose", is_flag=True, help=_help("verbose", more))


def debug_option(fn):
    return click.option("--debug", is_flag=True, help=_help("debug"))(fn)


def output_option(more: str = "", default: str | None = "-"):
    extra = {} if default is None else {"default": default}
    return click.option("-o", "--output", type=OutputPath(allow_dash=True), metavar="FILE",
                        help=_help("output", more), **extra)


def format_option(choices, default: str | None, more: str, required: bool = False):
    extra = {} if default is None else {"default": default, "show_default": True}
    return click.option("-f", "--format", "fmt", type=click.Choice(list(choices)),
                        required=required, help=_help("format", more), **extra)


def entries_option(more: str = ""):
    """--entries auto|all (--select is its hidden old name on compile, simulate and map;
    validate's --select names rules)."""
    return click.option("--entries", "--select", "entries", cls=Option,
                        hidden_names=("--select",), type=Choice(argspec.ENTRIES),
                        default="auto", show_default=True, help=_help("entries", more))


def static_od_option(more: str = ""):
    return click.option("--static-od", type=click.Path(), metavar="EDS",
                        help=_help("static_od", more))


def eds_option(more: str = ""):
    return click.option("--eds", type=click.Path(), metavar="EDS",
                        help=EDS_HELP + (" " + more if more else ""))


def force_option(fn):
    return click.option("--force", is_flag=True, help=_help("force"))(fn)


def from_option(choices, more: str = ""):
    return click.option("--from", "from_", type=click.Choice(list(choices)),
                        help=_help("from_", more))


# -- the kind of an input -----------------------------------------------------------------------

def input_kind(path: str, data: bytes, accepted, forced: str | None = None, *,
               quiet: bool = False, use=None) -> str:
    """The kind of an input (dcf2bin.filekind: content first). A kind the command does not
    take ends it with one sentence naming the command that does (exit 1); a name that says
    another kind than the content is a warning, and the content wins. ``--from`` (forced)
    is taken as given."""
    from dcf2bin import filekind
    if forced:
        return forced
    name = "<stdin>" if path == "-" else path
    kind = filekind.detect(data, "" if path == "-" else path)
    problem = filekind.mismatch(name, kind, accepted, use=use)
    if problem:          # not what this command reads: an input error, as a damaged file is
        fail(problem, name, ExitCode.FINDINGS)
    note = filekind.misnamed(name, kind) if path != "-" else None
    if note:
        emit([Diagnostic(Severity.WARNING, note, name)], quiet)
    return kind


def load_static_od(path: str | None, quiet: bool, outcome: str):
    """Check a --static-od file as compile checks it, the one rule of every command: it
    must be readable (exit 3), DCF/EDS text (exit 1, naming what it is) and free of the
    errors that make its object list unreliable (printed, then exit 1 with ``outcome``).
    Returns its bytes (None without --static-od)."""
    if path is None:
        return None
    data = read_input(path)
    input_kind(path, data, ("dcf", "xdd"), quiet=quiet,
               use="--static-od takes the EDS of the target's firmware")
    from dcf2bin.compiler import static_od_indexes
    _, errors = static_od_indexes(path)
    if errors:
        emit(errors, quiet)
        n = len(errors)
        click.echo(f"{path}: {n} error{'s' if n != 1 else ''} in the static OD, {outcome}",
                   err=True)
        raise Failure(ExitCode.FINDINGS)
    return data


def default_output(input: str, suffix: str, force: bool, why: str = "") -> str:
    """The output name a command makes up (INPUT with another suffix): it never replaces an
    existing file unless --force says so; an -o name is the user's and is written over.
    ``why`` says in a few words what the existing file may be."""
    if input == "-":
        fail("reading stdin needs -o OUTPUT (or -o - for stdout)", code=ExitCode.USAGE)
    output = os.path.splitext(input)[0] + suffix
    if not force and os.path.lexists(output):
        fail(f"the file exists{why}; name the output with -o to replace it, or give --force",
             output, code=ExitCode.USAGE)
    return output


def target_stack_options(fn=None, *, prefix: str = ""):
    """--tx-cobs/--rx-cobs/--granularity/--no-bit-mapping: what the target's stack was
    built with, shared by compile, validate, simulate and node (which passes
    ``prefix="With --container: "``)."""
    if fn is None:
        return lambda f: target_stack_options(f, prefix=prefix)

    def text(help: str) -> str:
        if not prefix or help[1].isupper():     # keep "TPDO", lower-case "The"
            return prefix + help
        return prefix + help[0].lower() + help[1:]
    fn = click.option("--no-bit-mapping", is_flag=True,
                      help=text("The target cannot map a BOOLEAN as 1 bit."))(fn)
    fn = click.option("--granularity", type=Choice(argspec.GRANULARITY), default="64",
                      show_default=True, help=text("The target's PDO mapping granularity in "
                                                   "bits (8: whole bytes only)."))(fn)
    fn = click.option("--rx-cobs", type=COUNT, metavar="N",
                      help=text("RPDO entries of the target's COB table "
                                "(default: unlimited)."))(fn)
    fn = click.option("--tx-cobs", type=COUNT, metavar="N",
                      help=text("TPDO entries of the target's COB table "
                                "(default: unlimited)."))(fn)
    return fn

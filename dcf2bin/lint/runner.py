"""Run the rules over files, directories and stdin; collect diagnostics; decide the exit code.

Per DCF/EDS file: read the INI text, build the model, compute the PI layout, run the
compile selection (for the errors only compile finds), then every active check. The
core's problems arrive with their own rule ids; each check runs guarded, so a bug in
one check becomes an INT001 diagnostic (exit 70) and the others still run.
"""
from __future__ import annotations

import gc
import os
import traceback
from dataclasses import dataclass, field

from dcf2bin.diagnostics import LIMIT, Diagnostic, ExitCode, Severity, summarise, summary_finding
from dcf2bin.lint import registry
from dcf2bin.lint.context import BinContext, ConciseContext, DcfContext, Options
from dcf2bin.lint.registry import BIN, CONCISE, DCF, RULES, Finding

SUFFIXES = (".eds", ".dcf", ".xdd", ".xdc", ".xpd", ".bin")
DCF_SUFFIXES = (".eds", ".dcf", ".ini")
KIND_DCF, KIND_BIN, KIND_UNREADABLE = "dcf", "container", "unreadable"
KIND_JSON, KIND_CONCISE, KIND_CONCISE_JSON = "json", "concise", "concise-json"
NOTHING_FOUND = "no *.dcf, *.eds, *.xdd, *.xdc, *.xpd or *.bin file in this directory"


@dataclass
class FileResult:
    path: str
    kind: str
    diagnostics: list[Diagnostic] = field(default_factory=list)
    tracebacks: list[str] = field(default_factory=list)

    def count(self, severity: Severity) -> int:
        return sum(d.weight for d in self.diagnostics if d.severity is severity)


@dataclass
class RunResult:
    files: list[FileResult] = field(default_factory=list)

    @property
    def diagnostics(self) -> list[Diagnostic]:
        return [d for f in self.files for d in f.diagnostics]

    @property
    def tracebacks(self) -> list[str]:
        return [t for f in self.files for t in f.tracebacks]

    def exit_code(self, strict: bool = False) -> ExitCode:
        diags = self.diagnostics
        if any(d.rule == "INT001" for d in diags):
            return ExitCode.INTERNAL
        if any(d.rule == "IO001" for d in diags):
            return ExitCode.UNREADABLE
        failing = (Severity.ERROR, Severity.WARNING) if strict else (Severity.ERROR,)
        if any(d.severity in failing for d in diags):
            return ExitCode.FINDINGS
        return ExitCode.OK


# -- inputs ----------------------------------------------------------------------------------

def discover(paths: list[str]) -> list[tuple[str, str | None]]:
    """(shown path, error or None) for every input: files as given, directories walked
    for *.eds, *.dcf, *.xdd, *.xdc, *.xpd, *.bin (any case; hidden entries skipped), '-' for
    stdin."""
    out: list[tuple[str, str | None]] = []
    for p in paths:
        if p == "-" or not os.path.isdir(p):
            out.append((p, None))
            continue
        found = []
        errors: list[OSError] = []
        for root, dirs, files in os.walk(p, onerror=errors.append):
            dirs[:] = sorted(d for d in dirs if not d.startswith("."))
            for name in sorted(files):
                if not name.startswith(".") and name.lower().endswith(SUFFIXES) \
                        and os.path.isfile(os.path.join(root, name)):  # a FIFO would block
                    found.append(os.path.join(root, name))
        out.extend((f, None) for f in sorted(found, key=lambda f: f.split(os.sep)))
        for exc in errors:
            out.append((exc.filename or p, exc.strerror or str(exc)))
        if not found and not errors:
            # a CI job pointed at the wrong folder must not pass: exit 3, like an input
            # that cannot be read
            out.append((p, NOTHING_FOUND))
    return out


def _kind_of(path: str, data: bytes) -> str:
    """The file's kind by content, as every command reads it (dcf2bin.filekind); the name
    decides only for an empty or blank file. Every description format is KIND_DCF; a kind
    validate does not check (a CSV list, a network file, an output of dcf2bin:
    filekind.KINDS) is returned as filekind names it."""
    return _lint_kind(_file_kind(path, data))


def _file_kind(path: str, data: bytes) -> str:
    from dcf2bin import filekind
    return filekind.detect(data, "" if path.startswith("<") else path)


def _lint_kind(file_kind: str) -> str:
    from dcf2bin import filekind
    if filekind.kind_of(file_kind) is not None:
        return file_kind
    return _KINDS.get(file_kind, KIND_DCF)


# filekind's kinds; the rest: KIND_DCF
_KINDS = {"bin": KIND_BIN, "json": KIND_JSON, "concise": KIND_CONCISE,
          "concise-json": KIND_CONCISE_JSON}


def run(paths: list[str], opts: Options, *, stdin: bytes | None = None,
        stdin_name: str = "<stdin>", jobs: int = 1) -> RunResult:
    """Lint every input of ``paths`` (see ``discover``); with ``jobs`` > 1 the files are
    checked in that many worker processes (``parallel``), with the same results in the
    same order."""
    result = RunResult()
    files: list[tuple[int, str]] = []          # (place in result.files, path) to lint
    for path, error in discover(paths):
        shown = stdin_name if path == "-" else path
        if error is not None:
            result.files.append(_unreadable(shown, error))
        elif path == "-":
            result.files.append(lint_bytes(shown, stdin if stdin is not None else b"", opts))
        else:
            files.append((len(result.files), path))
            result.files.append(None)  # type: ignore[arg-type]
    if jobs > 1 and len(files) > 1:
        from dcf2bin.lint.parallel import lint_paths
        done = lint_paths([(p, p) for _, p in files], opts, jobs, lint_path)
    else:
        done = [lint_path(p, p, opts) for _, p in files]
    for (at, _), res in zip(files, done):
        result.files[at] = res
    return result


def lint_path(path: str, shown: str, opts: Options) -> FileResult:
    """Read and lint the file ``path`` (named ``shown`` in the diagnostics); an unreadable
    file is one IO001 finding."""
    from dcf2bin.fileio.reading import read_file   # bounded, never a FIFO or a device
    try:
        data = read_file(path)
    except OSError as exc:
        return _unreadable(shown, exc.strerror or str(exc))
    return lint_bytes(shown, data, opts)


def _unreadable(shown: str, error: str) -> FileResult:
    rule = RULES["IO001"]
    message = error if error is NOTHING_FOUND else f"cannot read: {error}"
    return FileResult(shown, KIND_UNREADABLE, [Diagnostic(
        Severity.ERROR, message, shown, rule="IO001", hint=rule.hint)])


def lint_bytes(name: str, data: bytes, opts: Options | None = None,
               kind: str | None = None) -> FileResult:
    """Lint one input given as bytes; ``name`` is used in the diagnostics."""
    opts = opts or Options()
    file_kind = _file_kind(name, data)
    kind = kind or _lint_kind(file_kind)
    res = FileResult(name, kind)
    if kind in (KIND_JSON, KIND_CONCISE_JSON):
        res.diagnostics.append(_not_lintable(name, file_kind))
        return res
    if kind not in (KIND_DCF, KIND_BIN, KIND_CONCISE):   # another kind: one sentence
        res.kind = KIND_DCF
        res.diagnostics.append(_other_kind(name, kind))
        return res
    note = _misnamed(name, "bin" if kind == KIND_BIN else
                     "concise" if kind == KIND_CONCISE else file_kind)
    # As in a compile: a large file makes hundreds of thousands of small objects and no
    # reference cycles worth collecting; the cyclic GC would only rescan them, more often
    # the larger the file (a cost that grows faster than the file). The caller's setting
    # is restored.
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        if kind == KIND_BIN:
            _Run(res, opts).container(data)
        elif kind == KIND_CONCISE:
            _Run(res, opts).concise(data)
        else:
            _Run(res, opts).dcf(data)
    finally:
        if was_enabled:
            gc.enable()
    if note is not None and "IO002" in (opts.active if opts.active is not None else RULES):
        res.diagnostics.insert(0, note)
    return res


def lint_model(name: str, data: bytes, dev, opts: Options) -> FileResult:
    """``lint_bytes`` of a DCF/EDS whose model the caller built already from ``data``, as
    ``model.build(ini.parse_bytes(data, name), node_id=opts.node_id)`` does (network check:
    each node's file as configure read it): the same findings, without reading it twice."""
    if dev is None or _kind_of(name, data) != KIND_DCF:
        return lint_bytes(name, data, opts)
    res = FileResult(name, KIND_DCF)
    _Run(res, opts).dcf(data, dev)
    note = _misnamed(name, _file_kind(name, data))
    if note is not None and "IO002" in (opts.active if opts.active is not None else RULES):
        res.diagnostics.insert(0, note)
    return res


def _misnamed(name: str, file_kind: str) -> Diagnostic | None:
    """IO002: a file whose content is another kind than its name says (checked by content;
    ``file_kind`` is filekind's)."""
    from dcf2bin import filekind
    if name.startswith("<"):
        return None
    if file_kind not in (filekind.CONTAINER, filekind.XDD, filekind.CONCISE):
        file_kind = filekind.DCF
    text = filekind.misnamed(name, file_kind)
    if text is None:
        return None
    return Diagnostic(Severity.WARNING, text.replace("; read as", "; checked as"), name,
                      rule="IO002", hint=RULES["IO002"].hint)


def _other_kind(name: str, kind: str) -> Diagnostic:
    """A file of another kind (filekind.KINDS): what it looks like and who reads it, once
    (DCF008: not EDS/DCF text), instead of a DCF002 for each of its lines."""
    from dcf2bin import filekind
    return Diagnostic(Severity.ERROR, filekind.mismatch(
        name, kind, (filekind.DCF, filekind.CONTAINER)), name, rule="DCF008",
        hint=RULES["DCF008"].hint)


def _not_lintable(name: str, kind: str) -> Diagnostic:
    """A JSON form given to validate: what it is, and the command that makes a container
    or a concise DCF of it (DCF008: not EDS/DCF text)."""
    from dcf2bin import filekind
    what = "the concise DCF" if kind == filekind.CONCISE_JSON else "the container"
    return Diagnostic(Severity.ERROR, filekind.mismatch(
        name, kind, (filekind.DCF, filekind.CONTAINER),
        use=f"dcf2bin compile turns it back into {what}, which validate checks"),
        name, rule="DCF008", hint=RULES["DCF008"].hint)


# -- one file --------------------------------------------------------------------------------

class _Run:
    def __init__(self, res: FileResult, opts: Options):
        self.res = res
        self.opts = opts
        self.active = opts.active if opts.active is not None else set(RULES)
        self.diags: list[Diagnostic] = []     # from the checks here
        self.core: list[Diagnostic] = []      # from the reader, model, layout, selection
        # a check's findings after the first LIMIT are counted, not kept (issue 26: 5
        # million unknown keys): rule -> [count, the first of them]; and, for a rule the
        # core reports too, the lines of those (a core finding there is one of them)
        self.left: dict[str, list] = {}
        self.left_lines: dict[str, set] = {}
        self.core_rules: set[str] = set()

    # guarded execution: a bug becomes INT001, never a traceback
    def guard(self, what: str, fn, *args):
        try:
            return True, fn(*args)
        except Exception as exc:  # noqa: BLE001 - turned into a diagnostic
            self.internal_error(what, exc)
            return False, None

    def internal_error(self, what: str, exc: Exception) -> None:
        """INT001 for ``exc``, being handled (its traceback kept for --debug)."""
        self.res.tracebacks.append(f"{self.res.path}: {what}:\n{traceback.format_exc()}")
        self.diags.append(Diagnostic(
            Severity.ERROR, f"internal error in {what}: {type(exc).__name__}: {exc}",
            self.res.path, rule="INT001", hint=RULES["INT001"].hint))

    def checks(self, kind: str, ctx) -> None:
        active = self.active
        for r in registry.all_rules():
            if r.check is None or r.kind != kind or r.id not in active:
                continue
            n = len(self.diags)
            try:
                self.collect(r, r.check(ctx))
            except Exception as exc:  # noqa: BLE001 - as in guard(): INT001, no traceback
                # (not through guard: its label and closure for each of the ~60 rules
                # were a fixed cost of every file)
                del self.diags[n:]                 # as if the rule had not run
                self.left.pop(r.id, None)
                self.left_lines.pop(r.id, None)
                self.internal_error(f"rule {r.id} ({r.name})", exc)

    def collect(self, r, findings) -> None:
        """The first LIMIT findings of rule ``r`` as diagnostics, the others counted."""
        diags, to_diag = self.diags, self.to_diag
        for n, f in enumerate(findings, 1):
            if n <= LIMIT:
                diags.append(to_diag(r, f))
                continue
            left = self.left.get(r.id)
            if left is None:
                left = self.left[r.id] = [0, to_diag(r, f)]
            left[0] += 1
            if r.id in self.core_rules:
                self.left_lines.setdefault(r.id, set()).add(f.line)

    def to_diag(self, r, f: Finding) -> Diagnostic:
        return Diagnostic(r.severity, f.message, self.res.path, f.line, f.column, f.offset,
                          r.id, f.hint or r.hint)

    def dcf(self, data: bytes, dev=None) -> None:
        from dcf2bin import formats, layout, model
        from dcf2bin import select as select_mod
        from dcf2bin.profiles import get_profile
        opts, path = self.opts, self.res.path
        ok, dev = (True, dev) if dev is not None else self.guard(
            "reading the file", lambda: formats.build(
                formats.read(data, path), node_id=opts.node_id,
                allow_external_files=opts.allow_external_files))
        if not ok:
            return self.finish()
        ctx = DcfContext(path, data, opts, dev.ini, dev)
        if any(model.is_network_variable_index(i) for i in dev.objects):
            self.guard("the process-image layout", lambda: setattr(ctx, "layout", layout.compute(
                dev, align=opts.pi_align, pi_size=opts.pi_size,
                address_base=opts.address_base)))
        static = None
        if opts.static_od is not None:     # checked by the command before any file is read
            from dcf2bin.compiler import static_od_indexes
            static = static_od_indexes(opts.static_od)[0]
        ok, sel = self.guard("the compile selection", lambda: select_mod.select(
            dev, static_od=static, rules=get_profile(opts.profile).pdo_rules()))
        # the rules the core reports too (see finish), known before the checks run: but
        # DCF202's, whose check adds them as it reads each DownloadFile
        self.core_rules = {p.diagnostic.rule for p in dev.problems} | {"DCF202"}
        if ok:
            self.core_rules.update(d.rule for d in sel.errors)
        self.checks(DCF, ctx)
        # after the checks: DCF202's DownloadFile reads may add core problems
        for p in dev.problems:
            d = p.diagnostic
            self.core.append(self._core(d, d.rule or "DCF099"))
        if ok:
            for d in sel.errors:
                self.core.append(self._core(d, d.rule or "DCF099"))
        if ok and self.target_wanted() and (ctx.layout is not None or not any(
                model.is_network_variable_index(i) for i in dev.objects)):
            self.guard("the target emulation", self.target_dcf, dev, sel, ctx.layout)
        self.finish()

    def target_wanted(self) -> bool:
        return self.opts.target_check and any(r.startswith("TGT") for r in self.active)

    def target_dcf(self, dev, sel, lay) -> None:
        """TGT0xx on a DCF: the container ``compile`` would write, checked as compile checks
        it (SPEC §8.1); nothing when compile would stop on other errors first."""
        from dcf2bin import compiler
        if compiler.blocked(dev, sel):
            return
        o = self.opts
        opts = compiler.CompileOptions(
            node_id=o.node_id, pi_align=o.pi_align, pi_size=o.pi_size,
            address_base=o.address_base, allow_external_files=o.allow_external_files,
            profile=o.profile, tx_cobs=o.tx_cobs, rx_cobs=o.rx_cobs,
            granularity=o.granularity, bit_mapping=o.bit_mapping, static_od=o.static_od)
        found = compiler.target_check(dev, sel, compiler.container_of(dev, sel, lay, opts),
                                      opts)        # the cyclic GC is off: see lint_bytes
        for d in found:
            self.core.append(self._core(d, d.rule))

    def target_container(self, data: bytes) -> None:
        """TGT0xx on a container: the emulation, with the static OD of --static-od when given
        (else without one). A container the reader rejects is left to the CNT rules."""
        from dcf2bin.container import ContainerError, read
        from dcf2bin.dynod import TargetOptions, emulate
        from dcf2bin.dynod.check import message
        try:
            c, _ = read(data)
        except ContainerError:
            return
        o = self.opts
        static = None
        if o.static_od is not None:
            from dcf2bin.dynod import StaticOD
            static = StaticOD.from_eds(o.static_od)
        out = emulate(c, TargetOptions(pi_size=o.pi_size, tx_cobs=o.tx_cobs, rx_cobs=o.rx_cobs,
                                       granularity=o.granularity, bit_mapping=o.bit_mapping,
                                       address_base=o.address_base), static)
        if not out.ok:
            r = RULES[out.rule]
            self.core.append(Diagnostic(Severity.ERROR, message(out), self.res.path,
                                        offset=out.offset, rule=out.rule, hint=r.hint))

    def _core(self, d: Diagnostic, rule: str) -> Diagnostic:
        r = RULES.get(rule)
        hint = d.hint or (r.hint if r else "")
        return Diagnostic(d.severity, d.message, d.file or self.res.path, d.line, d.column,
                          d.offset, rule, hint, d.more)

    def container(self, data: bytes) -> None:
        ok, ctx = self.guard("reading the container",
                             lambda: BinContext(self.res.path, data, self.opts))
        if ok:
            self.checks(BIN, ctx)
        # a container the CNT rules already call broken is not emulated as well: the
        # target would refuse it with 0xA1, and the CNT findings say why
        broken = any(d.severity is Severity.ERROR and d.rule.startswith("CNT")
                     for d in self.diags)
        if self.target_wanted() and not broken:
            self.guard("the target emulation", self.target_container, data)
        self.finish()

    def concise(self, data: bytes) -> None:
        """A concise DCF: the reader's finding (CON001-CON004), or the checks of one that
        reads."""
        ok, ctx = self.guard("reading the concise DCF",
                             lambda: ConciseContext(self.res.path, data, self.opts))
        if ok:
            self.core.extend(self._core(d, d.rule) for d in ctx.diagnostics)
            if ctx.entries is not None:
                self.checks(CONCISE, ctx)
        self.finish()

    def finish(self) -> None:
        # A check here and the core may report one fact under one id (DCF200, DCF202,
        # DCF203: the core only for what compile encodes). Then the core's words are
        # printed, so that compile and validate say the same thing about the same line;
        # the check adds the column it knows.
        path, left_lines = self.res.path, self.left_lines
        if left_lines:     # a core finding at the line of a check's finding only counted
            self.core = [d for d in self.core if d.file != path or d.line not in
                         left_lines.get(d.rule, ())]
        core = {}
        for d in self.core:
            core.setdefault((d.rule, d.file, d.line), d)
        diags = []
        for d in self.diags:
            key = (d.rule, d.file, d.line)
            c = core.get(key)
            if c is not None and d.line is not None:
                d = Diagnostic(c.severity, c.message, d.file, d.line,
                               d.column if c.column is None else c.column, d.offset, d.rule,
                               c.hint or d.hint)
            diags.append(d)
        seen = {(d.rule, d.file, d.line) for d in self.diags}
        out, keys = [], set()
        for d in diags + [d for d in self.core if (d.rule, d.file, d.line) not in seen]:
            if d.rule not in self.active:
                continue
            key = (d.rule, d.line, d.column, d.offset, d.message)
            if key in keys:
                continue
            keys.add(key)
            out.append(d)
        out.extend(summary_finding(first, n) for n, first in self.left.values())
        out.sort(key=_order)
        # the first LIMIT of each rule, then one finding that counts the others: every
        # output format shows those, the text form 20 of them (report.CAP)
        self.res.diagnostics = summarise(out)


def _order(d: Diagnostic):
    return (d.line or 0, d.offset or 0, d.column or 0, registry._sort_key(d.rule), d.message)

"""DCF/EDS -> container: the ``compile`` job as a library call.

    >>> from dcf2bin.compiler import compile_file, compile_path, CompileOptions
    >>> data = compile_file("samples/plc.dcf")                     # doctest: +SKIP
    >>> res = compile_path("samples/plc.dcf", CompileOptions(), node_id=5)  # doctest: +SKIP

The documented API is ``dcf2bin.api`` (docs/api.md), which re-exports these.

Errors vs warnings (SPEC.md): a problem stops the build only when it touches an
entry the container writes (or the layout); problems elsewhere become warnings.
"""
from __future__ import annotations

import dataclasses
import gc
import os
import warnings
from dataclasses import dataclass, field

from dcf2bin import argspec as spec
from dcf2bin import layout as layout_mod
from dcf2bin import formats, model
from dcf2bin import select as select_mod
from dcf2bin import values
from dcf2bin.container import BinContainer
from dcf2bin.diagnostics import DcfError, Diagnostic, DiagnosticWarning, Severity, summarise


@dataclass
class CompileOptions:
    """The options of ``dcf2bin compile``, by field name (docs/compile.md, man/dcf2bin.1).

    Every field is checked as the command line checks its option (``ARGS``, from
    ``argspec``): a value of the wrong type raises TypeError, one the command would refuse
    raises ValueError in the command's words ('node_id: 200 is not in the range
    1<=x<=127'). ``dataclasses.replace`` checks the new values too."""
    node_id: int | None = None
    select: str = select_mod.AUTO
    pdo_sequence: str = select_mod.CIA301
    static_od: str | None = None              # path of the target's static OD (EDS)
    process_image: bool = True
    pi_align: int = 8
    pi_size: int | None = None
    address_base: str = "image"
    container_version: int = 1
    allow_external_files: bool = False
    profile: str = "cia301"
    append: tuple[str, ...] = ()              # extra-writes files, added after all groups
    # the DynBuildOd check of what is written (SPEC §8, D-11): "error", "warning" or "off"
    target_check: str = "error"
    tx_cobs: int | None = None
    rx_cobs: int | None = None
    granularity: int = 64
    bit_mapping: bool = True
    # a written value outside LowLimit..HighLimit (DCF212): "warning" (the default: such
    # values are often read back from the device, and vendors' limits are not always
    # right) or "error"
    limit_check: str = "warning"

    def __post_init__(self) -> None:
        spec.check_all({f.name: getattr(self, f.name) for f in dataclasses.fields(self)},
                       ARGS)
        if self.static_od is not None:
            self.static_od = os.fspath(self.static_od)
        self.append = tuple(map(os.fspath, self.append))


#: CompileOptions field -> (its spec, None allowed): the option of ``compile`` it stands for
ARGS = {
    "node_id": (spec.NODE_ID, True), "select": (spec.ENTRIES, False),
    "pdo_sequence": (spec.PDO_SEQUENCE, False), "static_od": (spec.PATH, True),
    "process_image": (spec.FLAG, False), "pi_align": (spec.PI_ALIGN, False),
    "pi_size": (spec.COUNT, True), "address_base": (spec.ADDRESS_BASE, False),
    "container_version": (spec.CONTAINER_VERSION, False),
    "allow_external_files": (spec.FLAG, False), "profile": (spec.PROFILE, False),
    "append": (spec.PATHS, False), "target_check": (spec.TARGET_CHECK, False),
    "tx_cobs": (spec.COUNT, True), "rx_cobs": (spec.COUNT, True),
    "granularity": (spec.GRANULARITY, False), "bit_mapping": (spec.FLAG, False),
    "limit_check": (spec.LIMIT_CHECK, False),
}


@dataclass
class Result:
    """What a compile made: the bytes (None when errors stop the build), every finding,
    and the model, container and process-image layout it went through."""
    data: bytes | None                      # None when errors stop the build
    diagnostics: list[Diagnostic] = field(default_factory=list)
    device: model.Device | None = None
    container: BinContainer | None = None
    layout: layout_mod.Layout | None = None
    selection: select_mod.Selection | None = None   # what the index segment writes
    extra: list = field(default_factory=list)       # the --append writes, after it

    @property
    def ok(self) -> bool:
        return self.data is not None


class CompileError(Exception):
    """Errors stopped the build; ``diagnostics`` holds every finding, ``str()`` the errors."""

    def __init__(self, diagnostics: list[Diagnostic]):
        self.diagnostics = diagnostics
        errors = [d for d in diagnostics if d.severity is Severity.ERROR]
        super().__init__("\n".join(d.format() for d in errors))


def pdo_rules(profile: str) -> select_mod.PdoRules:
    from dcf2bin.profiles import get_profile
    return get_profile(profile).pdo_rules()


def static_od_indexes(path: str) -> tuple[set[int], list[Diagnostic]]:
    """The object indexes of the target's static OD, and the errors that make that set
    unreliable (an unreadable file, broken INI syntax, repeated sections)."""
    try:
        dev = formats.load(path)
    except OSError as exc:
        return set(), [Diagnostic(Severity.ERROR, f"cannot read the static OD: {exc.strerror}",
                                  path)]
    errors = [p.diagnostic for p in dev.problems if p.diagnostic.severity is Severity.ERROR
              and p.diagnostic.rule in ("DCF001", "DCF002", "DCF003", "DCF006", "DCF010",
                                         "DCF008", "DCF056", "XDD001", "XDD002",
                                         "XDD003", "XDD004")
              and (p.diagnostic.rule != "DCF010" or p.sub is None)]
    return set(dev.objects), [
        Diagnostic(d.severity, f"static OD: {d.message}", d.file, d.line, d.column, d.offset,
                   d.rule, d.hint) for d in errors]


def compile_device(dev: model.Device, opts: CompileOptions) -> Result:
    static, static_errors = (static_od_indexes(opts.static_od) if opts.static_od
                             else (None, []))
    lay = None
    if any(model.is_network_variable_index(i) for i in dev.objects):
        lay = layout_mod.compute(dev, align=opts.pi_align, pi_size=opts.pi_size,
                                 address_base=opts.address_base)
    sel = select_mod.select(dev, policy=opts.select, pdo_sequence=opts.pdo_sequence,
                            static_od=static, rules=pdo_rules(opts.profile))
    diags: list[Diagnostic] = list(static_errors)
    for p in dev.problems:
        d = p.diagnostic
        if d.severity is Severity.ERROR and p.index is not None:
            if not sel.wrote(p.index, p.sub):
                d = Diagnostic(Severity.WARNING, d.message + " (not written by compile)",
                               d.file, d.line, d.column, d.offset, d.rule, d.hint)
        diags.append(d)
    diags.extend(sel.errors)
    # the values the container does not write: warnings, as validate words them (minus
    # what the selection already reported as an error, e.g. a DIS-2 old COB-ID, D-12)
    reported = {(d.rule, d.line) for d in sel.errors}
    for p in dev.value_problems(sel.wrote, sel.created):
        d = p.diagnostic
        if (d.rule, d.line) not in reported:
            diags.append(Diagnostic(Severity.WARNING, d.message + " (not written by compile)",
                                    d.file, d.line, d.column, d.offset, d.rule, d.hint))
    diags.extend(value_checks(dev, sel.wrote, limit_errors=opts.limit_check == "error"))
    extra = []
    for path in opts.append:
        from dcf2bin.writes import ExtraWritesError, load_extra_writes
        try:
            extra.extend(load_extra_writes(path, node_id=dev.node_id))
        except ExtraWritesError as exc:
            diags.extend(exc.diagnostics)
    if any(d.severity is Severity.ERROR for d in diags):
        return Result(None, summarise(diags), dev, None, lay)
    c = container_of(dev, sel, lay, opts, extra)
    if not c.entries:
        diags.append(_nothing_to_write(dev, opts))
    segs = c.segments()
    data = c.to_bytes(segs)
    _self_check(data, c, segs)
    found = target_check(dev, sel, c, opts, extra)
    if found:
        diags.extend(found)
        if any(d.severity is Severity.ERROR for d in found):
            return Result(None, summarise(diags), dev, None, lay)
    # the first diagnostics.LIMIT findings of a rule, then one that counts the others
    return Result(data, summarise(diags), dev, c, lay, sel, extra)


# -- LowLimit/HighLimit and 0x-prefixed hex (validate's DCF210-212, DCF218) ------------------
_LIMITS = (("lowlimit", "LowLimit"), ("highlimit", "HighLimit"))
_HEX_CODES = (0x0A, 0x0F)                                    # OCTET_STRING, DOMAIN


def value_checks(dev: model.Device, written, limit_errors: bool = False) -> list[Diagnostic]:
    """What validate says of the values beyond DCF200, in its words: a DefaultValue or
    ParameterValue outside LowLimit..HighLimit (DCF212) -- where ``written(index, sub)``
    says the entry's effective value is written, a warning (an error with
    ``limit_errors``: ``--limit-check error``), elsewhere a warning "(not written by
    compile)"; a limit that is no value of the type (DCF210) or LowLimit above HighLimit
    (DCF211), warnings (limits are never written; the check cannot be made); an
    OCTET_STRING/DOMAIN value with a 0x prefix (DCF218, a warning). Only entries with a
    limit or of those two types are looked at (one test per entry otherwise)."""
    found: dict[tuple[str, int | None], list] = {}   # (rule, line) -> [message, written]
    node_id, enc = dev.node_id, dev.encoding

    def add(rule: str, line: int | None, message: str, is_written: bool) -> None:
        old = found.get((rule, line))   # CompactSubObj: one line for N entries
        if old is None:
            found[(rule, line)] = [message, is_written]
        elif is_written:
            old[1] = True

    for obj in dev.objects.values():
        for e in obj.entries.values():
            dtype = e.dtype
            if e.low is None and e.high is None and (dtype is None or dtype.size is not None):
                continue   # the common case: no limits, a fixed-size type
            if dtype is None or e.implicit:
                continue
            texts = []
            if e.param is not None:
                texts.append(("parametervalue", "ParameterValue", e.param, True))
            if e.default is not None:
                texts.append(("defaultvalue", "DefaultValue", e.default,
                              e.param is None and e.download_file is None))
            some = written(e.index, e.sub)
            if dtype.code in _HEX_CODES:
                for key, shown, text, eff in texts:
                    if values.hex_prefix(text) and values.hex_problem(dtype, text) is None:
                        add("DCF218", e.key_where(key).line,
                            f"{e.label} {shown}: {values.hex_prefix_problem(dtype)}",
                            eff and some)
                continue
            if dtype.size is None:
                continue   # limits on a string or DOMAIN: validate's DCF217
            limits = []
            for (key, shown), text in zip(_LIMITS, (e.low, e.high)):
                number = None
                if text is not None:
                    try:
                        number = values.as_number(dtype, text, node_id, encoding=enc)
                    except values.ValueProblem as exc:
                        add("DCF210", e.key_where(key).line,
                            f"{e.label} {shown}: {values.clip(str(exc))}", some)
                limits.append(number)
            low, high = limits
            message = values.inverted_limits(e.label, e.low, low, e.high, high)
            if message is not None:
                add("DCF211", e.key_where("lowlimit").line, message, some)
                continue
            if low is None and high is None:
                continue
            for key, shown, text, eff in texts:
                try:
                    v = values.as_number(dtype, text, node_id, encoding=enc)
                except values.ValueProblem:
                    continue   # DCF200
                message = None if v is None else values.limit_problem(
                    e.label, shown, text, v, e.low, low, e.high, high)
                if message is not None:
                    add("DCF212", e.key_where(key).line, message, eff and some)
    out = []
    for (rule, line), (message, is_written) in found.items():
        hint = ""
        if not is_written:
            severity, message = Severity.WARNING, message + " (not written by compile)"
        elif rule == "DCF212" and limit_errors:
            severity, hint = Severity.ERROR, ("change the value or the limits; without "
                                              "--limit-check error this is a warning")
        elif rule == "DCF212":
            severity, hint = Severity.WARNING, ("the value is written as it is; "
                                                "--limit-check error refuses it")
        else:
            severity = Severity.WARNING
        out.append(Diagnostic(severity, message, dev.path, line, rule=rule, hint=hint))
    out.sort(key=lambda d: d.line or 0)
    return out


def container_of(dev: model.Device, sel, lay, opts: CompileOptions, extra=()) -> BinContainer:
    """The container of a selection and layout (validate builds it too, for its TGT rules)."""
    has_nv = any(model.is_network_variable_index(i) and any(s for s in o.entries)
                 for i, o in dev.objects.items())
    # extra writes (--append) come after every D-8 group and get no PI address
    c = BinContainer(entries=sel.entries + [(w.index, w.sub, w.data) for w in extra],
                     attributes=bytes(sel.attrs) + bytes(w.attr for w in extra),
                     version=opts.container_version)
    if lay is not None and has_nv and opts.process_image:
        # SPEC §3.4: index-segment order, first occurrence of each variable; that is
        # group 1, which writes each network-variable object whole, by subindex
        c.addresses = lay.addresses_of(sel.nv_objects)
        c.pi = lay.pi_parameters
    return c


def blocked(dev: model.Device, sel) -> bool:
    """Would compile stop before writing (an error that touches what it writes)?"""
    return bool(sel.errors) or any(
        p.diagnostic.severity is Severity.ERROR and (p.index is None or sel.wrote(p.index, p.sub))
        for p in dev.problems)


def target_options(opts: CompileOptions):
    from dcf2bin.dynod import TargetOptions
    return TargetOptions(pi_size=opts.pi_size, tx_cobs=opts.tx_cobs, rx_cobs=opts.rx_cobs,
                         granularity=opts.granularity, bit_mapping=opts.bit_mapping,
                         address_base=opts.address_base)


def target_check(dev: model.Device, sel, c: BinContainer, opts: CompileOptions,
                 extra=()) -> list[Diagnostic]:
    """Run the DynBuildOd emulation on the container just built (SPEC §8.1, D-11): the
    DCF's objects minus the creation group are the static OD. A failure is an error (or
    a warning with --no-target-check) at the DCF line of the offending value."""
    if opts.target_check == "off":
        return []
    from dcf2bin.dynod import check
    out = check.run(dev, sel, c, target_options(opts), list(extra))
    severity = Severity.ERROR if opts.target_check == "error" else Severity.WARNING
    return check.diagnostics(out, dev.path, severity)


def _nothing_to_write(dev: model.Device, opts: CompileOptions) -> Diagnostic:
    """The warning for a container without entries (an EDS, say, compiled as it is)."""
    if opts.select == select_mod.AUTO:
        return Diagnostic(Severity.WARNING, "nothing is configured (no ParameterValue or "
                          "DownloadFile, no network variable): the container holds no entries",
                          dev.path, rule="DCF009", hint="--entries all also writes every "
                          "DefaultValue (the device's defaults)")
    return Diagnostic(Severity.WARNING, "no entry has a value: the container holds no entries",
                      dev.path, rule="DCF009", hint="give the entries a ParameterValue")


def _self_check(data: bytes, c: BinContainer, segs: dict[str, bytes]) -> None:
    """What we wrote must read back as what we meant: header fields through the
    construct schema, every segment's size against its content. (The full
    entry-by-entry read-back is exercised by the tests, on every sample and corpus file.)"""
    from dcf2bin import schema
    h = schema.HeaderC.parse(data[:schema.HEADER_SIZE])
    expected_total = schema.HEADER_SIZE + sum(len(b) for b in segs.values())
    ok = h.total_size == len(data) == expected_total and h.version == c.version
    for name, body in segs.items():
        off, size = h[f"{name}_offset"], h[f"{name}_size"]
        ok = ok and size == len(body) and data[off:off + size] == body
    if not ok or schema.COUNT.unpack_from(data, h.index_offset)[0] != len(c.entries):
        raise AssertionError("container self-check failed: header and segments disagree")


def compile_path(path: str, opts: CompileOptions | None = None, data: bytes | None = None,
                 **options) -> Result:
    """Compile the DCF/EDS file ``path`` (or ``data``, named ``path`` in diagnostics).

    Options: a ``CompileOptions``, keyword arguments with its field names, or both
    (the keywords win). Errors and warnings are in the result's ``diagnostics``;
    ``data`` is None when errors stop the build. An unreadable file raises OSError; an
    argument the command line would refuse raises ValueError in its words, one of the
    wrong type TypeError.
    """
    spec.check("path", path, spec.PATH)
    spec.check("data", data, spec.BYTES, optional=True)
    if opts is None:
        opts = CompileOptions()
    elif not isinstance(opts, CompileOptions):
        raise TypeError(f"opts must be a CompileOptions or None, not {type(opts).__name__}")
    if options:
        opts = dataclasses.replace(opts, **options)
    path = os.fspath(path)
    if data is not None and not isinstance(data, bytes):
        data = bytes(data)
    # A compile builds hundreds of thousands of small objects and no reference cycles
    # worth collecting: the cyclic GC would only rescan them (about a third of the time
    # on a 60,000-variable file). Restore the caller's setting afterwards.
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        dev = formats.load(path, node_id=opts.node_id,
                           allow_external_files=opts.allow_external_files, data=data)
        return compile_device(dev, opts)
    finally:
        if was_enabled:
            gc.enable()


def compile_file(path: str, opts: CompileOptions | None = None, **options) -> bytes:
    """Compile and return the container bytes (options as for ``compile_path``).

    Errors raise CompileError (its ``diagnostics`` hold every finding); warnings are
    delivered through ``warnings.warn`` as ``DiagnosticWarning``s, one per finding.
    """
    res = compile_path(path, opts, **options)
    if res.data is None:
        raise CompileError(res.diagnostics)
    for d in res.diagnostics:
        warnings.warn(DiagnosticWarning(d), stacklevel=2)
    return res.data


__all__ = ["CompileOptions", "CompileError", "Result", "compile_file", "compile_path",
           "compile_device", "DcfError", "DiagnosticWarning"]

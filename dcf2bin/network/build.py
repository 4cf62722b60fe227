"""``network build`` (SPEC §10.2, D-17): the outputs of a configured network.

``<master>.dcf`` -- the PLC's file with its NodeID, the variables (as ``allocate --into``
writes them), its PDOs and NMT entries as ParameterValue, every other line as it was;
it compiles and simulates to 0x00 (tests/test_network_build.py). Per slave ``<slave>.bin``, its
configuration as a CiA 302 concise DCF, and ``<slave>.dcf``, its file with the configured
values as ParameterValue and its NodeID. The network's rules run first; nothing is made
when there is an error, there or here.
"""
from __future__ import annotations

import gc
import re
from dataclasses import dataclass, field

from dcf2bin.diagnostics import Diagnostic, Diagnostics, Severity, Where, shorten
from dcf2bin.network.model import Network

from dcf2bin.network.configuration import LELY, PLC
_BAD_NAME = re.compile(r"[/\\\x00-\x1f:*?\"<>|]")


@dataclass
class BuildResult:
    """What a build made: the configured network, every finding, and the outputs
    (file name -> bytes, in the order they are written; empty when errors stop it)."""
    network: Network
    diagnostics: list[Diagnostic] = field(default_factory=list)
    outputs: dict[str, bytes] = field(default_factory=dict)
    mode: str = PLC                    # the master built: PLC (its dcf:) or LELY (D-21)

    @property
    def ok(self) -> bool:
        return not any(d.severity is Severity.ERROR for d in self.diagnostics)


def build_network(path: str, outdir: str | None = None, *, data: bytes | None = None,
                  master: str | None = None, select=None, ignore=None) -> BuildResult:
    """Read, configure, check and build the network file ``path`` (or ``data`` named
    ``path``). ``master``: PLC or LELY forces the kind of master; by default a master
    with ``dcf:`` is a PLC, one without a lely master (D-21). With ``outdir``, the
    outputs are written there when there is no error, all or none (:func:`write_all`). A
    network file that cannot be read, or an output that cannot be written, raises OSError;
    an output over an input, ``OutputIsInput``.

    The findings are ``network check``'s (``select``/``ignore`` as there), validate's
    warnings about each node's file left out; an error of the network file, of the
    configuration or of reading a node's file stops the build whatever they say."""
    # As compile does: a build makes many small objects and no reference cycles worth
    # collecting; the cyclic GC would only rescan them (a fifth of the time at 126
    # slaves, and the cost would grow faster than the network). The caller's setting
    # is restored.
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        return _build(path, outdir, data, master, select, ignore)
    finally:
        if was_enabled:
            gc.enable()


def _build(path: str, outdir: str | None, data: bytes | None, kind: str | None = None,
           select=None, ignore=None) -> BuildResult:
    from dcf2bin.network.check import CONFIGURES, ERRORS, examine, is_cpj
    if is_cpj(path):
        res = BuildResult(Network(path, kind="cpj"))
        res.diagnostics.append(Diagnostic(
            Severity.ERROR, "build reads a YAML network file (lely's dcfgen, ros2_canopen's "
            "bus.yml): a .cpj project has no master and nothing to build (network check, "
            "show, download and scan read it)", path, rule="NET012"))
        return res
    if data is None:
        from dcf2bin.fileio import read_file
        data = read_file(path)               # the one bounded reader; OSError as promised
    checked = examine(path, select=select, ignore=ignore, data=data, lint=ERRORS,
                      binding=CONFIGURES, master=kind)
    net = checked.network
    master = net.master
    mode = kind or (PLC if master is not None and master.file is not None else LELY)
    res = BuildResult(net, list(checked.diagnostics), mode=mode)    # NET119: master_kind
    if not res.ok or master is None or not net.configured:
        return res
    out = Diagnostics()
    outputs = make_outputs(net, out, outdir or ".")
    res.diagnostics += out.items
    if not res.ok:
        return res
    res.outputs = outputs
    if outdir is not None:
        report = write_all(outdir, outputs, [path, *net.files])
        res.diagnostics += write_warnings(report, outdir)
    return res


def output_names(net: Network, diags: Diagnostics) -> dict[str, str] | None:
    """node name -> output base name; None (reported) when one cannot be a file name."""
    names: dict[str, str] = {}
    seen: dict[str, str] = {}
    ok = True
    for node in net.nodes:
        n = node.name
        if not n or n in (".", "..") or _BAD_NAME.search(n) or len(n) > 200:
            diags.error(f"node name '{shorten(n)}' cannot be an output file name", node.where,
                        rule="NET120")
            ok = False
            continue
        fold = n.casefold()
        if fold in seen:
            diags.error(f"nodes '{shorten(seen[fold])}' and '{shorten(n)}' would write the same "
                        "output files",
                        node.where, rule="NET120")
            ok = False
            continue
        seen[fold] = n
        names[n] = n
    return names if ok else None


def make_outputs(net: Network, diags: Diagnostics, outdir: str) -> dict[str, bytes]:
    from dcf2bin.network.concise import concise_dcf
    from dcf2bin.network.dcfedit import edit
    from dcf2bin.network.files import cia306
    names = output_names(net, diags)
    if names is None:
        return {}
    master = net.master
    cache: dict = {}
    if master.device is None:           # a lely master (D-21)
        from dcf2bin.network.lely import make_outputs as lely_outputs
        outputs = lely_outputs(net, names, diags)
        for s in net.slaves:            # and, unlike dcfgen, each slave's DCF (issue 29)
            dcf = slave_dcf(net, s, names, diags, cache)
            if dcf is not None:
                outputs[names[s.name] + ".dcf"] = dcf
        return outputs
    outputs: dict[str, bytes] = {}
    plc_name = names[master.name] + ".dcf"
    base, base_ini = cia306(net, master.device)
    from dcf2bin.plc.allocate import AllocationError
    try:
        plc = edit(base, master.device.path, master.settings, master.node_id, diags,
                   shown_as=plc_name, ini=base_ini, merge_plan=net.plc_plan)
    except AllocationError as exc:          # a name the PLC file's encoding cannot hold
        for d in exc.diagnostics:
            diags.error(d.message, Where(d.file, d.line), rule="NET118")
        return {}
    if plc is not None:
        outputs[plc_name] = plc
    for s in net.slaves:
        dcf = slave_dcf(net, s, names, diags, cache)
        outputs[names[s.name] + ".bin"] = concise_dcf(s)
        if dcf is not None:
            outputs[names[s.name] + ".dcf"] = dcf
    return outputs


def slave_dcf(net: Network, s, names: dict[str, str], diags: Diagnostics,
              cache: dict) -> bytes | None:
    """``<slave>.dcf``: the slave's file with its configured values (``Node.settings``)
    and the identity its network file gives it (0x1018 sub 1-4, ``dcfedit.identity``)
    as ParameterValue, and its NodeID; None when a value has no place (reported). A
    file in CiA 311 XML gives its sections as CiA 306 text (``files.cia306``)."""
    from dcf2bin.network.dcfedit import edit, identity
    from dcf2bin.network.files import cia306
    settings = {**identity(s), **s.settings}
    text, parsed = cia306(net, s.device)
    return edit(text, s.device.path, settings, s.node_id, diags,
                shown_as=names[s.name] + ".dcf", ini=parsed, cache=cache)


def write_all(outdir: str, outputs: dict[str, bytes], inputs=(), on_wait=None):
    """Write every output into ``outdir`` all or none (``fileio.OutputSet``: each file
    checked first, never over one of ``inputs``, written as a temporary file and renamed
    only when all are complete, rolled back on any error or signal). Returns the
    ``SetReport``; raises ``OSError`` or ``OutputIsInput`` (a ``ValueError``)."""
    from dcf2bin.fileio import OutputSet
    return OutputSet(outdir, outputs.items(), inputs=inputs, on_wait=on_wait).write()


def write_warnings(report, outdir: str) -> list[Diagnostic]:
    """What writing the set found in the folder: a build stopped there before that was
    undone first, and a warning per file an earlier build wrote that this one does not (a
    slave removed from the network): kept, never deleted."""
    out = []
    if report.recovered:
        out.append(Diagnostic(Severity.WARNING, report.recovered, outdir, rule="NET131"))
    return out + [Diagnostic(Severity.WARNING, "written by an earlier build, not an output of "
                             "this network: kept (remove it if it is no longer needed)", path,
                             rule="NET130")
                  for path in report.stale]

"""Configure the slaves of a network by SDO (SPEC §10.5, `network download`).

Slaves in node-ID order; for each, first the identity check — the node's 0x1000 and 0x1018
sub 1…4 against what the master will enforce (0x1F84…0x1F88, the nonzero ones): a node the
master would refuse is an error for that node, and nothing is written to it — then its
write list (D-18, ``Node.writes``) through ``download``'s machinery (retries, read-back,
"save"). The PLC is not written: its container goes with the PLC program.

    outcomes = configure_slaves(net, network, options, progress=print)

Nothing here imports click; the command renders the outcomes.
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from dcf2bin import datatypes as dt
from dcf2bin.bus import download as dl
from dcf2bin.bus.scan import ENFORCED, entry_label, expects

CONFIGURED, FAILED, SKIPPED = "configured", "failed", "skipped"
PLC = "not written"          # a .cpj project's PLC: its container goes with its program


@dataclass
class Options:
    timeout: float = 1.0
    retries: int = 2
    verify: bool = False
    keep_going: bool = False
    save: bool = False
    max_upload: int | None = None     # the most a read-back may be (None: sdo.MAX_DOMAIN)


@dataclass
class Problem:
    """One error of one node: the message and the place it comes from."""
    message: str
    where: str


@dataclass
class Outcome:
    node_id: int
    name: str
    status: str = SKIPPED
    total: int = 0
    written: int = 0
    problems: list[Problem] = field(default_factory=list)
    aborts: list[dl.Abort] = field(default_factory=list)
    verified: bool = False
    saved: bool = False

    @property
    def label(self) -> str:
        return f"node {self.node_id} ({self.name})"


def is_plc(node) -> bool:
    """A SYS TEC PLC: its file has network variables (0xA000–0xAFFF)."""
    dev = node.device
    return dev is not None and any(0xA000 <= i <= 0xAFFF for i in dev.objects)


def plan_of(node, source: str) -> dl.Plan:
    """A slave's D-18 write list as ``download``'s plan; each write's place is its YAML
    (or file) line, and its attribute byte says whether it can be read back."""
    writes = []
    for k, w in enumerate(node.writes):
        writes.append(dl.Write(k + 1, w.index, w.sub, w.data, _attr(node, w),
                               str(w.where) if w.where is not None else source))
    return dl.Plan(source, writes, b"")


def _attr(node, w) -> int | None:
    t = dt.BY_CODE.get(w.datatype)
    attr = t.type_attr if t is not None else 0
    access = None
    if node.device is not None:
        entry = node.device.entry(w.index, w.sub)
        access = entry.access if entry is not None else None
    if access is None or access in dt.READABLE:
        attr |= dl.ATTR_READ
    return attr


def cpj_plan(node) -> tuple[dl.Plan | None, list]:
    """A .cpj node's configuration: its DCF's entries, as ``download`` writes them (the
    plan, and the compile's diagnostics)."""
    from dcf2bin.compiler import CompileOptions, compile_path
    res = compile_path(node.file, CompileOptions(node_id=node.node_id))
    return (dl.plan_from_result(res, node.file) if res.ok else None), list(res.diagnostics)


def identity_problems(ch, node, identity: dict[int, int],
                      from_file: bool = False) -> list[Problem]:
    """The identity entries the node does not hold as ``identity`` says (read by SDO):
    what the master enforces, or with ``from_file`` what the node's own DCF states. Each is
    an UNSIGNED32: a node that answers more than 4 bytes, or anything but an answer, is a
    problem, and the entries after it are not read."""
    from dcf2bin.bus import sdo
    where = str(node.where) if node.where is not None else ""
    out = []
    for key in sorted(identity):
        want = identity[key]
        if not want:
            continue
        index, sub, what = ENFORCED[key]
        entry, expected = entry_label(index, sub), expects(key, want, from_file)
        try:
            data = ch.upload(index, sub, max_size=4)
        except sdo.Aborted as exc:
            out.append(Problem(f"{entry} ({what}) cannot be read: {dl.abort_message(exc.code)}; "
                               f"{expected}: nothing written", where))
            continue
        except sdo.NoAnswer as exc:
            raise dl.Stopped(dl.Write(0, index, sub, b"", None, where), 0, exc,
                             "identity") from None
        except sdo.SdoError as exc:
            out.append(Problem(f"{entry} ({what}) cannot be read: {exc}; {expected}: nothing "
                               "written", where))
            return out
        got = int.from_bytes(data, "little")
        if got != want:
            out.append(Problem(f"{entry} ({what}) is 0x{got:08X}, {expected}: nothing written",
                               where))
    return out


def configure_slaves(net, network, options: Options, *, source: str,
                     plans: dict[int, dl.Plan] | None = None,
                     identities: dict[int, dict[int, int]] | None = None,
                     from_file: bool = False,
                     progress: Callable[[Outcome], None] | None = None) -> list[Outcome]:
    """Configure every slave; one outcome per node, in node-ID order. ``plans``: each
    node's writes by node-ID (default: its D-18 list); a node without one is a PLC and is
    not written. ``identities``: what each node must be, 0x1F84…0x1F88 → value, by
    node-ID (default: what the master enforces, ``Node.identity``; ``from_file``: what
    each node's own DCF states, a .cpj project's nodes). Without
    ``keep_going`` the first node that fails ends the run, the rest are skipped."""
    nodes = sorted(network.slaves, key=lambda n: n.node_id)
    if plans is None:
        plans = {n.node_id: plan_of(n, source) for n in nodes}
    if identities is None:
        identities = {n.node_id: n.identity for n in nodes}
    outcomes = [Outcome(n.node_id, n.name, total=len(plans[n.node_id].writes)
                        if n.node_id in plans else 0) for n in nodes]
    stop = False
    for out, node in zip(outcomes, nodes):
        if stop:
            break
        if node.node_id not in plans:
            out.status = PLC
        else:
            _configure_one(net, node, plans[node.node_id], identities.get(node.node_id, {}),
                           from_file, out, options, source)
        if progress is not None:
            progress(out)
        if out.status == FAILED and not options.keep_going:
            stop = True
    return outcomes


def _configure_one(net, node, plan: dl.Plan, identity: dict[int, int], from_file: bool,
                   out: Outcome, options: Options, source: str) -> None:
    out.status = FAILED
    with dl.sdo_client(net, node.node_id, timeout=options.timeout,
                       retries=options.retries) as ch:
        try:
            out.problems = identity_problems(ch, node, identity, from_file)
            if out.problems:
                return
            if not _write(ch, node, plan, out, options, source):
                return
        except dl.Stopped as exc:
            out.written = max(out.written, exc.written_before)
            out.problems.append(Problem(exc.text(out.total), exc.write.where))
            return
    out.status = CONFIGURED


def _write(ch, node, plan: dl.Plan, out: Outcome, options: Options, source: str) -> bool:
    """The writes, the read-back and "save"; False when the node failed."""
    result = dl.execute(plan, ch, keep_going=options.keep_going)
    out.written, out.aborts = len(result.written), result.aborts
    for a in result.aborts:
        out.problems.append(Problem(_abort_line(a, node, out.total), a.write.where))
    if result.aborts:
        return False
    if options.verify:
        diffs = dl.verify(result.written, ch, max_upload=options.max_upload)
        out.problems += [Problem(d.text, d.write.where) for d in diffs]
        if diffs:
            return False
        out.verified = True
    if options.save:
        abort = dl.store(ch, str(node.where) if node.where is not None else source)
        if abort is not None:
            out.problems.append(Problem(f"storing the parameters: {abort.text}",
                                        abort.write.where))
            return False
        out.saved = True
    return True


def _abort_line(a: dl.Abort, node, total: int) -> str:
    w = node.writes[a.write.number - 1] if a.write.number <= len(node.writes) else None
    name = f" {w.name}" if w is not None and w.name else ""
    why = f" ({w.why})" if w is not None and w.why else ""
    return (f"{a.write.label}{name}{why}: {a.text}; {a.written_before} of {total} entries "
            "written before it")

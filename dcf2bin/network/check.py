"""``network check``: a network file (YAML or .cpj) checked as a whole (SPEC §10.4, D-19).

:func:`check_network` reads the network, configures it as ``build`` does (D-17, D-18),
validates every node's file as ``validate`` would — an error in an entry that the network
neither configures nor maps becomes a warning, as ``compile`` words it — then runs the rules
of the network as a whole (:func:`run_rules`) and compares the estimated bus load (D-20)
with ``max_load``. The result holds the configured network and every finding; the command
line renders them with ``validate``'s formats.
"""
from __future__ import annotations

import functools
import gc
import re
from dataclasses import dataclass, field

from dcf2bin.diagnostics import Diagnostic, Diagnostics, ExitCode, Severity, shorten
from dcf2bin.network.model import MASTER, Network, Node
from dcf2bin.network import rules_bus, rules_pdo
from dcf2bin.network.rules import RULES as NET_RULES
from dcf2bin.network.rules import Links, add, network_where, node_ids

UNREADABLE = ("IO001", "NET010", "NET055")     # an input that cannot be read: exit 3
ALWAYS = ("IO001", "INT001")
NOT_TOUCHED = " (the network neither configures nor maps this entry)"
_SECTION = re.compile(r"([0-9a-f]{4})(?:sub([0-9a-f]+))?")
_SERVICE_OBJECTS = (0x1000, 0x1005, 0x1006, 0x1007, 0x1012, 0x1014, 0x1016, 0x1017,
                    0x1018, 0x1019) + tuple(range(0x1F80, 0x1F8A))


@dataclass
class CheckResult:
    """What :func:`check_network` found: the configured ``network`` (None when the file
    could not be read), every finding in report order, the inputs as (path, kind) pairs
    and the load estimate (None when the network could not be configured)."""
    network: Network | None
    diagnostics: list[Diagnostic] = field(default_factory=list)
    files: list[tuple[str, str]] = field(default_factory=list)
    load: object = None

    @property
    def ok(self) -> bool:
        return not any(d.severity is Severity.ERROR for d in self.diagnostics)

    def exit_code(self, strict: bool = False) -> ExitCode:
        if any(d.rule == "INT001" for d in self.diagnostics):
            return ExitCode.INTERNAL
        if any(d.rule in UNREADABLE for d in self.diagnostics):
            return ExitCode.UNREADABLE
        failing = (Severity.ERROR, Severity.WARNING) if strict else (Severity.ERROR,)
        if any(d.severity in failing for d in self.diagnostics):
            return ExitCode.FINDINGS
        return ExitCode.OK


def run_rules(network: Network) -> Diagnostics:
    """Every rule of the network as a whole (D-19) over a configured network: node-IDs,
    COB-IDs, mappings, services, SYNC, heartbeats. The findings of the network file, of
    the configuration and of each node's file are not repeated here, nor the bus load
    (:func:`check_network` adds it). ``network build`` runs this too, and writes nothing
    when it finds an error."""
    out = Diagnostics()
    node_ids(network, out)
    links = Links(network)
    rules_pdo.cob_ids(network, links, out)
    rules_pdo.mappings(network, links, out)
    rules_pdo.written_twice(network, links, out)
    rules_bus.services(network, out)
    rules_bus.sync(network, out)
    rules_bus.heartbeats(network, out)
    return out


def rule_table() -> dict:
    """Every rule ``network check`` can report, by code: validate's (a node's file) and the
    network's (the YAML, the .cpj, the configuration, the rules of §10.4)."""
    from dcf2bin.lint import all_rules
    from dcf2bin.network import cpj
    table = {r.id: r for r in all_rules()}
    table.update(_config_rules())
    table.update(cpj.RULES)
    table.update(NET_RULES)
    return table


def _config_rules() -> dict:
    """The YAML reader's and the configuration's codes (``network/codes.py``)."""
    from dcf2bin.network import codes
    from dcf2bin.network.rules import NetRule
    return {c: NetRule(c, c.lower(), Severity(sev), text[:1].upper() + text[1:] + ".", "",
                       "network") for c, sev, text in codes.CODES}


class SelectorError(ValueError):
    pass


def resolve(select=None, ignore=None, table: dict | None = None) -> set[str]:
    """The active codes for ``select``/``ignore`` (codes, code prefixes such as ``NET2``,
    rule names or ``ALL``; comma-separated strings or lists), as ``validate`` resolves its
    rules."""
    table = table if table is not None else rule_table()

    def items(sel) -> list[str]:
        if sel is None:
            return []
        sel = [sel] if isinstance(sel, str) else list(sel)
        return [p.strip() for s in sel for p in s.split(",") if p.strip()]

    def match(s: str) -> set[str]:
        if s.upper() == "ALL":
            return set(table)
        hits = {k for k, r in table.items() if k.startswith(s.upper()) or r.name == s.lower()}
        if not hits:
            raise SelectorError(f"'{shorten(s)}' matches no rule code, code prefix or rule name "
                                "(see --list-rules)")
        return hits

    chosen = items(select)
    active = set(table) if not chosen else set().union(*(match(s) for s in chosen))
    for s in items(ignore):
        active -= match(s)
    return active | set(ALWAYS)


def unreadable(path: str, exc: OSError) -> Diagnostic:
    """IO001: the network file cannot be read (missing, a directory, a device, too large),
    as every network command says it."""
    return Diagnostic(Severity.ERROR, f"cannot read: {exc.strerror or exc}", path,
                      rule="IO001", hint="check the path and its permissions")


def is_cpj(path: str) -> bool:
    """A CiA 306-3 nodelist project is told by its name, as every network command tells
    it (a YAML file named .cpj would be read as INI)."""
    return path.lower().endswith(".cpj")


def read_network(path: str, *, net: int | None = None, data: bytes | None = None) -> Network:
    """A network file read (not configured): a .cpj project, else a YAML file. Raises
    OSError when the file cannot be read."""
    if is_cpj(path):
        from dcf2bin.network import cpj
        return cpj.read(path, net, data=data)
    from dcf2bin.network.yamlfile import load_network
    return load_network(path, data)


def check_network(path: str, *, select=None, ignore=None, max_load: float = 80.0,
                  net: int | None = None, master: str | None = None) -> CheckResult:
    """Check the network file ``path`` (YAML or .cpj) as ``dcf2bin network check`` does.

    ``select``/``ignore`` take rule codes, code prefixes or names (a string or a list);
    ``net`` picks the network of a .cpj (``[TopologyN]``, default the first); a bus load
    above ``max_load`` percent is a warning. Never raises for a problem in the inputs: a
    file that cannot be read is an ``IO001`` finding. ``master``: "plc" or "lely" checks
    the network for that kind of master (by default: plc when the master has ``dcf:``).
    """
    return examine(path, select=select, ignore=ignore, max_load=max_load, net=net,
                   master=master)


# What every network command finds (issue 26: one verdict). ``check`` lints each node's
# file with every rule of validate; build, show, download, scan, lss and upload with the
# rules that can report an error (their warnings and infos are check's alone), so that an
# error check reports is an error of every command, and their exit codes agree.
ALL, ERRORS = "all", "errors"

# What a command needs sound before it does its work: the errors that make it unsound are
# reported whatever --select/--ignore say, and stop it (``is_binding``). Each need holds
# the one before it.
#   FILE        the network file read and configured (show: else there is nothing to show)
#   NODES       and each node: its node-ID, its file read (its identity, its objects) --
#               what scan, lss and upload work from; the PDO plan is not their work
#   CONFIGURES  and the configuration (NET1xx): what build writes and download sends
FILE, NODES, CONFIGURES = "file", "nodes", "configures"
NEEDS = (FILE, NODES, CONFIGURES)
NODE_ID_RULES = ("NET200", "NET201")     # a node-ID given twice, or outside 1..127


def examine(path: str, *, select=None, ignore=None, max_load: float = 80.0,
            net: int | None = None, data: bytes | None = None, lint: str = ALL,
            binding: str | bool | None = None, master: str | None = None) -> CheckResult:
    """Read, configure and check a network as every ``network`` command does: the network
    file's findings, the configuration's, each node's file (read as ``validate`` reads it:
    its kind, syntax and model, and with ``lint`` ALL every rule of validate, with ERRORS
    the rules that can report an error), the rules of the network as a whole and the bus
    load. ``binding``: what the command needs sound (FILE, NODES, CONFIGURES; True is
    CONFIGURES, ``network build``'s): the errors that make its work unsound
    (:func:`is_binding`) are kept whatever ``select``/``ignore`` say. ``master``: the kind
    of master, PLC or LELY, when the user forces it (D-21; by default it follows ``dcf:``)."""
    need = CONFIGURES if binding is True else binding or None
    active = resolve(select, ignore)
    # As build does: a network makes many small objects and no reference cycles worth
    # collecting (a fifth of the time at 126 slaves); the caller's setting is restored.
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        res = _check(path, active | (_reading_rules() if need in (NODES, CONFIGURES)
                                     else set()), max_load, net, data, lint, master)
    finally:
        if was_enabled:
            gc.enable()
    res.diagnostics = one_per_cause([d for d in res.diagnostics if not d.rule
                                     or d.rule in active
                                     or need is not None and is_binding(d, need)])
    return res


# validate's rule that says, of a PDO mapping entry of a node's file, what the network's
# rule says of the same entry at the same line: the network's finding is the one kept
# (it knows whether the network uses that PDO)
SAME_CAUSE = {"DCF404": ("NET102", "NET105"), "DCF406": ("NET103",)}


def one_per_cause(diags: list[Diagnostic]) -> list[Diagnostic]:
    """One finding per cause (issue 27): validate's DCF404/DCF406 at a line where the
    network reports NET102, NET105 or NET103 are left out."""
    said = {(d.rule, d.file, d.line) for d in diags if d.rule in ("NET102", "NET103", "NET105")}
    if not said:
        return diags
    return [d for d in diags
            if not any((r, d.file, d.line) in said for r in SAME_CAUSE.get(d.rule, ()))]


def is_binding(d: Diagnostic, need: str = CONFIGURES) -> bool:
    """An error that a command with this ``need`` (see NEEDS) cannot leave out
    (``--ignore``), and that stops it: with FILE the network file's (NET0xx: its reading,
    a node's file that cannot be read or is no description) and an input that cannot be
    read; with NODES also a node-ID given twice or out of range (NET200, NET201) and the
    reading of a node's file (validate's core rules of syntax, structure and values,
    DCF0xx-DCF3xx); with CONFIGURES (build, download) also the configuration's (NET1xx)."""
    if d.severity is not Severity.ERROR:
        return False
    if d.rule.startswith("NET0") or d.rule in ALWAYS or d.rule in UNREADABLE:
        return True
    if need == FILE:
        return False
    if d.rule in NODE_ID_RULES or need == CONFIGURES and d.rule.startswith("NET1"):
        return True
    return d.rule in _reading_rules()


@functools.cache
def _reading_rules() -> frozenset[str]:
    """validate's core rules of reading a file (syntax, structure, values): ``binding``
    reports their errors whatever ``select``/``ignore`` say (see :func:`is_binding`)."""
    from dcf2bin.lint.registry import RULES
    return frozenset(c for c, r in RULES.items() if r.source == "core" and c.startswith("DCF"))


def _lint_rules(active: set[str], lint: str) -> set[str]:
    """The validate rules a node's file is linted with (see ALL, ERRORS): with ERRORS the
    rules whose findings can be errors -- those registered as errors, and the core's
    (the reader and the model word each finding with its own severity)."""
    if lint == ALL:
        return active
    from dcf2bin.lint.registry import RULES
    return {c for c in active
            if c not in RULES or RULES[c].severity is Severity.ERROR
            or RULES[c].source == "core"}


def _check(path: str, active: set[str], max_load: float, net: int | None,
           data: bytes | None = None, lint: str = ALL, master: str | None = None) -> CheckResult:
    try:
        network = read_network(path, net=net, data=data)
    except OSError as exc:
        return CheckResult(None, [unreadable(path, exc)], [(path, "unreadable")])
    if master is not None and network.kind == "yaml":
        from dcf2bin.network.configuration import master_kind
        master_kind(network, master)
    res = CheckResult(network, files=[(path, network.kind)])
    found = Diagnostics()
    configured = network.kind == "cpj"        # a .cpj's nodes are their files as they are
    if len(network.nodes) <= 127 and not configured and not network.diagnostics.has_errors:
        # (more nodes than node-IDs is not one network: a fuzzed file with 10,000 slaves
        # is not configured, its repeated node-IDs are the finding)
        from dcf2bin.network.configuration import configure
        configure(network)
        configured = True
    found.extend(network.diagnostics)
    if not configured:
        # the file could not be read as a network: the node-IDs are all that can be
        # checked (the other rules would report what configuration never did)
        node_ids(network, found)
    else:
        _validate_files(network, found, res, _lint_rules(active, lint), lint == ALL)
        if network.nodes:
            found.extend(run_rules(network))
            from dcf2bin.network.load import estimate
            res.load = estimate(network)
            total = res.load.total
            if total > max_load:
                n = len(res.load.unknown)
                add(found, "NET260", f"the estimated bus load is {total:.1f} % at "
                    f"{network.bitrate // 1000} kbit/s, above {max_load:g} %" + (
                        f" ({n} frame{'s' if n > 1 else ''} of unknown rate counted as 0)"
                        if n else ""), network_where(network))
    res.diagnostics = list(found)
    return res


# -- every node's file, as validate reads it ---------------------------------------------

def _validate_files(network: Network, out: Diagnostics, res: CheckResult,
                    active: set[str], full: bool = True) -> None:
    """Each node's file linted once, as ``validate`` lints it (a file that several nodes
    share: once, with the node-ID of the first; the COB-IDs each node-ID gives are the
    network rules' to check). An error is kept as an error when some node of that file
    configures or maps its entry, else it becomes a warning. Not ``full``: only what is
    an error before that (validate's warnings and infos are check's)."""
    from dcf2bin.lint.context import Options
    from dcf2bin.lint.runner import lint_bytes, lint_model
    linted: dict[str, tuple] = {}
    found: dict = {}
    for node in network.nodes:
        if node.file is None:
            continue
        if node.file not in linted:
            data = network.files.get(node.file)
            if data is None:
                continue             # the reader reported it
            if node.device is None:
                # read but not modelled (not text, no section): what validate says of it
                result = lint_bytes(node.file, data, Options(node_id=node.node_id,
                                                             active=active))
                linted[node.file] = (result, lambda line: None)
                res.files.append((node.file, result.kind))
                for d in result.diagnostics:
                    if full or d.severity is Severity.ERROR:
                        found.setdefault((d.file, d.line, d.column, d.rule, d.message), d)
                continue
            # the Device configure built from these bytes, with this node-ID (the first
            # node of a shared file owns the original, the others copies): linted as it
            # is, not read a second time; only the rules that will be reported run
            result = lint_model(node.file, data, node.device, Options(
                node_id=node.node_id, target_check=node.role == MASTER,
                active=active))
            linted[node.file] = (result, _line_owner(node))
            res.files.append((node.file, result.kind))
        elif node.device is None:
            continue
        result, lines = linted[node.file]
        touched = _touched(node)
        for d in result.diagnostics:
            if not full and d.severity is not Severity.ERROR:
                continue
            key = (d.file, d.line, d.column, d.rule, d.message)
            if d.severity is Severity.ERROR and d.line is not None and d.rule not in ALWAYS:
                owner = lines(d.line)
                if owner is not None and not _is_touched(owner, touched):
                    if key not in found:
                        found[key] = Diagnostic(Severity.WARNING, d.message + NOT_TOUCHED,
                                                d.file, d.line, d.column, d.offset, d.rule,
                                                d.hint)
                    continue
            found[key] = d           # an error some node touches stays an error
    out.items.extend(found.values())


def _touched(node: Node) -> set:
    """(index, sub or None) of every entry the network reads or writes in ``node``."""
    out: set = {(i, None) for i in _SERVICE_OBJECTS}
    for p in node.pdos:
        base = (0x1400 if p.kind == "rpdo" else 0x1800) + p.number - 1
        out.add((base, None))
        if p.exists and (p.config is not None or not p.broken):
            # (a kept PDO the YAML does not list, broken by a zero entry, is neither
            # configured nor linked: D-17 keeps it as its file has it)
            out.add((base + 0x200, None))
            out.update((m.index, m.sub) for m in p.mapping)
    out.update((w.index, w.sub) for w in node.writes)
    out.update(node.settings)
    return out


def _is_touched(owner: tuple[int, int | None], touched: set) -> bool:
    index, sub = owner
    if (index, None) in touched or (index, sub) in touched:
        return True
    return sub is None and any(i == index for i, _ in touched)


def _line_owner(node: Node):
    """line -> (index, sub or None) of the object section the line is in (None: not in an
    object's section)."""
    import bisect
    ini = node.device.ini if node.device is not None else None
    starts, owners = [], []
    for name, sec in (ini.sections.items() if ini is not None else ()):
        m = _SECTION.fullmatch(name)
        starts.append(sec.line)
        owners.append((int(m.group(1), 16), int(m.group(2), 16) if m.group(2) else None)
                      if m else None)
    order = sorted(range(len(starts)), key=starts.__getitem__)
    starts = [starts[i] for i in order]
    owners = [owners[i] for i in order]

    def owner(line: int):
        i = bisect.bisect_right(starts, line) - 1
        return owners[i] if i >= 0 else None
    return owner


__all__ = ["ALL", "CONFIGURES", "ERRORS", "FILE", "NEEDS", "NODES", "CheckResult",
           "SelectorError", "check_network", "examine", "is_binding", "is_cpj", "read_network",
           "resolve", "rule_table", "run_rules", "unreadable"]

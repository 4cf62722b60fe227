r"""``dcf2bin validate``: lint DCF/EDS files and binary containers.

    >>> from dcf2bin.lint import Options, lint_bytes
    >>> text = b"[1000]\nDataType=0x0007\nAccessType=ro\nDefaultValue=-1\n"
    >>> res = lint_bytes("x.dcf", text, Options(active={"DCF200"}))
    >>> [(d.rule, d.line, d.message) for d in res.diagnostics]
    [('DCF200', 4, '0x1000sub0 DefaultValue: value -1 out of range for UNSIGNED32 (0..4294967295)')]

Modules: ``registry`` (rule ids, names, severities; ``@rule``), ``context`` (what a
check sees), ``runner`` (files, directories, stdin, exit code), one ``rules_*``
module per family, and ``core_rules`` for the ids the core reports itself. This
``__init__`` imports every rule module (the list below), which registers its rules.
"""
from __future__ import annotations

from dcf2bin.lint.context import Options
from dcf2bin.lint.registry import RULES, Rule, SelectorError, all_rules, resolve
from dcf2bin.lint.runner import FileResult, RunResult, lint_bytes, run

# The one list of rule modules: importing one registers its rules in registry.RULES. It sits
# above both the registry and the rule modules (a new rules_* module is added here).
from dcf2bin.lint import (core_rules, rules_concise, rules_container,  # noqa: F401,E402
                          rules_nv, rules_od, rules_pdo, rules_syntax, rules_target,
                          rules_values, rules_xdd)

__all__ = ["Options", "RULES", "Rule", "SelectorError", "all_rules", "resolve", "FileResult",
           "RunResult", "lint_bytes", "run"]

"""The target side: a deterministic model of ``DynBuildOd()`` (SPEC §8, D-11).

    >>> from dcf2bin.dynod import TargetOptions, emulate
    >>> from dcf2bin.container import BinContainer
    >>> out = emulate(BinContainer(entries=[(0x2000, 0, b"\\x01")], attributes=b"\\x70"))
    >>> out.code, out.name, out.created.entries
    (0, 'kCopSuccessful', 1)

Never imports click: ``compile``, ``validate`` and ``simulate`` all use this package.
"""
from __future__ import annotations

from dcf2bin.dynod.codes import MEANINGS, NAMES, rule_id
from dcf2bin.dynod.emulate import (
                                    Created,
                                    Descriptor,
                                    Outcome,
                                    Pdo,
                                    TargetEntry,
                                    TargetOptions,
                                    TargetWarning,
                                    can_id_problem,
                                    emulate,
                                    emulate_bytes,
)
from dcf2bin.dynod.static import StaticOD

__all__ = [
                                    "MEANINGS",
                                    "NAMES",
                                    "Created",
                                    "Descriptor",
                                    "Outcome",
                                    "Pdo",
                                    "StaticOD",
                                    "TargetEntry",
                                    "TargetOptions",
                                    "TargetWarning",
                                    "can_id_problem",
                                    "emulate",
                                    "emulate_bytes",
                                    "rule_id",
]

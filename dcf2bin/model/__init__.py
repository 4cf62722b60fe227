"""The neutral model: a device's objects and entries, built from an INI file.

Every object and entry keeps where it came from (file:line of its section and
of each key), so every diagnostic can point at the line that caused it.
Values stay text here; they are encoded on demand (``Device.encode``) so that
``compile`` only fails for values it actually writes (SPEC "Errors vs warnings").

One module per step, from the bottom: ``objects`` (Entry, Obj, Problem), ``sections``
(builder helpers), ``encoding`` and ``checks`` (what a Device does with values), ``device``
(Device), ``build_object``/``build_entry``/``compact_pdo`` (the builder's steps) and
``builder`` (``load``/``build``). This ``__init__`` re-exports what ``dcf2bin.model`` has
always exported, so ``from dcf2bin.model import X`` keeps working.
"""
from __future__ import annotations

# The index predicates live in dcf2bin.indexes (a leaf module, so that layout does not
# import model); they are re-exported here for the modules that use them with the model.
from dcf2bin.indexes import (NV_FIRST, NV_LAST, RPDO_COMM, TPDO_COMM,  # noqa: F401
                             is_network_variable_index, is_pdo_comm, is_pdo_mapping,
                             is_pdo_object)
from dcf2bin.model.builder import build, load
from dcf2bin.model.device import Device
from dcf2bin.model.encoding import MAX_DOWNLOAD_FILE
from dcf2bin.model.objects import Entry, Obj, Problem, unstated_mapping_count
from dcf2bin.model.sections import _section_target  # noqa: F401  (plc.merge uses it)

__all__ = ["NV_FIRST", "NV_LAST", "RPDO_COMM", "TPDO_COMM", "MAX_DOWNLOAD_FILE", "Device",
           "Entry", "Obj", "Problem", "build", "is_network_variable_index", "is_pdo_comm",
           "is_pdo_mapping", "is_pdo_object", "load", "unstated_mapping_count"]

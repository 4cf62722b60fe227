"""Device profiles: how a device wants its PDOs written and checked (SPEC.md §6).

One module per profile; each defines ``PROFILE``. Add a module and list it in
``_MODULES`` to add a profile.
"""
from __future__ import annotations

import importlib
from dataclasses import dataclass

from dcf2bin.diagnostics import shorten

_MODULES = {"cia301": "dcf2bin.profiles.cia301", "dis2": "dcf2bin.profiles.dis2"}
NAMES = tuple(_MODULES)


@dataclass(frozen=True)
class Profile:
    name: str
    description: str
    disable_mask: int = 0x80000000     # OR-ed into the COB-ID of the disabling write
    enable_mask: int = 0               # OR-ed into the COB-ID of the enabling write
    max_mapped: int = 64               # mapped objects per PDO
    max_bits: int = 64                 # bits per PDO
    cob_bit30_required: bool = False   # COB-ID bit 30 (no RTR) must be set
    old_cob_first: bool = False        # disable under the drive's old COB-ID first (DIS-2)

    def pdo_rules(self):
        from dcf2bin.select import PdoRules
        return PdoRules(self.disable_mask, self.enable_mask, self.max_mapped, self.old_cob_first)


def get_profile(name: str) -> Profile:
    try:
        return importlib.import_module(_MODULES[name]).PROFILE
    except KeyError:
        raise ValueError(f"unknown profile '{shorten(name)}' (known: {', '.join(NAMES)})") from None

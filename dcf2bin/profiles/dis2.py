"""Metronix DIS-2 servo controllers (seed 003, SPEC.md §6).

At most 4 mapped objects and 64 bits per PDO; COB-ID bit 30 (no RTR) always set,
so the disabling write is ``final | 0xC0000000`` and the enabling one
``final | 0x40000000``; the COB-ID may only change while bit 31 is set.

Seed 003 changes a COB-ID in four steps: read it, write it + C0000000, write the new one
+ C0000000, write the new one + 40000000. A container cannot read, so (SPEC D-12) the
COB-ID the drive has is taken as comm sub 1's DefaultValue: when its CAN-ID (bits 0-28)
differs from the final one, the PDO block starts with ``old | 0xC0000000``.
"""
from dcf2bin.profiles import Profile

PROFILE = Profile("dis2", "Metronix DIS-2: max 4 objects per PDO, COB-ID bit 30 always set",
                  disable_mask=0xC0000000, enable_mask=0x40000000, max_mapped=4,
                  cob_bit30_required=True, old_cob_first=True)

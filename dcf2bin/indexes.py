"""Index ranges of the object dictionary that several modules need (CiA 301, CiA 405).

A leaf module: it imports nothing of dcf2bin, so model, layout, select, the target
emulation and the PLC side can all use it without importing each other.
"""
from __future__ import annotations

NV_FIRST, NV_LAST = 0xA000, 0xAFFF      # network variables (CiA 302-4 / CiA 405)
RPDO_COMM, TPDO_COMM = 0x1400, 0x1800   # first PDO communication objects (CiA 301)
MAPPING_OFFSET = 0x200                  # mapping object = comm object + 0x200


def is_network_variable_index(index: int) -> bool:
    return NV_FIRST <= index <= NV_LAST


def is_pdo_comm(index: int) -> bool:
    return 0x1400 <= index <= 0x15FF or 0x1800 <= index <= 0x19FF


def is_pdo_mapping(index: int) -> bool:
    return 0x1600 <= index <= 0x17FF or 0x1A00 <= index <= 0x1BFF


def is_pdo_object(index: int) -> bool:
    return is_pdo_comm(index) or is_pdo_mapping(index)


def is_rpdo(index: int) -> bool:
    """A comm or mapping object of a receive PDO (0x1400-0x15FF, 0x1600-0x17FF)."""
    return 0x1400 <= index <= 0x17FF


__all__ = ["NV_FIRST", "NV_LAST", "RPDO_COMM", "TPDO_COMM", "MAPPING_OFFSET",
           "is_network_variable_index", "is_pdo_comm", "is_pdo_mapping", "is_pdo_object",
           "is_rpdo"]

"""DynBuildOd's return codes (seed 000 §4, SPEC §8.1) and the rule ids that name them."""
from __future__ import annotations

OK = 0x00
NO_MEMORY = 0xA0
INVALID_CONFIG = 0xA1
ILLEGAL_CAN_ID = 0x23
COB_EXISTS = 0x21
NO_FREE_COB = 0x20
INDEX_NOT_EXIST = 0x31
SUBINDEX_NOT_EXIST = 0x32
PDO_MAPPING = 0x78

NAMES = {
    OK: "kCopSuccessful",
    NO_MEMORY: "kCopDynNoMemory",
    INVALID_CONFIG: "kCopDynInvalidConfig",
    ILLEGAL_CAN_ID: "kCopCobIllegalCanId",
    COB_EXISTS: "kCopCobAlreadyExist",
    NO_FREE_COB: "kCopCobNoFreeEntry",
    INDEX_NOT_EXIST: "kCopObdIndexNotExist",
    SUBINDEX_NOT_EXIST: "kCopObdSubindexNotExist",
    PDO_MAPPING: "kCopPdoErrorMapp",
}

# What each code means here (docs, --help of nothing: the man page and docs/simulate.md).
MEANINGS = {
    OK: "the container was applied",
    NO_MEMORY: "the process image needs more memory than the target gives",
    INVALID_CONFIG: "the container's structure, a PI address or an entry's size is wrong",
    ILLEGAL_CAN_ID: "a PDO's CAN-ID is reserved, malformed, or changed while the PDO is valid",
    COB_EXISTS: "two valid PDOs of one direction use one CAN-ID",
    NO_FREE_COB: "more valid PDOs than the target's COB table holds",
    INDEX_NOT_EXIST: "an object that is written, mapped or needed does not exist",
    SUBINDEX_NOT_EXIST: "a sub-entry that is written, mapped or needed does not exist",
    PDO_MAPPING: "a PDO mapping is invalid or changed while not allowed",
}


# The warnings of an emulation with an unknown static OD (SPEC §8.1): what the model could not
# check because the container does not hold it (yet). TGT1xx: never a return code (those are
# one byte, TGT0xx).
UNCHECKED_ENTRY = "TGT101"           # written without attribute byte: assumed to exist
UNCHECKED_MAPPING_OBJECT = "TGT102"  # a PDO made valid, its mapping object not (yet) held
UNCHECKED_MAPPED_OBJECT = "TGT103"   # a mapped object not (yet) held, or held without type
UNCHECKED_MAPPING_ENTRY = "TGT104"   # mapping sub 0 = n counts a sub not (yet) held


def rule_id(code: int) -> str:
    """TGT + the code in three hex digits: TGT078, TGT0A1 (the same in compile and validate)."""
    return f"TGT{code:03X}"


def name(code: int) -> str:
    return NAMES.get(code, f"0x{code:02X}")


__all__ = ["MEANINGS", "NAMES", "UNCHECKED_ENTRY", "UNCHECKED_MAPPED_OBJECT",
           "UNCHECKED_MAPPING_ENTRY", "UNCHECKED_MAPPING_OBJECT", "name", "rule_id"]

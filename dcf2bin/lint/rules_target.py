"""TGT0xx: what the target's DynBuildOd() would return (SPEC §8, D-11).

The findings come from the emulation (``dcf2bin.dynod``), the same one ``compile``
runs on what it writes, so ``compile`` and ``validate`` report one fault under one id:
the rule id is TGT + the return code in hex. On a DCF, the file is compiled as
``compile`` would (nothing is checked when compile would stop on other errors first);
on a container, the emulation runs without a static OD.

TGT1xx are the warnings of such a run (``simulate`` of a container without --static-od):
what the model could not check because the container does not hold it, or holds it only
at a later entry. They are never a return code (those are one byte: TGT0xx).
"""
from __future__ import annotations

from dcf2bin.lint.registry import ANY, BIN, ERROR, core, WARNING

_HINT = "see 'dcf2bin simulate' for the whole run and the PDO table"

core("TGT0A1", "target-invalid-config", ERROR,
     "DynBuildOd would return 0xA1 kCopDynInvalidConfig: bad container structure, PI address, "
     "or an entry's data size that differs from its object's.",
     hint="the target creates and writes entries with the sizes the container gives",
     kind=ANY)
core("TGT0A0", "target-no-memory", ERROR,
     "DynBuildOd would return 0xA0 kCopDynNoMemory: the process image needs more than "
     "--pi-size bytes.",
     hint="give the target more PI memory, or use fewer network variables", kind=ANY)
core("TGT031", "target-index-missing", ERROR,
     "DynBuildOd would return 0x31 kCopObdIndexNotExist: a written, mapped or needed object "
     "does not exist on the target.",
     hint=_HINT, kind=ANY)
core("TGT032", "target-subindex-missing", ERROR,
     "DynBuildOd would return 0x32 kCopObdSubindexNotExist: a written, mapped or needed "
     "sub-entry does not exist on the target.",
     hint=_HINT, kind=ANY)
core("TGT023", "target-illegal-can-id", ERROR,
     "DynBuildOd would return 0x23 kCopCobIllegalCanId: a PDO's CAN-ID is restricted by "
     "CiA 301, malformed, or changed while the PDO is valid.",
     hint="use a CAN-ID outside 0x000-0x07F, 0x101-0x180, 0x581-0x5FF, 0x601-0x67F, "
          "0x6E0-0x7FF", kind=ANY)
core("TGT021", "target-can-id-in-use", ERROR,
     "DynBuildOd would return 0x21 kCopCobAlreadyExist: two valid PDOs of one direction use "
     "one CAN-ID.",
     hint="give every valid PDO of a direction its own CAN-ID", kind=ANY)
core("TGT020", "target-no-free-cob", ERROR,
     "DynBuildOd would return 0x20 kCopCobNoFreeEntry: more valid PDOs of a direction than "
     "the target's COB table holds (--tx-cobs, --rx-cobs).",
     hint="disable PDOs (COB-ID bit 31) or build the target with a larger COB table",
     kind=ANY)
core("TGT078", "target-pdo-mapping", ERROR,
     "DynBuildOd would return 0x78 kCopPdoErrorMapp: a PDO mapping names an object that "
     "cannot be mapped so, exceeds 64 bits, or is changed while not allowed.",
     hint="map existing, mappable objects with their exact bit length, in the right "
          "direction", kind=ANY)

_UNCHECKED = "give --static-od (the firmware's EDS) to check it"
core("TGT101", "target-unchecked-entry", WARNING,
     "An entry of a container without extended info segment could not be checked: with no "
     "static OD it is assumed to exist (0x31/0x32 on a target that lacks it).",
     hint=_UNCHECKED, kind=BIN)
core("TGT102", "target-unchecked-mapping-object", WARNING,
     "A PDO is made valid, but the container does not write its mapping object before: it "
     "is taken to be in the static OD (0x31 on a target that lacks it).",
     hint=_UNCHECKED, kind=BIN)
core("TGT103", "target-unchecked-mapped-object", WARNING,
     "A PDO maps an object the container does not hold yet (or holds without an attribute "
     "byte): it is taken to be in the static OD with a fitting type and access (0x31/0x32/0x78 "
     "on a target where it is not).",
     hint=_UNCHECKED, kind=BIN)
core("TGT104", "target-unchecked-mapping-entry", WARNING,
     "A mapping's sub 0 counts a sub the container has not written, in a mapping object it "
     "did not create: it is taken to be in the static OD (0x32 on a target that lacks it).",
     hint=_UNCHECKED, kind=BIN)

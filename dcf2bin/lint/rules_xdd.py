"""XDD0xx: what only a CiA 311 XML description can get wrong. The reader
(dcf2bin/formats/xdd) finds these while it reads the file; they are registered here so
that ``--list-rules``, ``--select``/``--ignore`` and the documentation know them.
Everything else about an XDD/XDC -- values, types, PDOs -- is checked by the DCF rules,
which read its objects as they read an EDS's."""
from __future__ import annotations

from dcf2bin.lint.registry import ERROR, INFO, WARNING, core

core("XDD001", "xml-not-well-formed", ERROR,
     "The file is not well-formed XML (or nests elements more than 256 deep); nothing in it "
     "is read.",
     hint="an XDD/XDC is well-formed XML; an editor that checks XML finds the spot")
core("XDD002", "xml-doctype", ERROR,
     "The file has a DOCTYPE (entity declarations, a DTD to fetch); a CiA 311 description "
     "has none, and dcf2bin expands no entity and fetches no DTD: nothing in it is read.",
     hint="remove the DOCTYPE; CiA 311 files are checked against XML Schema")
core("XDD003", "not-cia311", ERROR,
     "XML that is not a CiA 311 device description: another root element than "
     "ISO15745ProfileContainer, or no CANopenObjectList.",
     hint="dcf2bin reads CiA 311 XDD/XDC files and CiA 306 EDS/DCF files")
core("XDD004", "powerlink", ERROR,
     "An Ethernet POWERLINK device description (the same ISO 15745 frame, an ObjectList of "
     "Object elements): not CANopen, and not read.",
     hint="dcf2bin reads CANopen descriptions only; take the device's CANopen XDD or EDS")
core("XDD010", "missing-reference", ERROR,
     "A uniqueIDRef names no parameter of the parameterList, or a dataTypeIDRef no type of "
     "the dataTypeList.",
     hint="add the parameter or type, or correct the reference")
core("XDD011", "unknown-datatype", ERROR,
     "A dataType attribute that is not 4 hex digits, or a type element (or a type's base) "
     "that is none of IEC 61131's elementary types.",
     hint="give one of CiA 301's data types (dataType) or IEC 61131's (UDINT, ...)")
core("XDD012", "attribute-contradicts-parameter", WARNING,
     "An object's own attribute (dataType, accessType, defaultValue, ...) and the parameter "
     "its uniqueIDRef names say different things; the attribute is read.",
     hint="make the attribute and the parameter agree, or drop one")
core("XDD013", "bad-attribute", ERROR,
     "An attribute of an object is missing or not of its kind: index not 4 hex digits, "
     "subIndex not 2, objectType not a number, an unknown accessType, access, PDOmapping "
     "or objFlags.",
     hint="see CiA 311 for the attribute's values")
core("XDD014", "duplicate-id", ERROR,
     "An object index, a subIndex of one object or a uniqueID is given twice (both lines "
     "named); the first is read.",
     hint="remove one of them; dcf2bin does not guess which is meant")
core("XDD020", "disabled-objects", INFO,
     "Objects marked CO_disabled (CANopenNode's property: not built into its object "
     "dictionary) are left out of the device's objects; one line names them.",
     hint="remove the CO_disabled property to read an object")

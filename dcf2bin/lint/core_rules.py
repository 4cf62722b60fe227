"""Rules whose findings the core produces (ini reader, model, layout, selection).

They are registered here so that ``--list-rules``, ``--select``/``--ignore``, the
JSON/SARIF rule tables and the documentation know them; the checks themselves live
where the data is built and are not repeated.
"""
from __future__ import annotations

from dcf2bin.lint.registry import ANY, ERROR, WARNING, core

# -- syntax: dcf2bin/ini.py ------------------------------------------------------------------
core("DCF001", "key-outside-section", ERROR,
     "A key=value line stands before the first section header.",
     hint="put the key into its section, or delete it")
core("DCF002", "malformed-line", ERROR,
     "A non-blank line is neither a section header, a comment nor key=value.",
     hint="comments start with ';' (or '#'); keys need '='")
core("DCF003", "malformed-section-header", ERROR,
     "A section header lacks its ']', is empty, or has text after the ']'.",
     hint="write section headers as [Name] alone on their line")
core("DCF004", "comment-after-section-header", WARNING,
     "A comment follows a section header on the same line; it is ignored.",
     hint="put the comment on its own line")
core("DCF008", "not-text", ERROR,
     "The file is not EDS/DCF text at all: UTF-16, binary, or lines that end in CR alone; "
     "it is reported once and not read further.",
     hint="an EDS/DCF is text in UTF-8 or Latin-1 with LF or CRLF line ends")
core("DCF009", "nothing-configured", WARNING,
     "compile only: nothing in the file is configured, so the container holds no entries.",
     hint="--entries all also writes every DefaultValue (the device's defaults)")
core("DCF014", "too-many-keys", ERROR,
     "A section has more than 65,536 keys (an object list names each index at most once); "
     "the keys after the 65,536th are not read.",
     hint="no CiA 306 section has that many: an object list names each of the 65,536 "
          "indexes at most once")
core("DCF015", "too-many-sections", ERROR,
     "The file has more than 1,048,576 sections (as many as the whole network-variable "
     "area 0xA000-0xAFFF holds); the rest of the file is not read.",
     hint="every network variable of CiA 405 (A000-A8FF) is 589,824 sections: is this the "
          "file you meant?")
core("DCF056", "no-sections", ERROR,
     "The file has no section at all (empty, or not an EDS/DCF); compile refuses it too.",
     hint="an EDS/DCF has [FileInfo], [DeviceInfo] and object sections")

# -- structure: dcf2bin/model/ ----------------------------------------------------------------
core("DCF005", "subindex-too-large", ERROR,
     "A sub-object section names a subindex above 0xFF.",
     hint="subindexes are 0x00..0xFF; check the section name")
core("DCF006", "sub-section-without-object", ERROR,
     "A [<index>subN] section has no [<index>] object section.",
     hint="add the object section with ObjectType, SubNumber and ParameterName")
core("DCF007", "aux-section-without-object", WARNING,
     "A [<index>Name]/[<index>Value]/[<index>Denotation] section has no object section; ignored.",
     hint="add the object section or remove the orphan")
core("DCF010", "duplicate", ERROR,
     "A section or a key within one section appears twice (both lines named).",
     hint="remove one of them; dcf2bin does not guess which is meant")
core("DCF011", "commissioning-spellings", WARNING,
     "Both [DeviceComissioning] and [DeviceCommissioning] exist; the first wins.",
     hint="keep one section, spelled [DeviceComissioning] as in CiA 306")
core("DCF012", "bad-node-id", ERROR,
     "[DeviceComissioning] NodeID is not a number in 1..127.",
     hint="NodeID is the device's node-ID, 1..127")
core("DCF013", "bad-dummy-usage", WARNING,
     "A [DummyUsage] entry is not Dummy<type>=0/1.",
     hint="write Dummy<type>=1 to allow data type <type> as a dummy mapping")
core("DCF020", "bad-structural-number", ERROR,
     "ObjectType, SubNumber, CompactSubObj or ObjFlags is not a valid integer.",
     hint="decimal, 0x-hex or 0-octal integers only")
core("DCF021", "compactsubobj-range", ERROR,
     "CompactSubObj is outside 1..254.",
     hint="CompactSubObj counts the subindexes 1..N, at most 254")
core("DCF022", "unknown-object-type", ERROR,
     "ObjectType is not 0x2, 0x5, 0x6, 0x7, 0x8 or 0x9.",
     hint="0x7 VAR, 0x8 ARRAY, 0x9 RECORD, 0x2 DOMAIN, 0x5 DEFTYPE, 0x6 DEFSTRUCT")
core("DCF023", "object-type-conflict", WARNING,
     "An object has sub-objects but an ObjectType other than ARRAY/RECORD.",
     hint="set ObjectType=0x8 (ARRAY) or 0x9 (RECORD)")
core("DCF024", "compact-and-sub-sections", WARNING,
     "A CompactSubObj object also has sub-sections; the sub-section wins.",
     hint="use either CompactSubObj or sub-sections, not both")
core("DCF025", "compact-parametervalue-ignored", WARNING,
     "ParameterValue in the main section of a CompactSubObj object is ignored.",
     hint="give the values in [<index>Value] (keys are decimal subindexes)")
core("DCF026", "compact-aux-bad-key", WARNING,
     "A [<index>Name]/[<index>Value]/[<index>Denotation] key is not a decimal subindex in 1..N.",
     hint="keys of these sections are decimal subindexes within CompactSubObj")
core("DCF027", "value-section-without-compact", WARNING,
     "[<index>Value] is given for an object without CompactSubObj; ignored.",
     hint="put ParameterValue into the sub-sections instead")
core("DCF030", "unknown-data-type", ERROR,
     "DataType is not a number or not a supported CANopen data type.",
     hint="use a basic type code such as 0x0007 (UNSIGNED32)")
core("DCF031", "missing-data-type", ERROR,
     "An entry has no DataType.",
     hint="add DataType= (only network variables and sub 0 may omit it)")
core("DCF032", "unknown-access-type", ERROR,
     "AccessType is not ro, wo, rw, rwr, rww or const.",
     hint="AccessType is one of ro, wo, rw, rwr, rww, const")
core("DCF033", "missing-access-type", ERROR,
     "An entry has no AccessType.",
     hint="add AccessType= (only network variables and sub 0 may omit it)")
core("DCF040", "bad-deviceinfo-pdo-number", ERROR,
     "[DeviceInfo] CompactPDO, NrOfRXPDO or NrOfTXPDO is not a valid integer.",
     hint="these keys are integers")
core("DCF099", "core-check", ERROR,
     "A problem found by the model or the compile selection that has no finer rule id.",
     hint="see the message")

# -- values: Device.encode -------------------------------------------------------------------
core("DCF201", "node-id-needed", ERROR,
     "A written value uses $NODEID but no node-ID is known.",
     hint="give --node-id N or set NodeID in [DeviceComissioning]")

# -- network variables: dcf2bin/layout.py ----------------------------------------------------
core("DCF300", "nv-not-array", ERROR,
     "An object in 0xA000-0xAFFF is a VAR; network variable objects are ARRAYs.",
     hint="set ObjectType=0x8 and give the variables as sub 1..254")
core("DCF301", "nv-without-channel", ERROR,
     "An object in 0xA900-0xAFFF is not covered by a [DynamicChannels] segment.",
     hint="declare a [DynamicChannels] segment whose Range covers it")
core("DCF302", "nv-subindex-too-large", ERROR,
     "A network variable has subindex 255; an index holds variables 1..254.",
     hint="the 255th variable of a kind goes to the next index")
core("DCF303", "nv-type-mismatch", ERROR,
     "A network variable's DataType differs from its range's (or segment's) type.",
     hint="use the type of the CiA 405 range, or move the variable")
core("DCF304", "nv-maxcnt-exceeded", ERROR,
     "A network variable lies beyond its segment's MaxCnt capacity.",
     hint="raise MaxCnt<k> or use fewer variables")
core("DCF305", "pi-too-large", ERROR,
     "The process image is larger than --pi-size.",
     hint="reduce the variables or check --pi-size")
core("DCF306", "pi-address-overflow", ERROR,
     "A network variable's PI address does not fit the WORD of the address segment.",
     hint="the process image must stay within 64 KiB")
core("DCF307", "pi-overlap", ERROR,
     "Two network variables (or MaxCnt reservations) of one area overlap; both are named.",
     hint="fix the PPOffset<k> values of the [DynamicChannels] segments")
core("DCF310", "dynch-bad-number", ERROR,
     "A [DynamicChannels] number (NrOfSeg, MaxCnt<k>, ...) is not a valid integer.",
     hint="these keys are integers")
core("DCF311", "dynch-unnumbered-key", WARNING,
     "[DynamicChannels] has an unnumbered PIOffset/MaxCnt/Range key; ignored.",
     hint="use the numbered form, e.g. PIOffset1")
core("DCF312", "dynch-segment-incomplete", ERROR,
     "A [DynamicChannels] segment lacks Type<k>, Dir<k> or Range<k>.",
     hint="every segment 1..NrOfSeg needs Type<k>, Dir<k> and Range<k>")
core("DCF313", "dynch-bad-segment", ERROR,
     "A [DynamicChannels] segment has a bad Type, Dir, Range or PPOffset.",
     hint="Type is a fixed-size type code, Dir ro/rw/rwr/rww, Range 0xA000-0xAFFF")
core("DCF314", "dynch-offset-twice", ERROR,
     "A [DynamicChannels] segment gives both PPOffset<k> and PIOffset<k>.",
     hint="keep one of them (PIOffset<k> is a synonym)")
core("DCF315", "dynch-range-overlap", ERROR,
     "The Ranges of two [DynamicChannels] segments overlap.",
     hint="every index belongs to at most one segment")

# -- inputs and internal errors (always on) --------------------------------------------------
core("IO001", "input-unreadable", ERROR,
     "An input could not be read at all (missing, a directory, no permission).",
     hint="check the path", kind=ANY, always=True)
core("IO002", "kind-not-as-named", WARNING,
     "The file's content is another kind than its name says (a container named .dcf, DCF "
     "text named .bin); it is checked by its content.",
     hint="rename the file to the suffix of its kind (.dcf/.eds text, .bin container)",
     kind=ANY)
core("INT001", "internal-error", ERROR,
     "A check crashed: a bug in dcf2bin, not in the input.",
     hint="run with --debug for the traceback, and please report it", kind=ANY, always=True)

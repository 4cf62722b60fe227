"""What CiA 311 says in words that CiA 306 says in numbers: the IEC 61131 type elements of a
``parameter``, its ``access`` values, the ``PDOmapping`` values, and the elements a
``parameter`` holds besides its type. Data only.
"""
from __future__ import annotations

# IEC 61131-3 elementary types (CiA 311 ``parameter``/``varDeclaration`` content) -> the
# CiA 301 data type code. BITSTRING is an OCTET_STRING with a default value and a DOMAIN
# without one, as CANopenEditor writes them (see ``type_code``).
IEC_TYPES = {
    "BOOL": 0x0001, "SINT": 0x0002, "INT": 0x0003, "DINT": 0x0004, "USINT": 0x0005,
    "UINT": 0x0006, "UDINT": 0x0007, "REAL": 0x0008, "STRING": 0x0009, "WSTRING": 0x000B,
    "LREAL": 0x0011, "LINT": 0x0015, "ULINT": 0x001B, "CHAR": 0x0002, "BYTE": 0x0005,
    "WORD": 0x0006, "DWORD": 0x0007, "LWORD": 0x001B, "BITSTRING": 0x000A,
}
OCTET_STRING, DOMAIN = 0x000A, 0x000F

# the elements of a parameter that are not its type
NOT_TYPES = frozenset({
    "label", "description", "labelRef", "descriptionRef", "conditionalSupport",
    "denotation", "actualValue", "defaultValue", "substituteValue", "allowedValues", "unit",
    "property", "dataTypeIDRef", "variableRef"})

# parameter@access (CiA 311) -> CiA 306 AccessType; XML Schema's default is "read"
PARAM_ACCESS = {"const": "const", "read": "ro", "write": "wo", "readWrite": "rw",
                "readWriteInput": "rwr", "readWriteOutput": "rww"}
DEFAULT_PARAM_ACCESS = "read"
# CANopenObject@accessType: CiA 306's own words
OBJECT_ACCESS = frozenset({"const", "ro", "wo", "rw", "rwr", "rww"})
# the same SDO access, for comparing an object's accessType with its parameter's access
SDO_ACCESS = {"const": "ro", "ro": "ro", "wo": "wo", "rw": "rw", "rwr": "rw", "rww": "rw"}

# CANopenObject@PDOmapping -> CiA 306 PDOMapping
PDO_MAPPING = {"no": "0", "default": "1", "optional": "1", "TPDO": "1", "RPDO": "1"}

# supportedBaudRate@value -> CiA 306 [DeviceInfo] key
BAUD_RATES = {"10 Kbps": "BaudRate_10", "20 Kbps": "BaudRate_20", "50 Kbps": "BaudRate_50",
              "125 Kbps": "BaudRate_125", "250 Kbps": "BaudRate_250",
              "500 Kbps": "BaudRate_500", "800 Kbps": "BaudRate_800",
              "1000 Kbps": "BaudRate_1000"}

# CANopenNode's own settings (CANopenEditor's ``property`` elements), kept for its writers
CANOPENNODE_PROPERTIES = ("CO_countLabel", "CO_storageGroup", "CO_flagsPDO",
                          "CO_stringLengthMin", "CO_disabled", "CO_accessSRDO")


def type_code(name: str, default: str | None) -> int | None:
    """The CiA 301 code of an IEC type element, None when unknown."""
    code = IEC_TYPES.get(name)
    if code == OCTET_STRING and not default:
        return DOMAIN
    return code

"""Identifiers for the IEC 61131-3 and C forms of the variable map (SPEC.md D-14).

The name with each run of characters other than A-Z, a-z, 0-9 replaced by one ``_``,
leading/trailing ``_`` dropped, ``_`` put before a leading digit; an IEC keyword or an
empty result gets the prefix ``nv_`` (empty: ``nv_<index>_<sub>``); repeats, compared
without regard to case, get ``_2``, ``_3``, ... counting on until the name is unused.
"""
from __future__ import annotations

import re

# IEC 61131-3 (3rd edition) keywords, elementary type names and standard function
# names that cannot be a variable's name; compared in upper case.
IEC_KEYWORDS = frozenset("""
ABS ACOS ACTION ADD AND ANDN ANY ANY_BIT ANY_CHAR ANY_DATE ANY_DERIVED ANY_ELEMENTARY
ANY_INT ANY_MAGNITUDE ANY_NUM ANY_REAL ANY_STRING ARRAY ASIN AT ATAN BOOL BY BYTE CAL CALC
CALCN CASE CHAR CLASS CONCAT CONFIGURATION CONSTANT COS CTD CTU CTUD DATE DATE_AND_TIME DELETE
DINT DIV DO DT DWORD ELSE ELSIF EN END_ACTION END_CASE END_CLASS END_CONFIGURATION END_FOR
END_FUNCTION END_FUNCTION_BLOCK END_IF END_INTERFACE END_METHOD END_NAMESPACE END_PROGRAM
END_REPEAT END_RESOURCE END_STEP END_STRUCT END_TRANSITION END_TYPE END_VAR END_WHILE ENO EQ
EXIT EXP EXPT EXTENDS F_EDGE F_TRIG FALSE FINAL FIND FOR FROM FUNCTION FUNCTION_BLOCK GE GT
IF IMPLEMENTS INITIAL_STEP INSERT INT INTERFACE INTERNAL INTERVAL JMP JMPC JMPCN LD LDN LDATE
LDATE_AND_TIME LDT LE LEFT LEN LIMIT LINT LN LOG LREAL LT LTIME LTIME_OF_DAY LTOD LWORD MAX
METHOD MID MIN MOD MOVE MUL MUX NAMESPACE NE NON_RETAIN NOT NULL OF ON OR ORN OVERLAP OVERRIDE
PRIVATE PROGRAM PROTECTED PUBLIC R R_EDGE R_TRIG READ_ONLY READ_WRITE REAL REF REF_TO REPEAT
REPLACE RESOURCE RET RETAIN RETC RETCN RETURN RIGHT ROL ROR RS S SEL SHL SHR SIN SINGLE SINT
SQRT SR ST STEP STN STRING STRUCT SUB SUPER TAN TASK THEN THIS TIME TIME_OF_DAY TO TOD TOF TON
TP TRANSITION TRUE TYPE UDINT UINT ULINT UNTIL USING USINT VAR VAR_ACCESS VAR_CONFIG
VAR_EXTERNAL VAR_GLOBAL VAR_IN_OUT VAR_INPUT VAR_OUTPUT VAR_TEMP WCHAR WHILE WITH WORD WSTRING
XOR XORN
""".split())

_RUN = re.compile(r"[^A-Za-z0-9]+")


def base_ident(name: str, index: int, sub: int) -> str:
    """The identifier of one name before repeats are counted (D-14)."""
    if (name.isascii() and name.isidentifier() and name[0] != "_" and name[-1] != "_"
            and "__" not in name):       # already one: the common case, kept as it is
        return "nv_" + name if name.upper() in IEC_KEYWORDS else name
    ident = _RUN.sub("_", name).strip("_")
    if not ident:
        return f"nv_{index:04X}_{sub:X}"
    if ident[0].isdigit():
        ident = "_" + ident
    if ident.upper() in IEC_KEYWORDS:
        ident = "nv_" + ident
    return ident


def identifiers(rows) -> list[str]:
    """One identifier per row, unique without regard to case (D-14)."""
    used: set[str] = set()
    add = used.add
    out = []
    append = out.append
    keywords = IEC_KEYWORDS
    for r in rows:
        name = r.name
        if (name.isascii() and name.isidentifier() and name[0] != "_" and name[-1] != "_"
                and "__" not in name):       # already one: the common case
            key = name.upper()
            ident = name
            if key in keywords:
                ident, key = "nv_" + name, "NV_" + key
        else:
            ident = base_ident(name, r.index, r.sub)
            key = ident.upper()
        if key in used:
            n = 2
            while f"{key}_{n}" in used:
                n += 1
            ident, key = f"{ident}_{n}", f"{key}_{n}"
        add(key)
        append(ident)
    return out

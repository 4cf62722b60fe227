"""What CiA 306 (-1, -3) defines: the kinds of sections (``classify``) and the keys each
kind has (``known_key``). Shared by the rules (rules_syntax) and their tables (tables), so
it imports nothing of the lint package."""
from __future__ import annotations

import functools
import re

OBJ_KEYS = frozenset({
    "parametername", "objecttype", "datatype", "accesstype", "defaultvalue", "pdomapping",
    "subnumber", "lowlimit", "highlimit", "objflags", "compactsubobj", "parametervalue",
    "denotation", "downloadfile", "uploadfile", "srdomapping", "invertedsrad"})
SUB_KEYS = OBJ_KEYS - {"subnumber", "compactsubobj"}
FIXED = {
    "fileinfo": frozenset({
        "filename", "fileversion", "filerevision", "edsversion", "description", "creationtime",
        "creationdate", "createdby", "modificationtime", "modificationdate", "modifiedby",
        "lasteds"}),
    "deviceinfo": frozenset({
        "vendorname", "vendornumber", "productname", "productnumber", "revisionnumber",
        "ordercode", "baudrate_10", "baudrate_20", "baudrate_50", "baudrate_125",
        "baudrate_250", "baudrate_500", "baudrate_800", "baudrate_1000", "baudrate_auto",
        "simplebootupmaster", "simplebootupslave", "granularity", "dynamicchannelssupported",
        "groupmessaging", "nrofrxpdo", "nroftxpdo", "lss_supported", "compactpdo",
        "canopensafetysupported", "ng_slave", "ng_master", "nrofng_monitorednodes"}),
    "devicecomissioning": frozenset({
        "nodeid", "nodename", "baudrate", "netnumber", "networkname", "canopenmanager",
        "lss_serialnumber", "noderefd", "netrefd"}),
    "tools": None, "supportedmodules": None, "connectedmodules": None,
    "dummyusage": None, "comments": None, "mandatoryobjects": None, "optionalobjects": None,
    "manufacturerobjects": None, "dynamicchannels": None,
}
FIXED["devicecommissioning"] = FIXED["devicecomissioning"]
NUMBERED = {  # section kind -> (plain keys, numbered key prefixes)
    "tools": ({"items"}, ("tool",)),
    "supportedmodules": ({"nrofentries"}, ("",)),
    "connectedmodules": ({"nrofentries"}, ("",)),
    "dummyusage": (set(), ()),
    "comments": ({"lines"}, ("line",)),
    "mandatoryobjects": ({"supportedobjects"}, ("",)),
    "optionalobjects": ({"supportedobjects"}, ("",)),
    "manufacturerobjects": ({"supportedobjects"}, ("",)),
    "dynamicchannels": ({"nrofseg", "pioffset", "maxcnt", "range"},  # unnumbered: DCF311
                        ("type", "dir", "range", "ppoffset", "pioffset", "maxcnt")),
    "aux": ({"nrofentries"}, ("",)),
    "objectlinks": ({"objectlinks"}, ("",)),
    "tool": ({"name", "command"}, ()),
    "modulelist": ({"nrofentries"}, ("",)),
    "moduleinfo": ({"productname", "productversion", "productrevision", "ordercode"}, ()),
    "modulecomments": ({"lines"}, ("line",)),
}
_OBJ_RE = re.compile(r"[0-9a-f]{4}")
_SUB_RE = re.compile(r"[0-9a-f]{4}sub[0-9a-f]+")
_AUX_RE = re.compile(r"[0-9a-f]{4}(name|value|denotation)")
_LINKS_RE = re.compile(r"[0-9a-f]{4}objectlinks")
_TOOL_RE = re.compile(r"tool[0-9]+")
_MOD_RE = re.compile(r"m[0-9]+(moduleinfo|fixedobjects|subextends|comments|subext[0-9a-f]{4}"
                     r"(?:sub[0-9a-f]+)?)")
_DUMMY_RE = re.compile(r"dummy[0-9a-f]{4}")
def classify(canon: str) -> str | None:
    """The CiA 306 kind of a section (canonical name), or None when unknown."""
    if len(canon) > 7 and canon[4:7] == "sub" and _SUB_RE.fullmatch(canon):
        return "sub"
    if len(canon) == 4 and _OBJ_RE.fullmatch(canon):
        return "object"
    if _SUB_RE.fullmatch(canon):
        return "sub"
    if _AUX_RE.fullmatch(canon):
        return "aux"
    if _LINKS_RE.fullmatch(canon):
        return "objectlinks"
    if canon in FIXED:
        return canon
    if _TOOL_RE.fullmatch(canon):
        return "tool"
    m = _MOD_RE.fullmatch(canon)
    if m:
        kind = m.group(1)
        if kind.startswith("subext") and kind != "subextends":
            return "object"
        return {"moduleinfo": "moduleinfo", "comments": "modulecomments"}.get(kind, "modulelist")
    return None


def known_key(kind: str, key: str) -> bool:
    if kind == "object":
        return key in OBJ_KEYS
    if kind == "sub":
        return key in SUB_KEYS
    fixed = FIXED.get(kind)
    if fixed is not None:
        return key in fixed
    if kind == "dummyusage":
        return _DUMMY_RE.fullmatch(key) is not None
    plain, prefixes = NUMBERED.get(kind, (set(), ()))
    if key in plain:
        return True
    for p in prefixes:
        if key.startswith(p) and key[len(p):].isdigit() and key[len(p):].isascii():
            return True
    return False


def unknown_keys(kind: str, names) -> list[str]:
    """The key names (lower case) among ``names`` that CiA 306 does not define for a section
    of ``kind``, in their order: ``known_key`` for each, with one set lookup (and for the
    numbered keys one match) per key."""
    fixed = {"object": OBJ_KEYS, "sub": SUB_KEYS}.get(kind) or FIXED.get(kind)
    if fixed is not None:
        return [k for k in names if k not in fixed]
    numbered = _numbered(kind)
    if numbered is None:
        return [k for k in names if not known_key(kind, k)]
    plain, match = numbered
    return [k for k in names if k not in plain and match(k) is None]


@functools.lru_cache(maxsize=None)
def _numbered(kind: str):
    """(plain keys, fullmatch of the numbered ones) of a kind in NUMBERED, else None: a key
    is known when it is plain, or a prefix and ASCII digits (``known_key``)."""
    if kind not in NUMBERED or kind == "dummyusage":
        return None
    plain, prefixes = NUMBERED[kind]
    if not prefixes:
        return frozenset(plain), re.compile(r"(?!)").fullmatch
    alternatives = "|".join(re.escape(p) for p in prefixes)
    return frozenset(plain), re.compile(f"(?:{alternatives})[0-9]+").fullmatch

"""The frame of a written CiA 311 file and what it says about the file and the device: the
two ISO 15745 profiles, the ``ProfileBody`` file attributes ([FileInfo]), the
``DeviceIdentity``, the baud rates, ``dummyUsage``, the network management features
([DeviceInfo]) and an XDC's ``deviceCommissioning`` ([DeviceComissioning]) -- the inverse
of ``header``. What CiA 311 has no place for is a CNV005 warning.
"""
from __future__ import annotations

import re

from dcf2bin.diagnostics import shorten
from dcf2bin.formats import written as w
from dcf2bin.formats.xdd.vocabulary import BAUD_RATES

NS = "http://www.canopen.org/xml/1.1"
XSI = "http://www.w3.org/2001/XMLSchema-instance"
# [FileInfo] key -> ProfileBody attribute (header._FILE_INFO read backwards)
FILE_INFO = (("FileName", "fileName"), ("CreatedBy", "fileCreator"),
             ("CreationDate", "fileCreationDate"), ("CreationTime", "fileCreationTime"),
             ("ModifiedBy", "fileModifiedBy"), ("ModificationDate", "fileModificationDate"),
             ("ModificationTime", "fileModificationTime"), ("FileVersion", "fileVersion"))
FILE_INFO_SILENT = {"edsversion"}          # the version of CiA 306 text itself
# [DeviceInfo] key -> DeviceIdentity element; True: a number (written as 8 hex digits)
IDENTITY = (("VendorName", "vendorName", False), ("VendorNumber", "vendorID", True),
            ("ProductName", "productName", False), ("ProductNumber", "productID", True),
            ("RevisionNumber", "revisionNumber", True), ("OrderCode", "orderNumber", False))
# [DeviceInfo] key -> CANopenGeneralFeatures attribute; True: an XML Schema boolean
GENERAL = (("GroupMessaging", "groupMessaging", True),
           ("DynamicChannelsSupported", "dynamicChannels", False),
           ("Granularity", "granularity", False), ("NrOfRXPDO", "nrOfRxPDO", False),
           ("NrOfTXPDO", "nrOfTxPDO", False), ("SimpleBootUpSlave", "bootUpSlave", True),
           ("LSS_Supported", "layerSettingServiceSlave", True), ("NG_Slave", "ngSlave", True),
           ("NG_Master", "ngMaster", True),
           ("NrOfNG_MonitoredNodes", "NrOfNG_MonitoredNodes", False))
MASTER = (("SimpleBootUpMaster", "bootUpMaster", True),)
COMMISSIONING = (("NodeID", "nodeID", False), ("NodeName", "nodeName", None),
                 ("Baudrate", "actualBaudRate", None), ("NetNumber", "networkNumber", False),
                 ("NetworkName", "networkName", None), ("CANopenManager", "CANopenManager", True),
                 ("LSS_SerialNumber", "LSS_SerialNumber", None))
_DEVICE_INFO_KEYS = ({k.lower() for k, _, _ in IDENTITY + GENERAL + MASTER}
                     | {k.lower() for k in BAUD_RATES.values()} | {"compactpdo"})
_DATE = re.compile(r"(\d{2})-(\d{2})-(\d{4})")
_TIME = re.compile(r"(\d{1,2}):(\d{2})\s*([AaPp])[Mm]")
# characters XML 1.0 cannot hold
_NOT_XML = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ufffe\uffff\ud800-\udfff]")


def attr(value: str) -> str | None:
    """``value`` as an attribute value (tabs and line ends as references, so they
    survive), or None when XML cannot hold it (a control character)."""
    if _NOT_XML.search(value):
        return None
    return (value.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
            .replace('"', "&quot;").replace("\t", "&#9;").replace("\n", "&#10;")
            .replace("\r", "&#13;"))


def text(value: str) -> str:
    """``value`` as element text (control characters XML cannot hold left out: the same
    value is an attribute too, whose loss CNV007 names)."""
    return _NOT_XML.sub("", value).replace("&", "&amp;").replace("<", "&lt;").replace(
        ">", "&gt;").replace("\r", "&#13;")


def _number(value: str, *, hex8: bool = False) -> str:
    """A CiA 306 number as CiA 311 files write it (decimal; an ID as 0x and 8 hex digits,
    as real files write them); any other text as written (the reader gives it back)."""
    from dcf2bin import values
    try:
        n = values.parse_int(values.split_numeric_comment(value)[0])
    except values.ValueProblem:
        return value
    if n < 0:
        return value
    return f"0x{n:08X}" if hex8 and n <= 0xFFFFFFFF else str(n)


def _boolean(value: str) -> str:
    n = _number(value)
    return {"0": "false", "1": "true"}.get(n, value)


class Header:
    """The parts of the file around the objects."""

    def __init__(self, dev, losses, *, xdc: bool, name: str | None, node_id: int | None):
        self.dev, self.losses, self.xdc = dev, losses, xdc
        self.name, self.node_id = name, node_id
        self.info = w.header(dev, "deviceinfo")

    def _get(self, sec, key: str) -> str | None:
        if sec is None:
            return None
        return sec.values.get(key.lower())

    def _attrs(self, pairs) -> str:
        out = []
        for name, value in pairs:
            escaped = attr(value)
            if escaped is None:
                self.losses.add("CNV007", None, name)
            else:
                out.append(f' {name}="{escaped}"')
        return "".join(out)

    # -- the file --------------------------------------------------------------------------
    def file_attrs(self) -> str:
        sec = w.header(self.dev, "fileinfo")
        pairs = []
        for key, name in FILE_INFO:
            value = self.name if key == "FileName" and self.name else self._get(sec, key)
            if value is None:
                continue
            if key.endswith("Date") and (m := _DATE.fullmatch(value.strip())):
                value = f"{m.group(3)}-{m.group(1)}-{m.group(2)}"
            elif key.endswith("Time") and (m := _TIME.fullmatch(value.strip())):
                hour = int(m.group(1)) % 12 + (12 if m.group(3) in "Pp" else 0)
                value = f"{hour:02d}:{m.group(2)}:00"
            pairs.append((name, value))
        if sec is not None:
            known = {k.lower() for k, _ in FILE_INFO} | FILE_INFO_SILENT
            self.left_out(sec, known)
        return self._attrs(pairs + [("supportedLanguages", "en")])

    def left_out(self, sec, known) -> None:
        """CNV005 for the keys of ``sec`` with a value that CiA 311 has no place for."""
        for low, k in sec.keys.items():
            if low not in known and k.value:
                self.losses.add("CNV005", None, f"{shorten(k.name)}={shorten(k.value)}", sec.line,
                                group=f"[{shorten(sec.name.strip())}]")

    def identity(self) -> list[str]:
        lines = ["\t\t\t<DeviceIdentity>"]
        for key, name, number in IDENTITY:
            value = self._get(self.info, key)
            if value is not None:
                shown = _number(value, hex8=True) if number and value else value
                lines.append(f"\t\t\t\t<{name}>{text(shown)}</{name}>")
        lines.append("\t\t\t</DeviceIdentity>")
        if self.info is not None:
            self.left_out(self.info, _DEVICE_INFO_KEYS)
        return lines

    # -- the network ----------------------------------------------------------------------
    def dummies(self) -> list[str]:
        sec = w.header(self.dev, "dummyusage")
        if sec is None:
            return []
        lines = ["\t\t\t\t<dummyUsage>"]
        for k in sec.keys.values():
            lines.append(f'\t\t\t\t\t<dummy entry="{attr(f"{k.name}={k.value}") or ""}"/>')
        return lines + ["\t\t\t\t</dummyUsage>"]

    def baud_rates(self) -> list[str]:
        rates = [rate for rate, key in BAUD_RATES.items()
                 if _number(self._get(self.info, key) or "0") == "1"]
        if not rates:
            return ["\t\t\t\t\t<baudRate/>"]
        return (["\t\t\t\t\t<baudRate>"]
                + [f'\t\t\t\t\t\t<supportedBaudRate value="{r}"/>' for r in rates]
                + ["\t\t\t\t\t</baudRate>"])

    def features(self, table) -> str:
        pairs = []
        for key, name, boolean in table:
            value = self._get(self.info, key)
            if value is not None and value != "":
                pairs.append((name, _boolean(value) if boolean else _number(value)))
        return self._attrs(pairs)

    def commissioning(self) -> list[str]:
        dev = self.dev
        sec = w.header(dev, "devicecomissioning") or w.header(dev, "devicecommissioning")
        if not self.xdc:
            if sec is not None and sec.keys:
                for k in sec.keys.values():
                    self.losses.add("CNV002", None, f"{k.name}={k.value}", sec.line,
                                    group="[DeviceComissioning]")
            return []
        pairs = []
        for key, name, kind in COMMISSIONING:
            value = self._get(sec, key)
            if key == "NodeID" and self.node_id is not None:
                value = str(self.node_id)
            if value is None:
                continue
            if key == "Baudrate" and _number(value).isdigit():
                value = f"{_number(value)} Kbps"
            elif kind is not None:
                value = _boolean(value) if kind else _number(value)
            pairs.append((name, value))
        if sec is not None:
            self.left_out(sec, {k.lower() for k, _, _ in COMMISSIONING})
        if not pairs:
            return []
        return [f"\t\t\t\t<deviceCommissioning{self._attrs(pairs)}/>"]

    def other_sections(self) -> None:
        """CNV005 for the sections of CiA 306 text CiA 311 has no place for."""
        ini = self.dev.ini
        if ini is None or ini.format != "ini":
            return
        from dcf2bin.formats.ini_writer import KNOWN, OBJECT_SECTION
        for canon, sec in ini.sections.items():
            if canon in ("fileinfo", "deviceinfo", "dummyusage", "devicecomissioning",
                         "devicecommissioning", "mandatoryobjects", "optionalobjects",
                         "manufacturerobjects"):
                continue
            if OBJECT_SECTION.fullmatch(canon):
                for low, k in sec.keys.items():
                    if low not in KNOWN:
                        self.losses.add("CNV005", int(canon[:4], 16),
                                        f"[{shorten(sec.name.strip())}] "
                                        f"{shorten(k.name)}={shorten(k.value)}")
                continue
            if canon.endswith(("name", "value", "denotation")) and canon[:4].isalnum():
                continue                    # CompactSubObj's: in the sub-objects
            self.losses.add("CNV005", None, f"[{shorten(sec.name.strip())}]", sec.line)

    # -- the document ------------------------------------------------------------------------
    def document(self, params: list[str], objects: list[str], encoding: str = "UTF-8") -> str:
        """The whole file as text; ``encoding``: the name its XML declaration gives."""
        files = self.file_attrs()
        product = self._get(self.info, "ProductName") or ""
        out = [f'<?xml version="1.0" encoding="{encoding}"?>',
               f'<ISO15745ProfileContainer xmlns="{NS}" xmlns:xsi="{XSI}">',
               "\t<ISO15745Profile>"]
        out += _profile_header("CANopen device profile", "Device", product)
        out.append(f'\t\t<ProfileBody xsi:type="ProfileBody_Device_CANopen" '
                   f'formatName="CANopen" formatVersion="1.0"{files}>')
        out += self.identity()
        if params:
            out += ["\t\t\t<ApplicationProcess>", "\t\t\t\t<parameterList>", *params,
                    "\t\t\t\t</parameterList>", "\t\t\t</ApplicationProcess>"]
        out += ["\t\t</ProfileBody>", "\t</ISO15745Profile>", "\t<ISO15745Profile>"]
        out += _profile_header("CANopen communication network profile",
                               "CommunicationNetwork", product)
        out.append(f'\t\t<ProfileBody xsi:type="ProfileBody_CommunicationNetwork_CANopen" '
                   f'formatName="CANopen" formatVersion="1.0"{files}>')
        out += ["\t\t\t<ApplicationLayers>", "\t\t\t\t<CANopenObjectList>", *objects,
                "\t\t\t\t</CANopenObjectList>", *self.dummies(), "\t\t\t</ApplicationLayers>",
                "\t\t\t<TransportLayers>", "\t\t\t\t<PhysicalLayer>", *self.baud_rates(),
                "\t\t\t\t</PhysicalLayer>", "\t\t\t</TransportLayers>",
                "\t\t\t<NetworkManagement>",
                f"\t\t\t\t<CANopenGeneralFeatures{self.features(GENERAL)}/>"]
        if self._get(self.info, "SimpleBootUpMaster") is not None:
            out.append(f"\t\t\t\t<CANopenMasterFeatures{self.features(MASTER)}/>")
        out += self.commissioning()
        out += ["\t\t\t</NetworkManagement>", "\t\t</ProfileBody>", "\t</ISO15745Profile>",
                "</ISO15745ProfileContainer>"]
        self.other_sections()
        return "\n".join(out) + "\n"


def _profile_header(identification: str, class_id: str, name: str) -> list[str]:
    return ["\t\t<ProfileHeader>",
            f"\t\t\t<ProfileIdentification>{identification}</ProfileIdentification>",
            "\t\t\t<ProfileRevision>1.1</ProfileRevision>",
            f"\t\t\t<ProfileName>{text(name)}</ProfileName>" if name else
            "\t\t\t<ProfileName/>",
            "\t\t\t<ProfileSource/>",
            f"\t\t\t<ProfileClassID>{class_id}</ProfileClassID>",
            "\t\t\t<ISO15745Reference>", "\t\t\t\t<ISO15745Part>1</ISO15745Part>",
            "\t\t\t\t<ISO15745Edition>1</ISO15745Edition>",
            "\t\t\t\t<ProfileTechnology>CANopen</ProfileTechnology>",
            "\t\t\t</ISO15745Reference>", "\t\t</ProfileHeader>"]

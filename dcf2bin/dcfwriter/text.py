"""Writing a ``DcfSpec`` as DCF text (bin2dcf, SPEC §4).

One object section per index, in ascending order, with ``ParameterValue`` the last
value written; earlier writes are comments above it. ``[DeviceInfo]`` and
``[DummyUsage]`` come from the EDS (``--eds``) where one is given, and
``[DynamicChannels]`` from the reconstructed segments. Nothing depends on the clock.

The objects every device has and the entries the PDOs map are added where the container
does not write them (``described``), so that the DCF is a complete one that validates,
and compiles to the same bytes (SPEC §4).
"""
from __future__ import annotations

from operator import attrgetter

from dcf2bin import datatypes as dt
from dcf2bin import dcfparts
from dcf2bin.dcfwriter.described import describe
from dcf2bin.dcfwriter.spec import DcfSpec, ObjSpec, SubSpec, value_text
from dcf2bin.layout import INPUT
from dcf2bin.model import is_pdo_mapping as is_mapping


def render(spec: DcfSpec, dcf_name: str, eds_device=None, options: list[str] = ()) -> str:
    """The DCF text; ``dcf_name`` goes into ``[FileInfo] FileName``; ``options``, the
    compile options that give the container's bytes back, into a comment."""
    return _Renderer(spec, dcf_name, eds_device, options).render()


class _Renderer:
    def __init__(self, spec: DcfSpec, dcf_name: str, eds_device, options=()):
        self.options = list(options)
        self.spec = spec
        self.dcf_name = dcf_name
        self.eds_device = eds_device
        self.objects = spec.objects
        self.channels = spec.channels
        self._names: dict[str, str] = {}     # a sub's name -> as written (_clean)

    def render(self) -> str:
        c = self.spec.container
        out: list[str] = []
        w = out.append
        n = len(c.entries)
        what = "a concise DCF, " if self.spec.concise else ""
        w(f"; DCF written by dcf2bin bin2dcf from {self.spec.name} "
          f"({what}{self.spec.header['total_size']} bytes, "
          f"{n} entr{'y' if n == 1 else 'ies'}).")
        w("; ParameterValue is the last value written to each entry; comments list earlier "
          "writes.")
        if self.spec.concise:
            w("; A DCF keeps no order of writes: dcf2bin dump lists the concise DCF's, and "
              "types without --eds are CiA 301's or guessed from the size.")
        if self.options:
            w(f"; compile it with {' '.join(self.options)} to get the container's bytes back.")
        w("")
        w("[FileInfo]")
        w(f"FileName={self.dcf_name}")
        w("FileVersion=1")
        w("FileRevision=0")
        w("EDSVersion=4.0")
        source = "concise DCF" if self.spec.concise else "binary DCF segment container"
        w(f"Description=Converted from the {source} {self.spec.name}")
        w("CreatedBy=dcf2bin bin2dcf")
        w("")
        self._device_info(w)
        self._dummy_usage(w)
        if self.channels:
            w("[DynamicChannels]")
            w(f"NrOfSeg={len(self.channels)}")
            for k, ch in enumerate(self.channels, 1):
                w(f"Type{k}=0x{ch.dtype.code:04X}")
                w(f"Dir{k}={'ro' if ch.direction == INPUT else 'rw'}")
                w(f"Range{k}=0x{ch.first:04X}-0x{ch.last:04X}")
                w(f"PPOffset{k}={ch.pp}")
            w("")
        extra = describe(self.spec, self.eds_device)
        self.extra = extra
        added = extra.objects
        idxs = sorted(i for i in (*self.objects, *added) if i >= 0x1000)
        required = [i for i in idxs if i in dcfparts.MANDATORY]
        manufacturer = [i for i in idxs if 0x2000 <= i <= 0x5FFF]
        optional = [i for i in idxs if i not in required and i not in manufacturer]
        for title, lst in (("MandatoryObjects", required), ("OptionalObjects", optional),
                           ("ManufacturerObjects", manufacturer)):
            w(f"[{title}]")
            w(f"SupportedObjects={len(lst)}")
            for k, i in enumerate(lst, 1):
                w(f"{k}=0x{i:04X}")
            w("")
        for index in sorted((*self.objects, *added)):
            if index in added:
                out.extend(added[index])
            else:
                self._object(out, self.objects[index])
        return "\n".join(out).rstrip("\n") + "\n"

    def _device_info(self, w) -> None:
        sec = None
        if self.eds_device is not None and self.eds_device.ini is not None:
            sec = self.eds_device.ini.section("deviceinfo")
        rx = sum(1 for i in self.objects if 0x1400 <= i <= 0x15FF)
        tx = sum(1 for i in self.objects if 0x1800 <= i <= 0x19FF)
        w("[DeviceInfo]")
        if sec is not None:
            for key, k in sec.keys.items():
                if key in ("compactpdo", "nrofrxpdo", "nroftxpdo") or not k.value:
                    continue       # CompactPDO would create objects the container lacks
                w(f"{k.name}={_clean(k.value)}")
        w(f"NrOfRXPDO={rx}")
        w(f"NrOfTXPDO={tx}")
        if self.channels:
            if sec is None or "dynamicchannelssupported" not in sec.keys:
                w(f"DynamicChannelsSupported={len(self.channels)}")
        w("")

    def _dummy_usage(self, w) -> None:
        dummies = set()
        for obj in self.objects.values():
            if not is_mapping(obj.index):
                continue
            for s in obj.subs.values():
                if s.sub and s.writes and len(s.data) == 4:
                    v = int.from_bytes(s.data, "little")
                    if 1 <= v >> 16 <= 7 and (v >> 8) & 0xFF == 0:
                        dummies.add(v >> 16)
        if self.eds_device is not None:
            dummies |= set(self.eds_device.dummy_usage)
        if dummies:
            w("[DummyUsage]")
            for code in sorted(dummies):
                w(f"Dummy{code:04X}=1")
            w("")

    def _object(self, out: list[str], obj: ObjSpec) -> None:
        w = out.append
        if obj.object_type == dt.OT_VAR:
            s = obj.subs[0]
            w(f"[{obj.index:04X}]\nParameterName={_clean(obj.name or s.name)}\nObjectType=0x7")
            w(self._keys(s))
            return
        index = obj.index
        more = self.extra.subs.get(index, ())
        w(f"[{index:04X}]\nParameterName={_clean(obj.name)}\n"
          f"ObjectType=0x{obj.object_type:X}\n"
          f"SubNumber={len(obj.subs) + self.extra.sub_count.get(index, 0)}\n")
        out.extend(more)    # entries a PDO maps that the container does not write
        names = self._names
        subs = list(obj.subs.values())
        if len(subs) > 2 and _alike(subs[1:]):
            # the subs after the first (sub 0, most often) differ in number, name and value
            # only, as the variables of a network-variable object: one template for them
            self._sub(w, subs[0])
            rest = subs[1:]
            for text in set(map(_NAME, rest)):
                if text not in names:
                    names[text] = _clean(text)
            s = rest[0]
            template = (f"[{index:04X}sub%X]\nParameterName=%s\nObjectType=0x7\n"
                        f"DataType=0x{s.dtype.code:04X}\n"
                        f"AccessType={s.access.replace('%', '%%')}\n"
                        f"PDOMapping={1 if s.pdo else 0}\nParameterValue=%s\n")
            out += map(template.__mod__, zip(map(_SUB, rest), map(names.__getitem__,
                                                                    map(_NAME, rest)),
                                             map(_VALUE, rest)))
            return
        for s in subs:
            self._sub(w, s)

    def _sub(self, w, s: SubSpec) -> None:
        names = self._names
        name = names.get(s.name)
        if name is None:
            name = names[s.name] = _clean(s.name)
        if len(s.writes) == 1 and not s.default and not s.note:   # _keys of one write
            w(f"[{s.index:04X}sub{s.sub:X}]\nParameterName={name}\nObjectType=0x7\n"
              f"DataType=0x{s.dtype.code:04X}\nAccessType={s.access}\n"
              f"PDOMapping={1 if s.pdo else 0}\nParameterValue={s.value}\n")
            return
        w(f"[{s.index:04X}sub{s.sub:X}]\nParameterName={name}\nObjectType=0x7")
        w(self._keys(s))

    def _keys(self, s: SubSpec) -> str:
        if len(s.writes) == 1 and not s.default and not s.note:
            return (f"DataType=0x{s.dtype.code:04X}\nAccessType={s.access}\n"
                    f"PDOMapping={1 if s.pdo else 0}\nParameterValue={s.value}\n")
        lines = self._earlier(s)
        if s.note:
            lines.append(s.note)
        if not s.writes:
            lines.append(f"; not in the {self.spec.what}: the sub 0 that compile implies")
        lines.append(f"DataType=0x{s.dtype.code:04X}")
        lines.append(f"AccessType={s.access}")
        if s.default:
            lines.append(f"DefaultValue={s.default}")
        lines.append(f"PDOMapping={1 if s.pdo else 0}")
        if s.writes:
            lines.append(f"ParameterValue={s.value}")
        return "\n".join(lines) + "\n"

    def _earlier(self, s: SubSpec) -> list[str]:
        """Comments for the writes before the last one (PDO reconfiguration sequences)."""
        out = []
        for w in s.writes[:-1]:
            text = value_text(s.dtype, w.data, self.spec.encoding)
            if text is None or "\n" in text or "\r" in text:
                text = w.data.hex().upper() or '""'
            out.append(f"; entry {w.pos + 1} (offset 0x{w.offset:X}) wrote {text}")
        if len(s.writes) > 1:
            out.append(f"; entry {s.writes[-1].pos + 1} (offset 0x{s.writes[-1].offset:X}) "
                       "wrote the ParameterValue below")
        return out


_SUB, _NAME, _VALUE = attrgetter("sub"), attrgetter("name"), attrgetter("value")

def _alike(subs: list[SubSpec]) -> bool:
    """Do ``subs`` all have one write (no DefaultValue) of one type, access and mapping?"""
    return len({(s.dtype.code, s.access, s.pdo, len(s.writes), s.default, s.note)
                for s in subs}) == 1 and len(subs[0].writes) == 1 and not subs[0].default \
        and not subs[0].note


def _clean(text: str) -> str:
    return text.replace("\r", " ").replace("\n", " ").strip() or '""'



__all__ = ["render"]

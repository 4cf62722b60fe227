"""The target's static object dictionary (SPEC §8.1, D-11).

A ``StaticOD`` answers "does the firmware already have this entry, and what is it?"
from a ``model.Device`` without copying it: the objects of ``exclude`` (the creation
group of D-8, when the device is the DCF being compiled) are not there.
"""
from __future__ import annotations

from dcf2bin import datatypes as dt


class StaticOD:
    """``complete`` False: the objects are known to exist, but what is absent may exist on
    the target too (a DCF that bin2dcf wrote describes a container, not the device)."""

    def __init__(self, dev, exclude: set[int] | frozenset[int] = frozenset(),
                 complete: bool = True):
        self.dev = dev
        self.exclude = exclude
        self.complete = complete
        self._objects = dev.objects

    @classmethod
    def from_device(cls, dev, exclude=frozenset()) -> StaticOD:
        return cls(dev, set(exclude), complete=not converted_from_container(dev))

    @classmethod
    def from_eds(cls, path: str, data: bytes | None = None) -> StaticOD:
        """Load an EDS/DCF as the static OD (its problems are the caller's to report)."""
        from dcf2bin import formats
        return cls(formats.load(path, data=data))

    def has(self, index: int) -> bool:
        return index in self._objects and index not in self.exclude

    def entry(self, index: int, sub: int):
        """The model ``Entry`` or None."""
        if index in self.exclude:
            return None
        obj = self._objects.get(index)
        return None if obj is None else obj.entries.get(sub)

    def indexes(self) -> list[int]:
        return sorted(i for i in self._objects if i not in self.exclude)

    def entries(self, index: int) -> dict:
        obj = None if index in self.exclude else self._objects.get(index)
        return {} if obj is None else obj.entries

    def data(self, entry) -> bytes | None:
        """The entry's value as the firmware holds it (ParameterValue, else DefaultValue),
        encoded; None when it has none or it cannot be encoded."""
        if entry.dtype is None or (entry.value_text is None and entry.download_file is None):
            return None
        try:
            return self.dev.encode(entry)
        except Exception:  # noqa: BLE001 - a bad value is lint's to report, not ours
            return None

    def int_value(self, entry) -> int | None:
        data = self.data(entry)
        if data is None or entry.dtype is None or not entry.dtype.is_integer:
            return None
        return int.from_bytes(data, "little")

    @staticmethod
    def fixed_size(entry) -> int | None:
        t = entry.dtype
        if t is None or t.size is None or not (t.kind == dt.BOOL or t.is_numeric):
            return None
        return t.size


def converted_from_container(dev) -> bool:
    """Was this DCF written by ``bin2dcf`` (``[FileInfo] CreatedBy=dcf2bin bin2dcf``)? It holds
    only what a container writes, not the device's other objects."""
    ini = getattr(dev, "ini", None)
    sec = ini.section("fileinfo") if ini is not None else None
    if sec is None or not sec.has("createdby"):
        return False
    return (sec.get("createdby") or "").strip().lower() == "dcf2bin bin2dcf"


__all__ = ["StaticOD", "converted_from_container"]

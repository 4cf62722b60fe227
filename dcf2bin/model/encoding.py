"""Values to bytes: how a ``Device`` encodes an entry's value text (``encode``: $NODEID,
DownloadFile) and reads it back as an integer.
"""
from __future__ import annotations

import os

from dcf2bin import datatypes as dt, values
from dcf2bin.diagnostics import DcfError, shorten
from dcf2bin.model.objects import Entry
from dcf2bin.model.sections import _clip


# The largest DownloadFile read (bytes); the file's own size, not its name, decides.
MAX_DOWNLOAD_FILE = 16 << 20


class _Encoding:
    """How a ``Device`` turns an entry's value text into its exact bytes (``encode``), with
    $NODEID and DownloadFile, and reads it back as an integer.
    """

    # -- values ------------------------------------------------------------------------
    def encode(self, entry: Entry, text: str | None = None) -> bytes:
        """Encode an entry's effective value (or ``text``) to its exact bytes.

        Raises DcfError naming the value's file:line.
        """
        dtype = entry.dtype
        if dtype is None:
            raise DcfError(f"{entry.label} has no valid DataType", entry.where)
        if text is None:
            if entry.param is None and entry.download_file is not None:
                return self._download(entry)
            text = entry.value_text
            where = None  # worked out only for a diagnostic (entry.value_where)
        else:
            where = entry.where
        if text is None:
            return values.zero(dtype)
        cache_key = (dtype.code, text)
        data = self.encoded.get(cache_key)
        if data is not None:
            return data
        cache = len(self.encoded) < 4096
        if (";" in text or "#" in text) and (dtype.is_numeric or dtype.kind == dt.BOOL):
            number, comment = values.split_numeric_comment(text)
            if comment is not None:
                cache = False   # every entry that has the comment gets its own warning
                text = number
                if (entry.index, entry.sub) not in self._warned:
                    self._warned.add((entry.index, entry.sub))
                    self.warning(f"{entry.label}: comment '{shorten(comment)}' after the number is "
                                 "ignored", where or entry.value_where, entry.index, entry.sub,
                                 rule="DCF203")
        try:
            data = values.encode(dtype, text, node_id=self.node_id, encoding=self.encoding)
        except values.NeedsNodeId:
            where = where or entry.value_where
            raise DcfError(
                f"value '{shorten(text)}' of {entry.label} uses $NODEID but no node-ID is known",
                where, rule="DCF201",
                hint="give --node-id N or set NodeID in [DeviceComissioning]") from None
        except values.ValueProblem as exc:
            where = where or entry.value_where
            raise DcfError(f"{entry.label}: {_clip(str(exc))}", where, rule="DCF200") from None
        if cache:
            self.encoded[cache_key] = data
        return data

    def _download(self, entry: Entry) -> bytes:
        """The bytes of a DownloadFile (SPEC §1). Symlinks are resolved before the check
        that the file stays in the DCF's folder; only a regular file of at most
        MAX_DOWNLOAD_FILE bytes is read (a FIFO, a device or a directory never is),
        through the one bounded reader (``fileio.read_file``), which opens without
        blocking, so a FIFO cannot hang the read."""
        where = entry.key_where("downloadfile")
        name = entry.download_file or ""
        shown = _clip(name, 80)
        if "\0" in name:
            raise DcfError(f"DownloadFile '{shown}' contains a NUL byte", where, rule="DCF202")
        base = os.path.realpath(os.path.dirname(os.path.abspath(self.path)))
        if os.path.isabs(name) and not self.allow_external_files:
            raise DcfError(f"DownloadFile '{shown}' is an absolute path", where, rule="DCF202",
                           hint="use a path relative to the DCF, or --allow-external-files")
        full = os.path.realpath(os.path.join(base, name))
        if not self.allow_external_files and os.path.commonpath([base, full]) != base:
            leaves = "leaves" if os.path.commonpath([base, os.path.normpath(
                os.path.join(base, name))]) != base else "leads through a symbolic link out of"
            raise DcfError(f"DownloadFile '{shown}' {leaves} the DCF's folder", where,
                           rule="DCF202", hint="use --allow-external-files to permit it")
        from dcf2bin.fileio.reading import InputTooLarge, NotARegularFile, read_file
        try:
            return read_file(full, limit=MAX_DOWNLOAD_FILE, descriptors=False)
        except (NotARegularFile, IsADirectoryError):
            raise DcfError(f"DownloadFile '{shown}' is not a regular file", where,
                           rule="DCF202", hint="name a regular file, not a device, pipe "
                           "or directory") from None
        except InputTooLarge:
            raise DcfError(f"DownloadFile '{shown}' is larger than {MAX_DOWNLOAD_FILE >> 20} MiB",
                           where, rule="DCF202", hint="a DOMAIN value this large cannot be "
                           "meant for a container") from None
        except OSError as exc:
            raise DcfError(f"cannot read DownloadFile '{shown}': {exc.strerror}", where,
                           rule="DCF202") from None

    def effective_int(self, entry: Entry) -> int:
        """The effective value of an integer entry as a Python int (raises DcfError)."""
        data = self.encode(entry)
        signed = entry.dtype is not None and entry.dtype.kind == dt.SINT
        return int.from_bytes(data, "little", signed=signed)

    def default_int(self, entry: Entry) -> int | None:
        """The DefaultValue of an integer entry as a Python int, None without one (D-12:
        the COB-ID a DIS-2 drive has). Raises DcfError at the DefaultValue's line."""
        text, dtype = entry.default, entry.dtype
        if text is None or dtype is None:
            return None
        number = text
        if dtype.is_numeric or dtype.kind == dt.BOOL:
            number = values.split_numeric_comment(text)[0]
        where = entry.key_where("defaultvalue")
        try:
            data = values.encode(dtype, number, node_id=self.node_id, encoding=self.encoding)
        except values.NeedsNodeId:
            raise DcfError(
                f"value '{shorten(text)}' of {entry.label} uses $NODEID but no node-ID is known",
                where, rule="DCF201",
                hint="give --node-id N or set NodeID in [DeviceComissioning]") from None
        except values.ValueProblem as exc:
            raise DcfError(f"{entry.label} DefaultValue: {_clip(str(exc))}", where,
                           rule="DCF200") from None
        return int.from_bytes(data, "little", signed=dtype.kind == dt.SINT)

"""Extra writes: ordered write sequences appended after a DCF's entries.

A DCF can say only one value per (index, subindex). Some devices need the same entry
written several times, in order — the Metronix DIS-2 communication-object tunnel (SPEC §6,
seed 004) writes 0x2200 sub 0 to select a KO, then 0x2214 sub 0 to set it, and again for
the next KO. ``compile --append FILE`` adds such writes after every D-8 group, in file order,
with their attribute bytes and without PI addresses.

The text format ("extra-writes file", suffix ``.writes`` by convention)::

    # comment line (also ';')
    # INDEX  SUB   TYPE        VALUE        [ACCESS] [map]   ; trailing comment
    0x2200   0x00  UNSIGNED32  0x0000001A   rw               ; select KO 0x001A
    0x2214   0     UNSIGNED32  1            wo               ; KO 0x001A := 1
    0x2000   1     VISIBLE_STRING "two words"

* One write per line, executed in file order; the same entry may be written any number
  of times. Blank lines are ignored.
* ``#`` or ``;`` starts a comment at the start of a line or after a blank (outside quotes).
* INDEX: hexadecimal with ``0x``, 0x1000..0xFFFF (a bare ``2200`` is refused: it would be
  decimal). SUB: an integer 0..255 in any SPEC §1 form (``0``, ``0x00``).
* TYPE: a data type name of SPEC §1 (any case) or its code (``0x0007``).
* VALUE: as a DCF ``ParameterValue`` of that type (SPEC §1: integer forms, ``$NODEID``
  formulas, REAL literals or raw ``0x`` bits, hex byte pairs for OCTET_STRING/DOMAIN,
  ``""`` for an empty string). A value holding blanks, ``;`` or ``#`` is written in double
  quotes; it may not itself contain a double quote.
* ACCESS (optional, default ``rw``): ro, wo, rw, rwr, rww or const; it decides the
  attribute byte by D-9 (rw UNSIGNED32 -> 0x70, wo -> 0x50). ``map`` adds the PDO bit 0x80.
  Entries in 0xA000-0xAFFF get the network-variable attributes of SPEC §3.3.
* The file is UTF-8 (a BOM is skipped) if it decodes so, else Latin-1; VISIBLE_STRING
  values are written in the file's own encoding, as in a DCF.

Errors are one-line ``file:line`` diagnostics; ``load_extra_writes`` raises
``ExtraWritesError`` (a ``DcfError``) carrying all of them.
"""
from __future__ import annotations

from dataclasses import dataclass

from dcf2bin import datatypes as dt
from dcf2bin import values
from dcf2bin.diagnostics import DcfError, Diagnostic, Where, shorten
from dcf2bin.ini import decode_bytes

__all__ = ["ExtraWrite", "ExtraWritesError", "read_extra_writes", "load_extra_writes",
           "parse_extra_writes", "tunnel_writes", "format_write", "TUNNEL_SELECT",
           "TUNNEL_WRITE", "TUNNEL_READ", "READ_MODES"]

# The Metronix DIS-2 communication-object tunnel (seed 004); all three are UINT32 sub 0.
TUNNEL_SELECT = 0x2200   # read_write_ko, rw: low word KO number, high word read mode
TUNNEL_READ = 0x2204     # read_ko, ro: value of the selected KO (SDO upload)
TUNNEL_WRITE = 0x2214    # write_ko, wo: 32-bit value written into the selected KO
READ_MODES = {"value": 0, "min": 2, "max": 3}   # high word of 0x2200 for reads

_BLANKS = " \t"
_ACCESS = ("ro", "wo", "rw", "rwr", "rww", "const")
_R_SYNTAX, _R_INDEX, _R_SUB, _R_TYPE, _R_ACCESS = "XW001", "XW002", "XW003", "XW004", "XW005"


@dataclass(slots=True)
class ExtraWrite:
    """One parsed line: the write itself plus where it came from."""
    write: "object"          # select.Write (typed loosely to keep imports lazy)
    where: Where
    dtype: dt.DataType
    access: str
    value_text: str
    comment: str = ""


class ExtraWritesError(DcfError):
    """Problems in an extra-writes file.

    ``diagnostics`` holds all of them; ``diagnostic`` (as in every DcfError) is the first.
    """

    def __init__(self, diagnostics: list[Diagnostic]):
        first = diagnostics[0]
        super().__init__(first.message, Where(first.file, first.line), rule=first.rule,
                         hint=first.hint)
        self.diagnostics = list(diagnostics)


def _tokens(line: str) -> tuple[list[tuple[str, bool]], str, str | None]:
    """Split a line into (token, quoted) pairs and a trailing comment.

    Returns (tokens, comment, problem); ``problem`` names an unterminated quote.
    """
    tokens: list[tuple[str, bool]] = []
    i, n = 0, len(line)
    while i < n:
        ch = line[i]
        if ch in _BLANKS:
            i += 1
            continue
        if ch in "#;" and (i == 0 or line[i - 1] in _BLANKS):
            return tokens, line[i + 1:].strip(_BLANKS), None
        if ch == '"':
            end = line.find('"', i + 1)
            if end < 0:
                return tokens, "", "unterminated double quote"
            after = line[end + 1:end + 2]
            if after and after not in _BLANKS:
                return tokens, "", "a closing double quote must be followed by a blank"
            tokens.append((line[i:end + 1], True))
            i = end + 1
            continue
        j = i
        while j < n and line[j] not in _BLANKS:
            j += 1
        tokens.append((line[i:j], False))
        i = j
    return tokens, "", None


def _dtype(text: str) -> dt.DataType | None:
    t = dt.BY_NAME.get(text.upper())
    if t is not None:
        return t
    try:
        return dt.BY_CODE.get(values.parse_int(text))
    except values.ValueProblem:
        return None


def parse_extra_writes(text: str, path: str, *, node_id: int | None = None,
                       encoding: str = "utf-8") -> tuple[list[ExtraWrite], list[Diagnostic]]:
    """Parse extra-writes text -> (writes, error diagnostics). Never raises for bad input."""
    from dcf2bin.model import Entry
    from dcf2bin.select import Write, attribute

    out: list[ExtraWrite] = []
    errors: list[Diagnostic] = []

    def err(line_no: int, message: str, rule: str, hint: str = "") -> None:
        errors.append(DcfError(message, Where(path, line_no), rule=rule, hint=hint).diagnostic)

    for line_no, raw in enumerate(text.split("\n"), 1):
        line = raw[:-1] if raw.endswith("\r") else raw
        tokens, comment, problem = _tokens(line)
        if problem:
            err(line_no, problem, _R_SYNTAX)
            continue
        if not tokens:
            continue
        if len(tokens) < 4:
            err(line_no, f"expected INDEX SUB TYPE VALUE [ACCESS] [map], got {len(tokens)} "
                "field(s)", _R_SYNTAX, hint="quote a value that holds blanks: \"a b\"")
            continue
        (idx_t, idx_q), (sub_t, _), (type_t, _), (val_t, val_q) = tokens[:4]
        # INDEX
        if idx_q or idx_t[:2] not in ("0x", "0X"):
            err(line_no, f"index '{shorten(idx_t)}' must be hexadecimal with 0x (e.g. "
                         "0x2200)", _R_INDEX)
            continue
        try:
            index = values.parse_int(idx_t)
        except values.ValueProblem as exc:
            err(line_no, f"index: {exc}", _R_INDEX)
            continue
        if not 0x1000 <= index <= 0xFFFF:
            err(line_no, f"index {idx_t} is outside 0x1000..0xFFFF", _R_INDEX)
            continue
        # SUB
        try:
            sub = values.parse_int(sub_t)
        except values.ValueProblem as exc:
            err(line_no, f"subindex: {exc}", _R_SUB)
            continue
        if not 0 <= sub <= 0xFF:
            err(line_no, f"subindex {sub_t} is outside 0..255", _R_SUB)
            continue
        # TYPE
        dtype = _dtype(type_t)
        if dtype is None:
            err(line_no, f"unknown data type '{shorten(type_t)}'", _R_TYPE,
                hint="use a CiA 306 name such as UNSIGNED32, or its code such as 0x0007")
            continue
        # ACCESS / map
        access, mappable, bad = "rw", False, False
        seen_access = False
        for tok, quoted in tokens[4:]:
            low = tok.lower()
            if not quoted and low in _ACCESS and not seen_access:
                access, seen_access = low, True
            elif not quoted and low == "map" and not mappable:
                mappable = True
            else:
                err(line_no, f"unexpected field '{shorten(tok)}' after the value (expected an "
                             "access "
                    "type ro/wo/rw/rwr/rww/const and/or 'map')", _R_ACCESS,
                    hint="quote a value that holds blanks: \"a b\"")
                bad = True
                break
        if bad:
            continue
        # VALUE
        text_for_encode = val_t
        if val_q and dtype.kind not in (dt.VSTRING, dt.USTRING):
            text_for_encode = val_t[1:-1]
        if dtype.is_numeric or dtype.kind == dt.BOOL:
            text_for_encode = text_for_encode.strip(_BLANKS)
        where = Where(path, line_no)
        try:
            data = values.encode(dtype, text_for_encode, node_id=node_id, encoding=encoding)
        except values.NeedsNodeId:
            errors.append(DcfError(
                f"value '{shorten(val_t)}' uses $NODEID but no node-ID is "
                "known", where, rule="DCF201",
                hint="give --node-id N").diagnostic)
            continue
        except values.ValueProblem as exc:
            errors.append(DcfError(f"0x{index:04X}sub{sub:X}: {exc}", where,
                                   rule="DCF200").diagnostic)
            continue
        entry = Entry(index, sub, dtype=dtype, access=access, pdo_mapping=mappable)
        w = Write(index, sub, data, attribute(entry))
        out.append(ExtraWrite(w, where, dtype, access, val_t, comment))
    return out, errors


def read_extra_writes(path: str, data: bytes | None = None, *,
                      node_id: int | None = None) -> list[ExtraWrite]:
    """Read an extra-writes file (or ``data``) -> parsed lines; raises ExtraWritesError."""
    if data is None:
        from dcf2bin.fileio.reading import read_file
        try:
            data = read_file(path)
        except OSError as exc:
            raise ExtraWritesError([DcfError(f"cannot read: {exc.strerror}",
                                             Where(path)).diagnostic]) from None
    text, encoding = decode_bytes(data)  # as a DCF (SPEC §1)
    writes, errors = parse_extra_writes(text, path, node_id=node_id, encoding=encoding)
    if errors:
        raise ExtraWritesError(errors)
    return writes


def load_extra_writes(path: str, data: bytes | None = None, *,
                      node_id: int | None = None) -> list:
    """The writes of an extra-writes file as ``select.Write`` objects, in file order.

    ``data``: the file's bytes when already read (``path`` then only names it in
    diagnostics). ``node_id``: for ``$NODEID`` values. Raises ``ExtraWritesError``
    (a ``DcfError``; ``.diagnostics`` lists every problem, each with file:line).
    """
    return [x.write for x in read_extra_writes(path, data, node_id=node_id)]


# -- writing -------------------------------------------------------------------------------

def format_write(index: int, sub: int, type_name: str, value: str, access: str = "",
                 comment: str = "") -> str:
    """One aligned line of the extra-writes format."""
    line = f"0x{index:04X}  0x{sub:02X}  {type_name:<10}  {value:<10}"
    if access:
        line += f"  {access:<3}"
    if comment:
        line += f"  ; {comment}"
    return line.rstrip()


def _u32(value: int) -> int:
    if -0x80000000 <= value < 0:
        return value & 0xFFFFFFFF
    if not 0 <= value <= 0xFFFFFFFF:
        raise ValueError(f"value {value} does not fit 32 bits")
    return value


def tunnel_writes(assignments: list[tuple[int, int]], read_ko: list[int], *,
                  read_mode: int = 0, source: str = "") -> str:
    """The extra-writes text of DIS-2 tunnel accesses (seed 004).

    ``assignments``: (KO number, value) pairs, written in order: 0x2200 := KO, then
    0x2214 := value (32 bits; a negative value is written as its two's complement).
    ``read_ko``: KOs selected for reading, in order: 0x2200 := read_mode << 16 | KO. A
    container only writes; the read itself is an SDO upload of 0x2204 sub 0 at run time,
    which returns the KO selected last. Raises ValueError for a KO outside 0..0xFFFF, a
    value that does not fit 32 bits, or an unknown read mode.
    """
    if read_mode not in READ_MODES.values():
        raise ValueError(f"read mode {read_mode} is not 0 (value), 2 (min) or 3 (max)")
    for ko in [a[0] for a in assignments] + list(read_ko):
        if not 0 <= ko <= 0xFFFF:
            raise ValueError(f"KO number {ko} is outside 0..0xFFFF")
    mode_name = {v: k for k, v in READ_MODES.items()}[read_mode]
    lines = [
        "# dcf2bin extra writes: Metronix DIS-2 communication-object (KO) tunnel",
        "# (Metronix Application Note 83a). Append to the drive's DCF with",
        "#   dcf2bin compile DRIVE.dcf --profile dis2 --append THIS_FILE",
        "# 0x2200 read_write_ko UNSIGNED32 rw: low word = KO number; high word = read mode",
        "#        (0 current value, 2 lower limit, 3 upper limit; ignored for writes)",
        "# 0x2214 write_ko      UNSIGNED32 wo: 32-bit value written into the selected KO",
        "# 0x2204 read_ko       UNSIGNED32 ro: value of the selected KO, read by SDO at run",
        "#        time (a container only writes: a read is prepared by selecting the KO)",
    ]
    if source:
        lines.append(f"# made by: {source}")
    lines += ["#", "#index  sub   type        value       access"]
    for ko, value in assignments:
        v = _u32(value)
        lines.append(format_write(TUNNEL_SELECT, 0, "UNSIGNED32", f"0x{ko:08X}", "rw",
                                  f"KO 0x{ko:04X}: select"))
        lines.append(format_write(TUNNEL_WRITE, 0, "UNSIGNED32", f"0x{v:08X}", "wo",
                                  f"KO 0x{ko:04X} := 0x{v:08X}"))
    for ko in read_ko:
        lines.append(format_write(TUNNEL_SELECT, 0, "UNSIGNED32",
                                  f"0x{read_mode << 16 | ko:08X}", "rw",
                                  f"KO 0x{ko:04X}: select for reading through 0x2204 "
                                  f"({mode_name})"))
    if len(read_ko) > 1:
        lines.append(f"# note: 0x2204 reads the KO selected last (0x{read_ko[-1]:04X})")
    return "\n".join(lines) + "\n"

"""The Python API of dcf2bin: each command as a function (docs/api.md).

Import the names from the package; they load on first use, so ``import dcf2bin``
itself stays cheap::

    >>> import dcf2bin
    >>> res = dcf2bin.compile_path("samples/plc.dcf")
    >>> res.ok, res.data == open("samples/plc.bin", "rb").read()
    (True, True)
    >>> dcf2bin.to_dcf("samples/plc.bin").roundtrip
    True

Findings are ``Diagnostic`` values (severity, message, file, line or byte offset,
rule), the same the command line prints. Two kinds of function deliver them:

* those that return a result object (``compile_path``, ``to_dcf``, ``validate``)
  put every finding into it;
* those that return one value (``compile_file``, ``read_container``, ``dump_json``,
  ``dump_text``, ``from_json``) raise ``CompileError`` or ``ReadError`` on errors --
  both carry ``diagnostics`` -- and deliver each warning through ``warnings.warn``
  as a ``DiagnosticWarning`` (its ``diagnostic`` holds the finding).

A file that cannot be read raises ``OSError``, as ``open`` does. Containers may be
given as bytes (the content), as a path (``str`` or ``os.PathLike``) or as a
``BinContainer``. Every argument is checked as the command line checks its option
(``dcf2bin.argspec``): a value the command would refuse raises ``ValueError`` in its
words (``node_id: 200 is not in the range 1<=x<=127``), one of the wrong type
``TypeError``.
"""
from __future__ import annotations

import json
import os
import warnings
from collections.abc import Iterable

from dcf2bin import argspec as spec
from dcf2bin import dcfwriter
from dcf2bin import dump as _dump
from dcf2bin import formats as _formats
from dcf2bin.compiler import CompileError, CompileOptions, compile_file, compile_path
from dcf2bin.compiler import Result as CompileResult
from dcf2bin.container import BinContainer
from dcf2bin.dcfwriter import Result as DcfResult
from dcf2bin.diagnostics import Diagnostic, DiagnosticWarning, Severity
from dcf2bin.fileio import read_file
from dcf2bin.model import Device
from dcf2bin.network import configure as _configure
from dcf2bin.network import load_network as _load_network
from dcf2bin.network.build import BuildResult
from dcf2bin.network.model import Network

__all__ = ["BinContainer", "CompileError", "CompileOptions", "CompileResult", "DcfResult",
           "Device", "Diagnostic", "DiagnosticWarning", "ReadError", "Severity",
           "compile_file", "compile_path", "dump_json", "dump_text", "from_json", "load",
           "read_container", "to_dcf", "validate",
           "BuildResult", "Network", "build_network", "check_network", "configure_network",
           "load_network"]

Container = bytes | str | os.PathLike | BinContainer


class ReadError(ValueError):
    """A container (or JSON dump) that cannot be read; ``diagnostics`` name the byte
    offset (or line) and the rule, as ``dcf2bin dump`` and ``compile`` print them."""

    def __init__(self, diagnostics: list[Diagnostic]):
        self.diagnostics = diagnostics
        super().__init__("\n".join(d.format() for d in diagnostics
                                   if d.severity is Severity.ERROR))


def read_container(source: Container, *, name: str | None = None) -> BinContainer:
    """Decode a container: entries, attributes, PI segments, and whatever is odd about
    its layout (so that ``BinContainer.to_bytes()`` gives the same bytes back).

    ``name`` names the source in diagnostics (default: the path, or ``<bytes>``).
    Raises ``ReadError`` when the bytes are no container; warnings (a non-canonical
    layout, a segment count that disagrees) go through ``warnings.warn``.

        >>> c = read_container("samples/bild8.bin")
        >>> len(c.entries), c.addresses
        (6, [0, 1, 2, 4])
        >>> c.to_bytes() == open("samples/bild8.bin", "rb").read()
        True
    """
    c, _, diags = _read(source, name)
    _warn(diags)
    return c


def dump_json(source: Container, *, name: str | None = None) -> str:
    """The lossless JSON form of a container (``dcf2bin dump --format json``); schema in
    docs/dump.md. ``from_json`` turns it back into the same bytes.

        >>> data = open("samples/plc.bin", "rb").read()
        >>> from_json(dump_json(data)) == data
        True
    """
    c, _, diags = _read(source, name)
    _warn(diags)
    return _dump.to_json(c)


def dump_text(source: Container, *, eds: str | os.PathLike | None = None, full: bool = False,
              name: str | None = None) -> str:
    """The readable report of ``dcf2bin dump``: header, entries with decoded values and
    attribute bits, process image. ``eds``: the device's EDS/DCF, for exact types and
    names; ``full``: long data in full.

        >>> print(dump_text("samples/bild8.bin").splitlines()[0])
        samples/bild8.bin: binary DCF segment container, 127 bytes, canonical layout
    """
    spec.check("full", full, spec.FLAG)
    c, shown, diags = _read(source, name)
    info, _, eds_diags = _eds(eds)
    _warn(diags + eds_diags)
    return _dump.report(c, shown, eds=info, full=full)


def from_json(doc: str | bytes | dict, *, name: str = "<json>") -> bytes:
    """The container bytes of a lossless JSON dump (text, bytes or the parsed ``dict``),
    as ``dcf2bin compile FILE.json`` builds them. Raises ``ReadError`` on a document
    that is not a valid dump (the diagnostics name the line)."""
    spec.check("name", name, spec.TEXT)
    if not isinstance(doc, (str, bytes, bytearray, memoryview, dict)):
        raise TypeError(f"doc must be a str, bytes or a dict, not {type(doc).__name__}")
    if isinstance(doc, dict):
        doc = json.dumps(doc, indent=1)
    data = doc.encode("utf-8") if isinstance(doc, str) else bytes(doc)
    out, diags = _dump.from_json_bytes(data, name)
    if out is None:
        raise ReadError(diags)
    _warn(diags)
    return out


def to_dcf(source: Container, *, eds: str | os.PathLike | None = None,
           dcf_name: str | None = None, name: str | None = None) -> DcfResult:
    """A container as DCF text (``bin2dcf``), which compiles back to the same bytes
    whenever a DCF can say what the container holds.

    The result has ``text`` (write it with ``to_bytes()``, which uses the file's
    encoding), ``diagnostics`` (B2Dxxx warnings name what will not compile back, and
    the container's own warnings), ``roundtrip`` (compile with default options gives
    the container's bytes) and ``options`` (the compile options that give them
    otherwise, e.g. ``["--entries all"]``). ``eds``: the device's EDS, for exact types,
    access and names; ``dcf_name`` goes into ``[FileInfo] FileName``.
    Raises ``ReadError`` when the bytes are no container.

        >>> res = to_dcf("samples/bild8.bin")
        >>> res.roundtrip, res.diagnostics, res.text.count("[A4C0sub")
        (True, [], 4)
        >>> compile_path("bild8.dcf", data=res.to_bytes()).data == \\
        ...     open("samples/bild8.bin", "rb").read()
        True
    """
    spec.check("dcf_name", dcf_name, spec.TEXT, optional=True)
    c, shown, diags = _read(source, name)
    info, dev, eds_diags = _eds(eds)
    if dcf_name is None:
        base = os.path.basename(shown) if isinstance(source, (str, os.PathLike)) else "container"
        dcf_name = os.path.splitext(base)[0] + ".dcf"
    res = dcfwriter.convert(c, shown, dcf_name=dcf_name, eds=info, eds_device=dev)
    res.diagnostics[:0] = diags + eds_diags
    return res


def validate(paths: str | os.PathLike | Iterable[str | os.PathLike], *,
             select: str | Iterable[str] | None = None,
             ignore: str | Iterable[str] | None = None, profile: str = "cia301",
             node_id: int | None = None, pi_size: int | None = None, pi_align: int = 8,
             address_base: str = "image", allow_external_files: bool = False
             ) -> list[Diagnostic]:
    """Lint DCF/EDS files, containers and directories (``dcf2bin validate``): every
    finding (errors, warnings and infos), file by file.

    ``select``/``ignore`` pick rules by id, id prefix (``"DCF4"``, ``"CNT"``) or name,
    one string (comma-separated) or several; an unknown one raises ``ValueError``.
    An unreadable path is an ``IO001`` finding, not an exception.

        >>> [(d.severity.value, d.line, d.rule) for d in validate("samples/bench_plc.dcf",
        ...                                                       select="DCF3")]
        [('info', 243, 'DCF320')]
        >>> [d.rule for d in validate(["samples/bild8.bin"], select="CNT")]
        []
    """
    from dcf2bin.lint import Options, resolve, run
    paths = _paths(paths)
    spec.check_all(dict(profile=profile, node_id=node_id, pi_size=pi_size, pi_align=pi_align,
                        address_base=address_base, allow_external_files=allow_external_files),
                   _VALIDATE_ARGS)
    active = resolve(_names("select", select), _names("ignore", ignore))
    opts = Options(node_id=node_id, pi_size=pi_size, pi_align=pi_align,
                   address_base=address_base, profile=profile,
                   allow_external_files=allow_external_files, active=active)
    return run(paths, opts).diagnostics


#: validate's arguments -> (spec, None allowed), as the command's options take them
_VALIDATE_ARGS = {"profile": (spec.PROFILE, False), "node_id": (spec.NODE_ID, True),
                  "pi_size": (spec.COUNT, True), "pi_align": (spec.PI_ALIGN, False),
                  "address_base": (spec.ADDRESS_BASE, False),
                  "allow_external_files": (spec.FLAG, False)}


def load(path: str | os.PathLike, *, node_id: int | None = None,
         allow_external_files: bool = False, data: bytes | None = None) -> Device:
    """Read a device description (DCF/EDS, CiA 311 XDD/XDC) into the model compile works
    from (``Device``): problems are collected in its ``problems``, never raised; a file
    that cannot be read raises ``OSError``. ``node_id`` (1..127) resolves ``$NODEID``, as
    ``--node-id`` does.

        >>> dev = load("samples/plc.dcf")
        >>> dev.node_id, len(dev.objects)
        (16, 12)
    """
    spec.check("path", path, spec.PATH)
    spec.check("node_id", node_id, spec.NODE_ID, optional=True)
    spec.check("allow_external_files", allow_external_files, spec.FLAG)
    spec.check("data", data, spec.BYTES, optional=True)
    return _formats.load(os.fspath(path), node_id=node_id,
                         allow_external_files=allow_external_files,
                         data=None if data is None else bytes(data))


# -- networks --------------------------------------------------------------------------------

def load_network(path: str | os.PathLike, *, data: bytes | None = None) -> Network:
    """Read a network file (lely's dcfgen YAML, ros2_canopen's ``bus.yml``) into a
    ``Network`` of ``Node``s, not yet configured. Findings are in its ``diagnostics``;
    a file that cannot be read raises ``OSError``.

        >>> net = load_network("tests/golden/network/flat/bus.yml")
        >>> [(n.name, n.node_id, n.role) for n in net.nodes]
        [('plc', 1, 'master'), ('drive', 2, 'slave'), ('io', 5, 'slave')]
    """
    _path_and_data(path, data)
    return _load_network(os.fspath(path), None if data is None else bytes(data))


def configure_network(network: Network) -> Network:
    """Configure a loaded network in memory, as ``network build`` does: PDOs, COB-IDs,
    the PLC's mirrors and variables, its NMT entries, each slave's write list
    (``Node.writes``). Changes ``network`` and returns it; findings are added to its
    ``diagnostics``.

        >>> net = configure_network(load_network("tests/golden/network/flat/bus.yml"))
        >>> [(v.name, hex(v.pi_index), v.pi_sub) for v in net.variables][:2]
        [('drive_status', '0xa100', 1), ('drive_position', '0xa1c0', 2)]
        >>> [hex(w.index) for w in net.node(2).writes][-2:]
        ['0x1017', '0x6060']
    """
    if not isinstance(network, Network):
        raise TypeError(f"network must be a Network (from load_network), not "
                        f"{type(network).__name__}")
    return _configure(network)


def build_network(path: str | os.PathLike, outdir: str | os.PathLike | None = None, *,
                  data: bytes | None = None) -> BuildResult:
    """Load, configure and check a network and make its outputs (``dcf2bin network
    build``): ``outputs`` maps each file name (``<master>.dcf``, ``<slave>.bin``,
    ``<slave>.dcf``) to its bytes, empty when there is an error; ``ok``, ``diagnostics``
    and the configured ``network`` as for the other results. With ``outdir`` the files
    are written there (all or none).

        >>> res = build_network("tests/golden/network/flat/bus.yml")
        >>> res.ok, sorted(res.outputs)
        (True, ['drive.bin', 'drive.dcf', 'io.bin', 'io.dcf', 'plc.dcf'])
    """
    from dcf2bin.network.build import build_network as _build
    _path_and_data(path, data)
    spec.check("outdir", outdir, spec.PATH, optional=True)
    return _build(os.fspath(path), None if outdir is None else os.fspath(outdir),
                  data=None if data is None else bytes(data))


def check_network(path: str | os.PathLike, *, select: str | Iterable[str] | None = None,
                  ignore: str | Iterable[str] | None = None, max_load: float = 80.0,
                  net: int | None = None):
    """Check a network file -- a lely/ros2_canopen ``bus.yml`` or a CiA 306-3 ``.cpj``
    project -- as a whole (``dcf2bin network check``). Returns a result with
    ``network`` (the configured network: nodes, PDOs, variables), ``diagnostics`` (every
    finding: the network file's, each node's file as ``validate`` reads it, the NET2xx
    rules between nodes), ``load`` (the bus-load estimate, per COB-ID), ``ok`` and
    ``exit_code(strict)``.

    ``select``/``ignore`` pick rules as ``validate``'s do (``"NET2"``, ``"NET210"``,
    ``"cob-id-produced-twice"``); an unknown one raises ``ValueError``. ``net`` picks the
    ``[TopologyN]`` of a ``.cpj``. A file that cannot be read is an ``IO001`` finding.

        >>> res = check_network("tests/fixtures/network/check/network.cpj", max_load=3)
        >>> [(d.line, d.rule) for d in res.diagnostics], round(res.load.total, 3)
        ([(3, 'NET260')], 3.625)
    """
    from dcf2bin.network.check import check_network as _check
    spec.check("path", path, spec.PATH)
    spec.check("max_load", max_load, spec.MAX_LOAD)
    spec.check("net", net, spec.NET, optional=True)
    return _check(os.fspath(path), select=_names("select", select),
                  ignore=_names("ignore", ignore), max_load=max_load, net=net)


# -- helpers ---------------------------------------------------------------------------------

def _read(source: Container, name: str | None) -> tuple[BinContainer, str, list[Diagnostic]]:
    spec.check("name", name, spec.TEXT, optional=True)
    if not isinstance(source, (bytes, bytearray, memoryview, str, os.PathLike, BinContainer)):
        raise TypeError("source must be bytes, a path (str or os.PathLike) or a BinContainer, "
                        f"not {type(source).__name__}")
    if isinstance(source, BinContainer):
        return source, name or "<container>", []
    if isinstance(source, (bytes, bytearray, memoryview)):
        data, shown = bytes(source), name or "<bytes>"
    else:
        shown = name or os.fspath(source)
        data = read_file(os.fsdecode(source))
    c, diags = _dump.read_bytes(data, shown)
    if c is None:
        raise ReadError(diags)
    return c, shown, diags


def _eds(path):
    """(EdsInfo, Device, warnings) of ``--eds``, or Nones."""
    if path is None:
        return None, None, []
    spec.check("eds", path, spec.PATH)
    path = os.fsdecode(path)
    data = read_file(path)
    info, dev, errors = _dump.load_eds(path, data)
    return info, dev, _dump.eds_warnings(path, errors)


def _warn(diags: list[Diagnostic]) -> None:
    for d in diags:
        warnings.warn(DiagnosticWarning(d), stacklevel=3)


def _names(what: str, value: str | Iterable[str] | None) -> list[str] | None:
    """--select/--ignore as a list: one str (comma-separated) or several."""
    if value is None:
        return None
    if isinstance(value, str):
        return [value]
    try:
        names = list(value)
    except TypeError:
        names = None
    if names is None or not all(isinstance(n, str) for n in names):
        raise TypeError(f"{what} must be a str, an iterable of str or None, not "
                        f"{type(value).__name__}")
    return names


def _paths(value) -> list[str]:
    """One path or an iterable of them, as strings."""
    if isinstance(value, (str, os.PathLike)):
        return [os.fspath(value)]
    try:
        paths = list(value)
    except TypeError:
        paths = None
    if paths is None or not all(isinstance(p, (str, os.PathLike)) for p in paths):
        raise TypeError("paths must be a path (str or os.PathLike) or an iterable of paths, "
                        f"not {type(value).__name__}")
    return [os.fspath(p) for p in paths]


def _path_and_data(path, data) -> None:
    spec.check("path", path, spec.PATH)
    spec.check("data", data, spec.BYTES, optional=True)

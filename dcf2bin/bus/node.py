"""A software CANopen node on a python-can bus: ``canopen.LocalNode`` plus what a
bench needs from a slave — NMT (boot-up, resets), heartbeat, and PDOs as its mapping
says, re-read whenever a PDO object is written by SDO.

The SDO server, the NMT slave, the heartbeat producer and the PDO maps (bit packing
included) are canopen's; this module connects them:

* RPDOs are applied in OPERATIONAL only, as soon as they arrive (whatever their
  transmission type), by a local write of each mapped entry.
* TPDOs: transmission types 1–240 go out every n-th SYNC (COB-ID 0x080), type 0 on
  the SYNC after a mapped value changed, types 254/255 when a mapped value changes and
  every event-timer period (comm sub 5, ms) when it is not 0. Inhibit times are not
  enforced.
* NMT reset application restores every entry, reset communication the entries
  0x1000–0x1FFF, to the values stored by "save" in 0x1010 sub 1 (else the file's);
  then the node sends its boot-up message and enters PRE-OPERATIONAL. "load" in 0x1011
  (restore default parameters: sub 1 all, sub 2 communication, sub 3 application)
  forgets what was stored, from the next reset on (CiA 301).
* A new node-ID (LSS, bus/lss_slave.py) is taken at a reset communication: every value
  of the file that is a ``$NODEID`` formula -- DefaultValue or ParameterValue, whatever
  the object: 0x1014, 0x1200, the PDOs' COB-IDs, a manufacturer's -- is worked out
  again with it (``take_node_id``). Values written by SDO are configuration: a stored one
  comes back at the reset as it was written, one not stored in the communication area
  is gone (the reset restores that area), as on a device that keeps its configuration.

With a process image (an emulated SYS TEC target), the network variables live in one
``bytearray`` at their PI addresses: SDO, RPDOs and TPDOs all read and write there.
"""
from __future__ import annotations

import copy
import struct
from collections.abc import Callable
from dataclasses import dataclass, field

import canopen
import canopen.objectdictionary as od_mod
from canopen.sdo import SdoAbortedError

from dcf2bin import datatypes as dt
from dcf2bin import values
from dcf2bin.diagnostics import shorten
from dcf2bin.indexes import is_pdo_comm, is_pdo_mapping

SYNC_COB_ID = 0x080
NMT_COB_ID = 0x000
OPERATIONAL, PRE_OPERATIONAL, INITIALISING = 5, 127, 0
RESET_NODE, RESET_COMM = 0x81, 0x82
MAX_DOWNLOAD = 1 << 20          # the most one segmented download may bring (1 MiB)
OUT_OF_MEMORY = 0x05040005      # CiA 301 abort: out of memory
_TPDO_COMM, _RPDO_COMM = 0x1800, 0x1400
# CiA 301 dummy entries (mappable data-type objects): index -> canopen data type code
_DUMMIES = {1: 0x1, 2: 0x2, 3: 0x3, 4: 0x4, 5: 0x5, 6: 0x6, 7: 0x7}
# CiA 301 0x1010/0x1011 sub-indexes -> the indexes they store or restore
_PARAMETERS = {1: (0x1000, 0xFFFF), 2: (0x1000, 0x1FFF), 3: (0x6000, 0x9FFF)}


class NodeError(Exception):
    """The node cannot be built from what it was given (one line for the user)."""


@dataclass(frozen=True)
class Formula:
    """An entry whose value in the file depends on the node-ID: its DefaultValue and its
    ParameterValue text where each is a ``$NODEID`` formula (else None)."""
    dtype: dt.DataType
    default: str | None
    value: str | None

    def at(self, text: str, node_id: int):
        """``text`` worked out with ``node_id``, as canopen holds a value (None: it is no
        value of the type there, e.g. $NODEID+0x80 in an UNSIGNED8 at node-ID 0x80)."""
        number = values.split_numeric_comment(text)[0]
        try:
            return values.to_python(self.dtype, values.encode(self.dtype, number,
                                                               node_id=node_id))
        except values.ValueProblem:
            return None


def formulas(dev) -> dict[tuple[int, int], Formula]:
    """Every integer entry of the model whose DefaultValue or ParameterValue uses
    $NODEID (the objects ``to_canopen`` gives the node: 0x1000 and above)."""
    out = {}
    for obj in dev.sorted_objects():
        if obj.index < 0x1000:
            continue
        for e in obj.sorted_entries():
            if e.dtype is None or not e.dtype.is_integer:
                continue
            default, value = (t if t is not None and values.uses_nodeid(t) else None
                              for t in (e.default, e.param))
            if default is not None or value is not None:
                out[(e.index, e.sub)] = Formula(e.dtype, default, value)
    return out


@dataclass
class ProcessImage:
    """The target's PI memory and where each network variable sits in it."""
    data: bytearray
    places: dict[tuple[int, int], tuple[int, int]] = field(default_factory=dict)  # -> (addr, size)

    def get(self, index: int, sub: int) -> bytes | None:
        place = self.places.get((index, sub))
        if place is None:
            return None
        addr, size = place
        return bytes(self.data[addr:addr + size])

    def put(self, index: int, sub: int, value: bytes) -> bool:
        place = self.places.get((index, sub))
        if place is None:
            return False
        addr, size = place
        self.data[addr:addr + size] = value[:size].ljust(size, b"\0")
        return True

    def lines(self, width: int = 16) -> list[str]:
        """The image as hex, ``width`` bytes a line, each line led by its address."""
        return [f"0x{a:04X}  {self.data[a:a + width].hex(' ').upper()}"
                for a in range(0, len(self.data), width)] or ["(empty process image)"]


def add_dummies(od) -> None:
    """CiA 301 dummy entries 0x0001–0x0007, so a mapping that names one keeps its length."""
    for index, code in _DUMMIES.items():
        if index not in od:
            var = od_mod.ODVariable(f"Dummy{index:04X}", index, 0)
            var.data_type, var.access_type, var.default = code, "rw", 0
            od.add_object(var)


class BenchNode(canopen.LocalNode):
    """LocalNode with NMT resets, PDOs (``Pdos``) and an optional process image."""

    def __init__(self, node_id: int, od, image: ProcessImage | None = None):
        add_dummies(od)
        try:
            super().__init__(node_id, od)
        except KeyError as exc:
            raise NodeError(f"a PDO object lacks its partner: {exc}") from None
        self.image = image
        self.on_image_change: Callable[[ProcessImage], None] | None = None
        self.on_event: Callable[[str], None] | None = None
        self.nmt_state = INITIALISING
        self.pdos = Pdos(self)
        self.warnings: list = []    # Diagnostics: what from_file made up or cannot answer
        self.max_download = MAX_DOWNLOAD
        self.sdo.segmented_download = self._bounded(self.sdo.segmented_download)
        self._saved: dict[int, dict[int, bytes]] = {}
        self._saved_image = bytes(image.data) if image is not None else b""
        self.lss = None          # its LSS slave (bus/lss_slave.py), when it answers LSS
        self.formulas: dict[tuple[int, int], Formula] = {}   # the file's $NODEID values

    def _bounded(self, segmented_download):
        """canopen's server collects a segmented download without a limit: a client that
        never sends the last segment would grow the node's memory for as long as it runs.
        Past ``max_download`` bytes the transfer is aborted (out of memory)."""
        def bounded(command, request):
            if len(self.sdo._buffer or b"") + 7 > self.max_download:
                self.sdo._buffer = bytearray()
                raise SdoAbortedError(OUT_OF_MEMORY)
            segmented_download(command, request)
        return bounded

    # -- data -------------------------------------------------------------------------------
    def get_data(self, index: int, subindex: int, check_readable: bool = False) -> bytes:
        if self.image is not None:
            obj = self._find_object(index, subindex)
            value = self.image.get(index, subindex)
            if value is not None:
                if check_readable and not obj.readable:
                    raise SdoAbortedError(0x06010001)
                return value
        return super().get_data(index, subindex, check_readable)

    def set_data(self, index: int, subindex: int, data: bytes,
                 check_writable: bool = False) -> None:
        super().set_data(index, subindex, data, check_writable)
        if self.image is not None and self.image.put(index, subindex, bytes(data)):
            self.data_store[index].pop(subindex, None)
        if index == 0x1010 and subindex == 1 and bytes(data) == b"save":
            self._saved = copy.deepcopy(self.data_store)
            self._saved_image = bytes(self.image.data) if self.image is not None else b""
        elif index == 0x1011 and subindex in _PARAMETERS and bytes(data) == b"load":
            first, last = _PARAMETERS[subindex]
            self._saved = {i: subs for i, subs in self._saved.items()
                           if not first <= i <= last}
        if is_pdo_comm(index) or is_pdo_mapping(index):
            self.pdos.reread(index)
        else:
            self.pdos.value_changed(index, subindex)

    # -- NMT --------------------------------------------------------------------------------
    def boot(self) -> None:
        """Send the boot-up message and enter PRE-OPERATIONAL (heartbeat from 0x1017)."""
        self.nmt._state = INITIALISING
        self.network.send_message(0x700 + self.id, [0])
        self.nmt._state = PRE_OPERATIONAL
        self.nmt_state = PRE_OPERATIONAL
        self.pdos.read_all()
        self.nmt.start_heartbeat(self._heartbeat_ms())

    def take_node_id(self, node_id: int) -> None:
        """The file's $NODEID values worked out with ``node_id`` (``formulas``); the values
        written by SDO (``data_store``) are configuration and stay as written. The node's
        own services (SDO server, NMT, EMCY) are bus/lss_slave.py's ``renumber``."""
        od = self.object_dictionary
        for (index, sub), f in self.formulas.items():
            var = od.get_variable(index, sub)
            if var is None:              # a formula of an object the node was not given
                continue
            for attr in ("default", "value"):
                text = getattr(f, attr)
                if text is None:
                    continue
                setattr(var, attr, f.at(text, node_id))
                if getattr(var, attr) is None:
                    self.event(f"0x{index:04X} sub {sub}: '{shorten(text)}' is no "
                               f"{f.dtype.name} at "
                               f"node-ID {node_id}: no value")
        od.node_id = node_id

    def _heartbeat_ms(self) -> int:
        try:
            return struct.unpack("<H", self.get_data(0x1017, 0)[:2])[0]
        except (SdoAbortedError, struct.error):
            return 0

    def go_operational(self) -> None:
        self.nmt._state = OPERATIONAL
        self.nmt.update_heartbeat()
        self._state_changed()

    def on_nmt(self, can_id, data, timestamp) -> None:
        """Runs after canopen's NmtSlave has taken the command."""
        if len(data) < 2 or data[1] not in (0, self.id):
            return
        if data[0] in (RESET_NODE, RESET_COMM):
            self._reset(data[0])
        else:
            self._state_changed()

    def _reset(self, command: int) -> None:
        self.pdos.stop()
        if command == RESET_NODE:
            self.data_store = copy.deepcopy(self._saved)
            if self.image is not None:
                self.image.data[:] = self._saved_image
        else:
            for index in [i for i in self.data_store if 0x1000 <= i <= 0x1FFF]:
                del self.data_store[index]
            for index, subs in self._saved.items():
                if 0x1000 <= index <= 0x1FFF:
                    self.data_store[index] = dict(subs)
        self.event("reset " + ("application" if command == RESET_NODE else "communication"))
        if self.lss is not None:
            self.lss.take_pending()          # a node-ID configured by LSS takes effect
        self.boot()

    def _state_changed(self) -> None:
        new = self.nmt._state
        if new == self.nmt_state:
            return
        self.nmt_state = new
        self.event(f"NMT state {self.nmt.state}")
        if new == OPERATIONAL:
            self.pdos.start()
        else:
            self.pdos.stop()

    def event(self, text: str) -> None:
        if self.on_event is not None:
            self.on_event(text)

    # -- life -------------------------------------------------------------------------------
    def attach(self, network, *, operational: bool = False) -> None:
        if self.lss is not None and not self.lss.attach(network, operational):
            return                           # no node-ID yet: it answers LSS only
        network.add_node(self)
        network.subscribe(NMT_COB_ID, self.on_nmt)
        network.subscribe(SYNC_COB_ID, self.pdos.on_sync)
        self.boot()
        if operational:
            self.go_operational()

    def detach(self) -> None:
        """Stop the heartbeat and the PDO timers (waiting for their threads), leave the bus."""
        if self.lss is not None:
            self.lss.detach()
        tasks = self.pdos.tasks() + [self.nmt._send_task]
        self.pdos.stop()
        self.nmt.stop_heartbeat()
        for task in tasks:
            _join(task)
        if not self.has_network():
            return
        net = self.network
        self.pdos.unsubscribe()
        _unsubscribe(net, NMT_COB_ID, self.on_nmt)
        _unsubscribe(net, SYNC_COB_ID, self.pdos.on_sync)
        del net[self.id]


class Pdos:
    """The node's PDOs as canopen's PdoMaps, read from the node's current data (through its
    own SDO server) and driven by SYNC, value changes, event timers and received frames."""

    def __init__(self, node: BenchNode):
        self.node = node
        self._sync_count: dict[int, int] = {}
        self._changed: set[int] = set()          # TPDOs with a changed value (type 0)
        self._subscribed: dict[int, tuple[int, Callable]] = {}   # id(map) -> (cob, callback)
        self._refreshing = False
        for pdo_map in node.rpdo.map.values():
            pdo_map.add_callback(self.on_rpdo)

    @property
    def tx(self):
        return list(self.node.tpdo.map.values())

    def _map_of(self, index: int):
        comm = index - 0x200 if is_pdo_mapping(index) else index
        if comm >= _TPDO_COMM:
            return self.node.tpdo.map.get(comm - _TPDO_COMM + 1)
        return self.node.rpdo.map.get(comm - _RPDO_COMM + 1)

    def read_all(self) -> None:
        for pdo_map in list(self.node.rpdo.map.values()) + self.tx:
            self._read(pdo_map)

    def reread(self, index: int) -> None:
        """A comm or mapping object was written: that PDO as its objects now say."""
        pdo_map = self._map_of(index)
        if pdo_map is not None:
            self._read(pdo_map)
            if self.node.nmt_state == OPERATIONAL and pdo_map in self.tx:
                self._start(pdo_map)

    def _read(self, pdo_map) -> None:
        """The map as the node's current data says; one that cannot be read is off."""
        net = self.node.network
        pdo_map.stop()
        old = self._subscribed.pop(id(pdo_map), None)
        if old is not None:
            _unsubscribe(net, *old)
        try:
            pdo_map.read(from_od=False)      # subscribes an enabled map to its COB-ID
        except (KeyError, SdoAbortedError, ValueError, TypeError,
                od_mod.ObjectDictionaryError) as exc:
            pdo_map.enabled = False
            pdo_map.clear()
            self.node.event(f"PDO 0x{pdo_map.com_record.od.index:04X} off: {exc}")
        is_tpdo = pdo_map in self.tx
        if pdo_map.enabled and is_tpdo:      # a TPDO does not listen to its own COB-ID
            _unsubscribe(net, pdo_map.cob_id, pdo_map.on_message)
        elif pdo_map.enabled:
            self._subscribed[id(pdo_map)] = (pdo_map.cob_id, pdo_map.on_message)
        if is_tpdo:
            self._refresh(pdo_map)

    def _refresh(self, pdo_map) -> None:
        """Copy the mapped entries' values into the TPDO's data."""
        self._refreshing = True
        try:
            for var in pdo_map.map:
                if var.index < 0x1000 or not var.length:
                    continue
                try:
                    raw = self.node.get_data(var.index, var.subindex)
                except SdoAbortedError:
                    continue
                if var.offset % 8 or var.length % 8:
                    _put_bits(pdo_map.data, var.offset, var.length, raw)
                    pdo_map.update()
                    continue
                raw = raw[:var.length // 8].ljust(var.length // 8, b"\0")
                try:
                    var.set_data(raw)
                except (struct.error, ValueError, KeyError):
                    continue
        finally:
            self._refreshing = False

    def value_changed(self, index: int, sub: int) -> None:
        if self._refreshing:
            return
        for pdo_map in self.tx:
            if not pdo_map.enabled or not any(
                    v.index == index and v.subindex == sub for v in pdo_map.map):
                continue
            self._refresh(pdo_map)
            if self.node.nmt_state != OPERATIONAL:
                continue
            if pdo_map.trans_type in (254, 255):
                pdo_map.transmit()
            elif pdo_map.trans_type == 0:
                self._changed.add(id(pdo_map))

    def on_sync(self, can_id, data, timestamp) -> None:
        if self.node.nmt_state != OPERATIONAL:
            return
        for pdo_map in self.tx:
            t = pdo_map.trans_type
            if not pdo_map.enabled or t is None or t > 240:
                continue
            if t == 0:
                if id(pdo_map) in self._changed:
                    self._changed.discard(id(pdo_map))
                    pdo_map.transmit()
                continue
            n = self._sync_count.get(id(pdo_map), 0) + 1
            if n >= t:
                n = 0
                self._refresh(pdo_map)
                pdo_map.transmit()
            self._sync_count[id(pdo_map)] = n

    def _start(self, pdo_map) -> None:
        pdo_map.stop()
        if pdo_map.enabled and pdo_map.trans_type in (254, 255) and pdo_map.event_timer:
            self._refresh(pdo_map)
            pdo_map.start(pdo_map.event_timer / 1000.0)

    def start(self) -> None:
        for pdo_map in self.tx:
            self._start(pdo_map)

    def stop(self) -> None:
        for pdo_map in self.tx:
            pdo_map.stop()

    def tasks(self) -> list:
        return [m._task for m in self.tx if m._task is not None]

    def unsubscribe(self) -> None:
        for cob, callback in self._subscribed.values():
            _unsubscribe(self.node.network, cob, callback)
        self._subscribed.clear()

    def on_rpdo(self, pdo_map) -> None:
        node = self.node
        if node.nmt_state != OPERATIONAL:
            return
        before = bytes(node.image.data) if node.image is not None else None
        for var in pdo_map.map:
            if var.index < 0x1000 or not var.length:
                continue
            if (var.offset + var.length + 7) // 8 > len(pdo_map.data):
                continue     # a frame shorter than its mapping: nothing to take
            try:
                if var.offset % 8 or var.length % 8:
                    data = _take_bits(pdo_map.data, var.offset, var.length, var.od)
                else:
                    data = var.get_data()
                node.set_data(var.index, var.subindex, data)
            except (SdoAbortedError, struct.error, ValueError, KeyError):
                continue
        if before is not None and bytes(node.image.data) != before \
                and node.on_image_change is not None:
            node.on_image_change(node.image)


# A field that does not start and end on byte bounds (a bit-sized object, or one after a
# BOOLEAN dummy): python-canopen's PdoVariable packs it in the bytes of its type only, so a
# field that spans one byte more loses its top bits (and a negative value sets bits past
# the field). CiA 301 packs a PDO's bits from bit 0 of byte 0, little-endian.

def _put_bits(frame: bytearray, offset: int, length: int, raw: bytes) -> None:
    """The low ``length`` bits of ``raw`` (the object's bytes) at bit ``offset`` of the
    frame; the frame's other bits stay."""
    if offset + length > 8 * len(frame):
        return                      # a mapping longer than the frame: nothing to place
    mask = ((1 << length) - 1) << offset
    bits = (int.from_bytes(raw, "little") << offset) & mask
    whole = (int.from_bytes(frame, "little") & ~mask) | bits
    frame[:] = whole.to_bytes(len(frame), "little")


def _take_bits(frame: bytes, offset: int, length: int, od_var) -> bytes:
    """The ``length`` bits at bit ``offset`` of the frame as the object's bytes (its type's
    size; a signed type's value sign-extended from the field's top bit)."""
    value = (int.from_bytes(frame, "little") >> offset) & ((1 << length) - 1)
    size = max(1, (len(od_var) + 7) // 8)
    signed = od_var.data_type in od_mod.SIGNED_TYPES
    if signed and value >> (length - 1):
        value -= 1 << length
    return value.to_bytes(size, "little", signed=signed)


def _join(task, longest: float = 1.0) -> None:
    """Wait for a stopped periodic task's thread (it ends after its current period)."""
    thread = getattr(getattr(task, "_task", None), "thread", None)
    if thread is not None:
        thread.join(min(task.period, longest) + 0.05)


def _unsubscribe(net, cob_id: int, callback) -> None:
    if callback in net.subscribers.get(cob_id, ()):
        net.unsubscribe(cob_id, callback)


def bench_node(node_id: int, od, image: ProcessImage | None = None) -> BenchNode:
    """A ``canopen.LocalNode`` (subclass) for ``od``; attach it with ``node.attach(net)``."""
    return BenchNode(node_id, od, image)


def from_file(path: str, node_id: int | None, *, data: bytes | None = None):
    """A node from an EDS/DCF: canopen's object dictionary built from the dcf2bin model
    (values exactly as compile encodes them), the mandatory objects an EDS leaves without a
    value filled as ``fill_mandatory`` says (its warnings in ``node.warnings``), the file's
    $NODEID values kept as formulas for a new node-ID (``node.formulas``). Returns
    (node, model errors)."""
    from dcf2bin import formats
    from dcf2bin.diagnostics import Severity
    dev = formats.load(path, node_id=node_id, data=data)
    nid = node_id if node_id is not None else dev.node_id
    if nid is None:
        raise NodeError("no node-ID: give --node-id N or set NodeID in [DeviceComissioning]")
    errors = [p.diagnostic for p in dev.problems if p.diagnostic.severity is Severity.ERROR]
    od = dev.to_canopen()
    warnings = fill_mandatory(od, dev)
    node = bench_node(nid, od)
    node.warnings = warnings
    node.formulas = formulas(dev)
    return node, errors


# -- the mandatory objects (CiA 301: 0x1000, 0x1001, 0x1018 sub 0 and 1) ---------------------
# The node's diagnostics at start, each with its code (man/dcf2bin-node.1, "DIAGNOSTICS"):
MISSING, NO_DEVICE_TYPE, NO_VENDOR, FILE_ERRORS = "NOD001", "NOD002", "NOD003", "NOD004"

_NO_VALUE = "SDO abort 0x060A0023 (resource not available)"


def _unset(var) -> bool:
    return var is not None and var.value is None and var.default is None


def _warning(message: str, where, path: str, rule: str):
    from dcf2bin.diagnostics import Diagnostic, Severity
    return Diagnostic(Severity.WARNING, message, where.file if where else path,
                      where.line if where else None, rule=rule)


def fill_mandatory(od, dev) -> list:
    """An EDS often gives its identity in [DeviceInfo] only, and no value to 0x1000 or
    0x1018: a real device answers them, so the node does too. Without a value in the file,
    0x1018 sub 1-3 take [DeviceInfo] VendorNumber, ProductNumber and RevisionNumber, sub 4
    [DeviceComissioning] LSS_SerialNumber (``model.identity``, the rule diff compares by), sub 0
    the highest sub-index present, 0x1001 (error register) 0 (a software node has no
    error) and 0x1000 (device type) 0x00000000 (CiA 301: no device profile); each value
    the node has to make up that way, and each mandatory object it cannot answer, is one
    warning (a ``Diagnostic`` at the object's section, else the file, with its code)."""
    from dcf2bin.model.identity import stated_identity
    info = stated_identity(dev.ini)
    warnings = []
    for index, what in ((0x1000, "device type"), (0x1001, "error register"),
                        (0x1018, "identity object")):
        if index not in od:
            warnings.append(_warning(
                f"the file has no 0x{index:04X} ({what}), which every CANopen device has: "
                "the node answers SDO abort 0x06020000 (object does not exist)",
                None, dev.path, MISSING))
    if _unset(od.get_variable(0x1000)):
        od.get_variable(0x1000).default = 0
        warnings.append(_warning(
            "0x1000 (device type) has no value in the file, and every CANopen device "
            "answers it: the node answers 0x00000000, the device type of a device that "
            "follows no device profile", dev.objects[0x1000].where, dev.path,
            NO_DEVICE_TYPE))
    if _unset(od.get_variable(0x1001)):
        od.get_variable(0x1001).default = 0
    identity = od.get(0x1018)
    if identity is None or not hasattr(identity, "subindices"):
        return warnings
    for sub in (1, 2, 3, 4):
        var = identity.get(sub)
        if not _unset(var):
            continue
        if sub in info:
            var.default = info[sub].value
        elif sub == 1:
            entry = dev.objects[0x1018].entries.get(1)
            warnings.append(_warning(
                "0x1018 sub 1 (vendor-ID) has no value in the file nor in [DeviceInfo] "
                f"VendorNumber: the node answers {_NO_VALUE}",
                entry.where if entry is not None else None, dev.path, NO_VENDOR))
    sub0 = identity.get(0)
    if _unset(sub0):
        sub0.default = max(identity.subindices)
    return warnings


# -- an emulated SYS TEC target -----------------------------------------------------------

_KIND_CODES = {"bool": 0x01, "vstring": 0x09, "domain": 0x0F}


def _type_code(entry) -> int:
    """canopen data type of an emulated entry: its own type (static OD, network-variable
    range), else what DynBuildOd created it as (a NUMERIC of n bytes: UNSIGNEDn)."""
    if entry.dtype is not None:
        return entry.dtype.code
    if entry.kind == "numeric":
        t = dt.UNSIGNED_BY_SIZE.get(len(entry.data))
        return t.code if t is not None else 0x0F
    return _KIND_CODES.get(entry.kind, 0x0F)


def image_of(outcome, memory: int | None = None) -> ProcessImage:
    """The PI memory after DynBuildOd: ``memory`` bytes (default: the complete size the
    parameter segment gives), each placed network variable's data at its address."""
    out = outcome.descriptor.out if outcome.descriptor is not None else None
    size = memory if memory is not None else (out[0] if out else 0)
    image = ProcessImage(bytearray(size))
    for index, subs in outcome.od.items():
        for sub, e in subs.items():
            if e.pi_address is not None:
                image.places[(index, sub)] = (e.pi_address, len(e.data))
                end = e.pi_address + len(e.data)
                if end > len(image.data):
                    image.data.extend(bytes(end - len(image.data)))
                image.data[e.pi_address:end] = e.data
    return image


def from_outcome(outcome, node_id: int, memory: int | None = None):
    """A node whose object dictionary is the one DynBuildOd left (SPEC §8): static,
    created and written entries, values as the container wrote them; network variables
    live in the process image at their PI addresses."""
    od = od_mod.ObjectDictionary()
    od.node_id = node_id
    for index in sorted(outcome.od):
        subs = outcome.od[index]
        if index < 0x1000:
            continue
        made = []
        for sub in sorted(subs):
            e = subs[sub]
            var = od_mod.ODVariable(f"0x{index:04X}sub{sub:X}", index, sub)
            var.data_type = _type_code(e)
            var.access_type = e.access
            var.pdo_mappable = e.mappable
            var.value = bytes(e.data)
            made.append(var)
        if list(subs) == [0] and not (0xA000 <= index <= 0xAFFF):
            od.add_object(made[0])
            continue
        cls = od_mod.ODArray if 0xA000 <= index <= 0xAFFF else od_mod.ODRecord
        group = cls(f"0x{index:04X}", index)
        for var in made:
            group.add_member(var)
        od.add_object(group)
    return bench_node(node_id, od, image_of(outcome, memory))

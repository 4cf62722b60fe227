"""The LSS slave of a software node (CiA 305), so that LSS can be run end to end without
hardware: `dcf2bin node` answers the LSS master on 0x7E5 (answers on 0x7E4).

* Switch state global and selective, configure node-ID and bit timing, activate bit
  timing, store, inquire identity and node-ID; identify remote slave and identify
  non-configured remote slave (in both states); fastscan (waiting state, no node-ID).
* A node that starts without a node-ID (``unconfigured``: 0xFF) answers LSS only: no SDO,
  no boot-up, no heartbeat. When it has been given one and is switched back to waiting,
  it takes it and starts: boot-up at the new node-ID (an NMT reset communication of its
  own). A node that has a node-ID takes the one configured at its next NMT reset
  (communication or application).
* The identity is 0x1018 sub 1-4; the entries the object dictionary lacks are added, so
  that SDO reads what LSS answers.
* A new node-ID is taken as a CiA 301 node takes it, at a reset communication (bus/node.py
  restores the communication area from the stored values, else the file's): every value
  of the file that is a $NODEID formula is worked out again with it -- EMCY 0x1014, the SDO
  server 0x1200, the PDOs' COB-IDs and any other object's -- from the formulas the model
  keeps (``BenchNode.formulas``); values written by SDO, stored or not, stay as written.
  An emulated SYS TEC target has no formulas: its values are what its container wrote.
* A software node has no memory across runs: store keeps the pending node-ID and bit
  timing for the node's own resets only. A bit timing activated is reported, not
  applied (the bus rate is the interface's).

Faults, for the tests of the master: ``store_error`` (store answers this error code),
``twice`` (every answer is sent again this many seconds later), ``delay`` (seconds
before each answer).
"""
from __future__ import annotations

import time
from collections.abc import Callable

import canopen.objectdictionary as od_mod
from canopen.sdo import SdoAbortedError

from dcf2bin.bus import lss as L

_VALID_TIMINGS = frozenset(L.BIT_TIMINGS.values())
_IDENTITY_NAMES = ("Vendor-ID", "Product code", "Revision number", "Serial number")


class LssSlave:
    """LSS for one ``BenchNode``; ``node.lss`` is set to it (bus/node.py asks it before
    booting and at each reset)."""

    def __init__(self, node, identity: L.Identity, *, unconfigured: bool = False,
                 store_error: int = 0, twice: float | None = None, delay: float = 0.0):
        self.node, self.identity = node, identity
        self.active = L.UNCONFIGURED if unconfigured else node.id
        self.pending = self.stored = self.active
        self.timing: int | None = None        # pending bit timing (table index)
        self.stored_timing: int | None = None
        self.state = L.WAITING
        self.store_error, self.twice, self.delay = store_error, twice, delay
        self.on_event: Callable[[str], None] | None = None
        self.net = None
        self.operational = False
        self._selection: dict[int, int] = {}
        self._ranges: dict[int, int] = {}
        self._position = 0                    # fastscan: the part compared next
        node.lss = self

    @property
    def configured(self) -> bool:
        return self.active != L.UNCONFIGURED

    def event(self, text: str) -> None:
        if self.on_event is not None:
            self.on_event(text)

    # -- hooks of BenchNode -----------------------------------------------------------------
    def attach(self, network, operational: bool = False) -> bool:
        """Listen on 0x7E5; True when the node has a node-ID and may boot."""
        if self.net is None:
            self.net = network
            self.operational = operational
            network.subscribe(L.MASTER_COB, self.on_request)
        return self.configured

    def detach(self) -> None:
        if self.net is not None and self.on_request in self.net.subscribers.get(
                L.MASTER_COB, ()):
            self.net.unsubscribe(L.MASTER_COB, self.on_request)

    def take_pending(self) -> None:
        """An NMT reset: the node-ID configured becomes the node's."""
        if 1 <= self.pending <= 127 and self.pending != self.active:
            renumber(self.node, self.pending)
            self.active = self.pending
            self.event(f"node-ID {self.active} from LSS")

    # -- requests ---------------------------------------------------------------------------
    def answer(self, cs: int, value: int | None = None, *more: int) -> None:
        if self.delay:
            time.sleep(self.delay)           # a slow slave (a fault the tests ask for)
        data = L.frame(cs, value, *more)
        self.net.send_message(L.SLAVE_COB, data)
        if self.twice is not None:
            time.sleep(self.twice)
            self.net.send_message(L.SLAVE_COB, data)

    def on_request(self, can_id, data, timestamp) -> None:
        data = bytes(data)
        if len(data) != 8:
            return
        cs, value = data[0], int.from_bytes(data[1:5], "little")
        if cs == L.SWITCH_GLOBAL:
            self._switch(data[1])
        elif cs in L.IDENTIFY:
            self._identify(cs, value)
        elif cs == L.IDENTIFY_NON_CONFIGURED:
            if self._fresh():
                self.answer(L.NON_CONFIGURED)
        elif self.state == L.WAITING:
            if cs in L.SELECT:
                self._select(cs, value)
            elif cs == L.FASTSCAN and self._fresh():
                self._fastscan(value, data[5], data[6], data[7])
        else:
            self._configure(cs, data)

    def _fresh(self) -> bool:
        """No node-ID, and none given yet."""
        return self.active == L.UNCONFIGURED and self.pending == L.UNCONFIGURED

    def _switch(self, mode: int) -> None:
        if mode == L.CONFIGURATION:
            self.state = L.CONFIGURATION
        elif mode == L.WAITING:
            was = self.state
            self.state = L.WAITING
            self._selection.clear()
            if was == L.CONFIGURATION and not self.configured \
                    and self.pending != L.UNCONFIGURED:
                self._start()

    def _start(self) -> None:
        """A node without a node-ID was given one: it resets its communication and boots."""
        renumber(self.node, self.pending)
        self.active = self.pending
        self.event(f"node-ID {self.active} from LSS")
        self.node.attach(self.net, operational=self.operational)

    def _select(self, cs: int, value: int) -> None:
        self._selection[cs] = value
        if cs != L.SELECT[-1]:
            return
        chosen = tuple(self._selection.get(c) for c in L.SELECT)
        self._selection.clear()
        if chosen == self.identity.parts:
            self.state = L.CONFIGURATION
            self.answer(L.SELECTED)

    def _identify(self, cs: int, value: int) -> None:
        self._ranges[cs] = value
        if cs != L.IDENTIFY[-1]:
            return
        got = [self._ranges.get(c) for c in L.IDENTIFY]
        self._ranges.clear()
        if None in got:
            return
        vendor, product, rev_lo, rev_hi, ser_lo, ser_hi = got
        i = self.identity
        if (vendor, product) == (i.vendor, i.product) and rev_lo <= i.revision <= rev_hi \
                and ser_lo <= i.serial <= ser_hi:
            self.answer(L.IDENTIFIED)

    def _fastscan(self, value: int, bit: int, sub: int, following: int) -> None:
        if bit == L.FASTSCAN_RESET:
            self._position = 0
            self.answer(L.IDENTIFIED)
            return
        if bit > 31 or sub > 3 or following > 3 or sub != self._position:
            return
        mask = (L.MAX32 << bit) & L.MAX32
        if self.identity.parts[sub] & mask != value & mask:
            return
        self._position = following
        if bit == 0 and following < sub:
            self.state = L.CONFIGURATION
        self.answer(L.IDENTIFIED)

    def _configure(self, cs: int, data: bytes) -> None:
        if cs == L.CONFIGURE_NODE_ID:
            ok = 1 <= data[1] <= 127 or data[1] == L.UNCONFIGURED
            if ok:
                self.pending = data[1]
            self.answer(cs, None, 0 if ok else 1, 0)
        elif cs == L.CONFIGURE_BIT_TIMING:
            ok = data[1] == 0 and data[2] in _VALID_TIMINGS
            if ok:
                self.timing = data[2]
            self.answer(cs, None, 0 if ok else 1, 0)
        elif cs == L.ACTIVATE_BIT_TIMING:
            delay = int.from_bytes(data[1:3], "little")
            self.event(f"bit timing {self.timing} activated after {delay} ms (a software "
                       "node keeps its interface's bit rate)")
        elif cs == L.STORE:
            if self.store_error:
                self.answer(cs, None, self.store_error, 0)
                return
            self.stored, self.stored_timing = self.pending, self.timing
            self.answer(cs, None, 0, 0)
        elif cs in L.INQUIRE:
            self.answer(cs, self.identity.parts[L.INQUIRE.index(cs)])
        elif cs == L.INQUIRE_NODE_ID:
            self.answer(cs, None, self.active)


# -- the node's side ----------------------------------------------------------------------

def renumber(node, node_id: int) -> None:
    """Give a ``BenchNode`` another node-ID, as a reset communication does: its SDO server,
    NMT, heartbeat and EMCY, and every value of its file that is a $NODEID formula
    (``BenchNode.take_node_id``: 0x1014, 0x1200, the PDOs' COB-IDs, whatever the object).
    The values written by SDO stay as written: they are configuration."""
    old = node.id
    net = node.network if node.has_network() else None
    if net is not None:
        net.unsubscribe(node.sdo.rx_cobid, node.sdo.on_request)
    node.id = node.nmt.id = node_id
    node.sdo.rx_cobid, node.sdo.tx_cobid = 0x600 + node_id, 0x580 + node_id
    node.emcy.cob_id = 0x80 + node_id
    if net is not None:
        net.subscribe(node.sdo.rx_cobid, node.sdo.on_request)
        if net.nodes.get(old) is node:
            del net.nodes[old]
            net.nodes[node_id] = node
    node.take_node_id(node_id)


def identity_of(node, serial: int | None = None,
                info: dict[int, int] | None = None) -> L.Identity:
    """The node's LSS address: 0x1018 sub 1-3 (else ``info``: sub -> value from the file's
    [DeviceInfo]; else 0), the serial number given (else 0x1018 sub 4, else 0)."""
    parts = []
    for sub in (1, 2, 3, 4):
        value = None
        try:
            value = int.from_bytes(node.get_data(0x1018, sub)[:4], "little")
        except (SdoAbortedError, KeyError, ValueError, TypeError):
            value = None             # no such entry, or no value: not given
        if value is None and info is not None:
            value = info.get(sub)
        parts.append(value or 0)
    if serial is not None:
        parts[3] = serial
    return L.Identity(*parts)


def device_info(data: bytes, path: str) -> dict[int, int]:
    """0x1018 sub -> value from the [DeviceInfo] of an EDS/DCF: VendorNumber,
    ProductNumber, RevisionNumber, and [DeviceComissioning] LSS_SerialNumber (those that
    read as UNSIGNED32s: ``model.identity``, the one rule)."""
    from dcf2bin import ini
    from dcf2bin.model.identity import stated_identity
    return {sub: s.value for sub, s in stated_identity(ini.parse_bytes(data, path)).items()}


def fill_identity(node, identity: L.Identity, subs=(1, 2, 3, 4)) -> None:
    """0x1018 ``subs`` hold the identity LSS answers with (the entries the object
    dictionary lacks are added, read-only UNSIGNED32)."""
    od = node.object_dictionary
    if 0x1018 not in od:
        od.add_object(od_mod.ODRecord("Identity object", 0x1018))
    record = od[0x1018]
    if not isinstance(record, od_mod.ODRecord):
        return
    if 0 not in record:
        var = od_mod.ODVariable("Highest sub-index supported", 0x1018, 0)
        var.data_type, var.access_type = od_mod.UNSIGNED8, "ro"
        record.add_member(var)
    for sub, name, value in zip((1, 2, 3, 4), _IDENTITY_NAMES, identity.parts):
        if sub not in subs:
            continue
        if sub not in record:
            var = od_mod.ODVariable(name, 0x1018, sub)
            var.data_type, var.access_type = od_mod.UNSIGNED32, "ro"
            record.add_member(var)
        var = record[sub]
        var.value = _like(var.value, value)
        node.data_store.get(0x1018, {}).pop(sub, None)
    top, highest = record[0], max((*subs, 0))
    if _number(top.value if top.value is not None else top.default) < highest:
        top.value = _like(top.value, highest, 1)
        node.data_store.get(0x1018, {}).pop(0, None)


def _number(value) -> int:
    """An entry's value as canopen holds it: an int, raw bytes (an emulated target's
    object dictionary), or None."""
    if isinstance(value, (bytes, bytearray)):
        return int.from_bytes(value, "little")
    return value if isinstance(value, int) else 0


def _like(old, value: int, size: int = 4):
    """``value`` in the form ``old`` has (raw bytes of its length, else an int)."""
    if isinstance(old, (bytes, bytearray)):
        return value.to_bytes(len(old) or size, "little")
    return value


def attach_lss(node, *, serial: int | None = None, unconfigured: bool = False,
               info: dict[int, int] | None = None, info_from: str | None = None,
               **faults) -> LssSlave:
    """Make ``node`` answer LSS with the identity :func:`identity_of` gives; ``info_from``:
    the EDS/DCF whose [DeviceInfo] is read when 0x1018 lacks sub 1, 2 or 3."""
    held = {sub for sub in (1, 2, 3, 4) if _holds(node, sub)}
    if info is None and info_from is not None and not {1, 2, 3} <= held:
        from dcf2bin.fileio import read_file
        try:
            info = device_info(read_file(info_from), info_from)
        except OSError:
            info = None               # it was read a moment ago; now it is not there
    identity = identity_of(node, serial, info)
    # 0x1018 holds what is known: its own entries, [DeviceInfo]'s, the serial given
    fill_identity(node, identity, held | set(info or ()) | ({4} if serial is not None else set()))
    return LssSlave(node, identity, unconfigured=unconfigured, **faults)


def _holds(node, sub: int) -> bool:
    try:
        node.get_data(0x1018, sub)
        return True
    except (SdoAbortedError, KeyError, ValueError, TypeError):
        return False

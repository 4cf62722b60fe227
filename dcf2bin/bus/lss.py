"""An LSS master (CiA 305): find nodes by their identity and give them node-IDs.

The master speaks on CAN-ID 0x7E5, the slaves answer on 0x7E4. Every answer is matched to
its request: a command whose answer echoes its command specifier (configure node-ID 0x11,
configure bit timing 0x13, store 0x17, inquire 0x5A-0x5E) or has one of its own (switch
state selective 0x40-0x43, answered by 0x44) ends its wait when that answer comes, and
frames left over from an earlier request are never taken for it. Where silence is the
answer -- a fastscan step (0x51) or identify remote slave (0x46-0x4B), both answered by
0x4F, identify non-configured remote slave (0x4C), answered by 0x50 -- the master waits
``wait`` seconds and counts the answers: several slaves may answer one step, and an
answer that arrives late belongs to no step that follows.

Where one answer is expected to the step that selects nodes -- switch state selective,
fastscan's last confirmation -- the master listens ``wait`` seconds more after the first
and counts the answer frames: nodes that share one identity all answer, with identical
frames, so a second frame is a second node (or a slave that answers twice: the bus cannot
tell which). Configure and store then take the first answer: only the nodes that step
counted are in configuration.
``selected`` is the count of the last step that switched nodes into configuration
(switch state selective, or fastscan's last confirmation). Two identical frames sent in
the same bit time merge into one on a real bus: counting sees those nodes as one.

python canopen's ``LssMaster`` sends switch state global (no answer); for the rest it
falls short (its identify remote slave only sends, each command takes the first frame
of a queue it has emptied without checking what it is, so a second slave's late answer
becomes the next step's answer, and selective switch sleeps 0.8 s), so they are here.

    master = Master(net, timeout=0.5, wait=0.05)
    if master.select(Identity(0xAB, 8, 0x10002, 1)):
        master.configure_node_id(5)
        master.store()
    master.switch_global(configuration=False)

Nothing here imports click.
"""
from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field

MASTER_COB, SLAVE_COB = 0x7E5, 0x7E4
SWITCH_GLOBAL = 0x04
CONFIGURE_NODE_ID, CONFIGURE_BIT_TIMING, ACTIVATE_BIT_TIMING, STORE = 0x11, 0x13, 0x15, 0x17
SELECT = (0x40, 0x41, 0x42, 0x43)          # vendor-ID, product code, revision, serial
SELECTED = 0x44
IDENTIFY = (0x46, 0x47, 0x48, 0x49, 0x4A, 0x4B)   # vendor, product, rev low/high, serial l/h
IDENTIFIED = 0x4F                          # also the answer to a fastscan step
IDENTIFY_NON_CONFIGURED, NON_CONFIGURED = 0x4C, 0x50
FASTSCAN = 0x51
INQUIRE = (0x5A, 0x5B, 0x5C, 0x5D)         # vendor-ID, product code, revision, serial
INQUIRE_NODE_ID = 0x5E
WAITING, CONFIGURATION = 0, 1

UNCONFIGURED = 0xFF                        # the node-ID of a node that has none
FASTSCAN_RESET = 0x80                      # bit checked: every unconfigured node answers
PARTS = ("vendor-ID", "product code", "revision", "serial")
MAX32 = 0xFFFFFFFF

# the CiA bit timing table (table selector 0): bit/s -> table index; 5 is reserved
BIT_TIMINGS = {1_000_000: 0, 800_000: 1, 500_000: 2, 250_000: 3, 125_000: 4, 50_000: 6,
               20_000: 7, 10_000: 8}

TIMEOUT, WAIT = 0.5, 0.05
_SEND_TRIES, _SEND_PAUSE = 200, 0.002     # a full transmit queue (socketcan's is 10 frames)

# what an error code of a configure or store answer means (255: the second byte is the
# manufacturer's own code)
_ERRORS = {CONFIGURE_NODE_ID: {1: "node-ID out of range"},
           CONFIGURE_BIT_TIMING: {1: "bit timing not supported"},
           STORE: {1: "storing is not supported", 2: "storage media access error"}}
COMMANDS = {CONFIGURE_NODE_ID: "configure node-ID", CONFIGURE_BIT_TIMING: "configure bit timing",
            STORE: "store configuration"}


@dataclass(frozen=True)
class Identity:
    """A node's LSS address: 0x1018 sub 1-4."""
    vendor: int
    product: int
    revision: int
    serial: int

    @property
    def parts(self) -> tuple[int, int, int, int]:
        return (self.vendor, self.product, self.revision, self.serial)

    def text(self) -> str:
        return ", ".join(f"{n} 0x{v:08X}" for n, v in zip(PARTS, self.parts))


@dataclass(frozen=True)
class Reply:
    """The answer to a configure or store command: error 0 is success."""
    command: int
    code: int
    spec: int = 0

    @property
    def ok(self) -> bool:
        return self.code == 0

    @property
    def name(self) -> str:
        return COMMANDS.get(self.command, f"command 0x{self.command:02X}")

    def text(self) -> str:
        name = self.name
        if self.code == 255:
            why = f"manufacturer-specific error {self.spec}"
        else:
            why = _ERRORS.get(self.command, {}).get(self.code, "an error code CiA 305 reserves")
        return f"{name}: LSS error {self.code} ({why})"


def frame(cs: int, value: int | None = None, *more: int) -> bytes:
    """An LSS frame: the command specifier, a 32-bit value (little-endian) or bytes."""
    body = bytes([cs])
    if value is not None:
        body += value.to_bytes(4, "little")
    return (body + bytes(more)).ljust(8, b"\0")


def fastscan_steps(known: dict[int, int], skip: frozenset = frozenset()) -> int:
    """Fastscan steps (each one ``wait``) of one :meth:`Master.fastscan` at most: the
    reset, 32 bits and a confirmation for each part scanned, one for each part known."""
    parts = [s for s in range(4) if s not in skip]
    return 1 + sum(1 if s in known else 33 for s in parts)


class Master:
    """The LSS master on a ``canopen.Network``: ``timeout`` for an answer that ends the
    wait, ``wait`` for the steps whose answer may be silence."""

    def __init__(self, net, *, timeout: float = TIMEOUT, wait: float = WAIT):
        self.net, self.timeout, self.wait = net, timeout, wait
        self._frames: list[bytes] = []
        self._cond = threading.Condition()
        self.steps = 0                     # waits of ``wait`` seconds so far
        self.selected = 0                  # answers to the last step into configuration
        net.subscribe(SLAVE_COB, self._on)

    def close(self) -> None:
        if self._on in self.net.subscribers.get(SLAVE_COB, ()):
            self.net.unsubscribe(SLAVE_COB, self._on)

    # -- frames -----------------------------------------------------------------------------
    def _on(self, can_id, data, timestamp) -> None:
        with self._cond:
            self._frames.append(bytes(data))
            self._cond.notify_all()

    def _send(self, frames: list[bytes]) -> None:
        """Forget what came before, then send (a full transmit queue is waited out)."""
        import can
        with self._cond:
            self._frames.clear()
        for data in frames:
            for attempt in range(_SEND_TRIES):
                try:
                    self.net.send_message(MASTER_COB, data)
                    break
                except can.CanOperationError:
                    if attempt == _SEND_TRIES - 1:
                        raise
                    time.sleep(_SEND_PAUSE)

    def _ask(self, frames: list[bytes], answer: int, size: int = 1) -> bytes | None:
        """Send ``frames``; the first frame since then whose command specifier is
        ``answer`` (and that holds ``size`` bytes), or None after ``timeout``."""
        self._send(frames)
        end = time.monotonic() + self.timeout
        with self._cond:
            while True:
                for data in self._frames:
                    if len(data) >= size and data[0] == answer:
                        return data
                rest = end - time.monotonic()
                if rest <= 0:
                    return None
                self._cond.wait(rest)

    def _ask_all(self, frames: list[bytes], answer: int, size: int = 1) -> list[bytes]:
        """Send ``frames``; the frames answering them (as :meth:`_ask` takes one) that came
        until ``wait`` seconds after the first (none after ``timeout``): one is expected,
        so a second is a second node."""
        self._send(frames)
        end = time.monotonic() + self.timeout
        first = None
        with self._cond:
            while True:
                got = [d for d in self._frames if len(d) >= size and d[0] == answer]
                now = time.monotonic()
                if got and first is None:
                    first = now
                    end = now + self.wait
                    self.steps += 1        # a wait of ``wait``: silence is the answer
                if now >= end:
                    return got
                self._cond.wait(end - now)

    def _count(self, frames: list[bytes], answer: int) -> int:
        """Send ``frames``; how many answers ``answer`` came within ``wait``."""
        self._send(frames)
        self.steps += 1
        time.sleep(self.wait)              # silence is an answer here: the window is the wait
        with self._cond:
            return sum(1 for d in self._frames if d[:1] == bytes([answer]))

    # -- services ---------------------------------------------------------------------------
    def switch_global(self, *, configuration: bool) -> None:
        """Every slave into the configuration or the waiting state (no answer). A slave that
        had no node-ID and was given one takes it on its way back to waiting."""
        self.net.lss.send_switch_state_global(CONFIGURATION if configuration else WAITING)

    def select(self, identity: Identity, count: bool = True) -> int:
        """Switch state selective: the slave with this identity into configuration. How
        many answers came (0: none; more than 1: that many nodes have this identity, or
        the slave answers twice). ``count`` False takes the first answer at once (1): for
        an identity already counted when it was found."""
        frames = [frame(cs, v) for cs, v in zip(SELECT, identity.parts)]
        if count:
            self.selected = len(self._ask_all(frames, SELECTED))
        else:
            self.selected = int(self._ask(frames, SELECTED) is not None)
        return self.selected

    def _configure(self, cs: int, *data: int) -> Reply | None:
        # one answer taken at once: the selection before it counted the nodes it switched
        # into configuration, and only those answer
        got = self._ask([frame(cs, None, *data)], cs, size=3)
        return None if got is None else Reply(cs, got[1], got[2])

    def configure_node_id(self, node_id: int) -> Reply | None:
        return self._configure(CONFIGURE_NODE_ID, node_id)

    def configure_bit_timing(self, bitrate: int) -> Reply | None:
        return self._configure(CONFIGURE_BIT_TIMING, 0, BIT_TIMINGS[bitrate])

    def store(self) -> Reply | None:
        return self._configure(STORE)

    def inquire(self, part: int) -> int | None:
        """One part (0 vendor-ID ... 3 serial) of the identity of the slave in configuration."""
        got = self._ask([frame(INQUIRE[part])], INQUIRE[part], size=5)
        return None if got is None else int.from_bytes(got[1:5], "little")

    def inquire_node_id(self) -> int | None:
        got = self._ask([frame(INQUIRE_NODE_ID)], INQUIRE_NODE_ID, size=2)
        return None if got is None else got[1]

    def identify(self, vendor: int, product: int, revisions=(0, MAX32),
                 serials=(0, MAX32)) -> int:
        """Identify remote slave: how many slaves (any state) with this vendor-ID and
        product code, revision and serial within the ranges (bounds included) answered."""
        values = (vendor, product, *revisions, *serials)
        return self._count([frame(cs, v) for cs, v in zip(IDENTIFY, values)], IDENTIFIED)

    def non_configured(self) -> int:
        """Identify non-configured remote slave: how many slaves without a node-ID answered."""
        return self._count([frame(IDENTIFY_NON_CONFIGURED)], NON_CONFIGURED)

    def _step(self, value: int, bit: int, sub: int, next_: int) -> int:
        return self._count([frame(FASTSCAN, value, bit, sub, next_)], IDENTIFIED)

    def fastscan(self, known: dict[int, int] | None = None,
                 skip: frozenset = frozenset()) -> tuple[bool, dict[int, int] | None]:
        """One fastscan among the unconfigured slaves in the waiting state: the parts
        ``known`` (0 vendor-ID ... 3 serial) confirmed in one step each, the others scanned
        bit by bit (the lowest value any slave has), the parts in ``skip`` left out (never
        the vendor-ID). Returns whether any slave answered the reset step, and the parts
        found (None: no slave matched); the slave found is then in configuration, and
        takes part in no further fastscan until it is back in waiting."""
        known = known or {}
        self.selected = 0
        present = self._step(0, FASTSCAN_RESET, 0, 0) > 0
        if not present:
            return False, None
        subs = [s for s in range(4) if s not in skip or s == 0]
        found: dict[int, int] = {}
        for k, sub in enumerate(subs):
            following = subs[(k + 1) % len(subs)]    # back to the first: into configuration
            value = known.get(sub)
            if value is None:
                value = 0
                for bit in range(31, -1, -1):
                    if not self._step(value, bit, sub, sub):
                        value |= 1 << bit
            answers = self._step(value, 0, sub, following)
            if not answers:
                return present, None
            found[sub] = value
            self.selected = answers        # the last one: into configuration
        return present, found

    def matches(self, known: dict[int, int]) -> bool:
        """Does an unconfigured slave in the waiting state hold these parts (0 vendor-ID ...
        3 serial)? Fastscan's reset and one confirmation per part; the slave stays in
        waiting."""
        if not self._step(0, FASTSCAN_RESET, 0, 0):
            return False
        subs = sorted(known)
        for k, sub in enumerate(subs):
            following = subs[k + 1] if k + 1 < len(subs) else sub
            if not self._step(known[sub], 0, sub, following):
                return False
        return True

    def search(self, vendor: int, product: int, revisions=(0, MAX32), serials=(0, MAX32),
               limit: int = 2) -> list[tuple[int, int]]:
        """The (revision, serial) of the slaves with this vendor-ID and product code within
        the ranges, by identify remote slave halving each range that answers; at most
        ``limit`` of them. A range whose lower half is silent has its answer in the upper
        half, which is not asked again (a single value always is)."""
        out: list[tuple[int, int]] = []

        def halve(lo: int, hi: int, ask, leaf, answered: bool = False) -> None:
            if len(out) >= limit:
                return
            if lo == hi:
                if ask(lo, hi):
                    leaf(lo)
                return
            if not answered and not ask(lo, hi):
                return
            mid = (lo + hi) // 2
            lower = mid == lo or ask(lo, mid)
            if lower:
                halve(lo, mid, ask, leaf, answered=True)
            halve(mid + 1, hi, ask, leaf, answered=not lower)

        def revision_found(rev: int) -> None:
            halve(*serials, lambda lo, hi: self.identify(vendor, product, (rev, rev), (lo, hi)),
                  lambda serial: out.append((rev, serial)))

        halve(*revisions, lambda lo, hi: self.identify(vendor, product, (lo, hi), serials),
              revision_found)
        return out


@dataclass
class Census:
    """What :func:`unconfigured` found: the identities, the fastscans run, whether it
    ended because no node was left (False: a fastscan singled out nobody, again), and the
    identities that more than one node answered to (identity -> answers counted)."""
    identities: list[Identity]
    rounds: int
    complete: bool
    shared: dict[Identity, int] = field(default_factory=dict)


def unconfigured(master: Master, limit: int = 127, retries: int = 2) -> Census:
    """Every node without a node-ID, by fastscan repeated until none answers its reset
    step (at most ``limit`` nodes). Each identity found is confirmed by identify remote
    slave; a fastscan that ends with nobody, or with an identity nobody confirms, is
    run again up to ``retries`` times in a row. The nodes found stay in configuration
    (so that the next fastscan passes them by) until the caller switches them back."""
    found: list[Identity] = []
    shared: dict[Identity, int] = {}
    rounds = failures = 0
    while len(found) < limit:
        rounds += 1
        present, parts = master.fastscan()
        if not present:
            return Census(found, rounds, True, shared)
        if parts is not None:
            identity = Identity(*(parts[k] for k in range(4)))
            selected = master.selected
            answers = master.identify(identity.vendor, identity.product,
                                      (identity.revision,) * 2, (identity.serial,) * 2)
            if answers:
                found.append(identity)
                if max(answers, selected) > 1:     # nodes alike in all four parts
                    shared[identity] = max(answers, selected)
                failures = 0
                continue
        failures += 1
        if failures > retries:
            return Census(found, rounds, False, shared)
    return Census(found, rounds, True, shared)


def census_bound(rounds: int, wait: float) -> float:
    """Seconds ``rounds`` fastscans of nothing known take at most (and each confirmation)."""
    return rounds * (fastscan_steps({}) + 1) * wait

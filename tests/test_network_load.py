"""The bus-load estimate (SPEC §10.4, D-20), computed by hand.

A frame of n data bytes: 47 + 8n bits with an 11-bit ID, 67 + 8n with a 29-bit ID, plus
the worst-case stuff bits ⌊(34 + 8n − 1) / 4⌋ (⌊(54 + 8n − 1) / 4⌋).
"""
from __future__ import annotations

import pathlib

import pytest

from dcf2bin.network.cpj import read
from dcf2bin.network.load import estimate, frame_bits, pdo_rate
from dcf2bin.network.model import (COB_EXTENDED, COB_INVALID, MASTER, RPDO, SLAVE, TPDO,
                                   Heartbeat, Mapped, Network, Node, Pdo)

FIX = pathlib.Path(__file__).parent / "fixtures" / "network" / "check"


@pytest.mark.parametrize("n,extended,bits", [
    (0, False, 55),      # 47 + 0 + ⌊33/4⌋ = 47 + 8
    (1, False, 65),      # 47 + 8 + ⌊41/4⌋ = 55 + 10
    (2, False, 75),      # 47 + 16 + ⌊49/4⌋ = 63 + 12
    (4, False, 95),      # 47 + 32 + ⌊65/4⌋ = 79 + 16
    (8, False, 135),     # 47 + 64 + ⌊97/4⌋ = 111 + 24: the classic worst case
    (0, True, 80),       # 67 + 0 + ⌊53/4⌋ = 67 + 13
    (8, True, 160),      # 67 + 64 + ⌊117/4⌋ = 131 + 29
])
def test_frame_bits(n, extended, bits):
    assert frame_bits(n, extended) == bits


def _tpdo(t, **kw):
    return Pdo(2, TPDO, 1, 0x182, transmission=t, mapping=[Mapped(0x6000, 1, 8)], **kw)


@pytest.mark.parametrize("pdo,rate", [
    (_tpdo(255, event_timer=20), 50.0),            # 1000 / 20 ms
    (_tpdo(254, event_timer=20, inhibit_time=100), 50.0),   # the event timer wins
    (_tpdo(255, inhibit_time=50), 200.0),          # 10000 / 50 (×100 µs = 5 ms): upper bound
    (_tpdo(255), None),                            # event-driven without timers: unknown
    (_tpdo(253), None), (_tpdo(252), None), (_tpdo(241), None), (_tpdo(251), None),
    (_tpdo(0), 100.0),                             # acyclic synchronous: the SYNC rate
    (_tpdo(1), 100.0),
    (_tpdo(4), 25.0),                              # every 4th SYNC
    (_tpdo(240), 100 / 240),
])
def test_pdo_rate(pdo, rate):
    assert pdo_rate(pdo, 100.0) == rate


def test_the_fixture_network():
    load = estimate(read(str(FIX / "network.cpj")))
    rows = [(r.can_id, r.what, r.producer.name, [(n.name, p.label if p else None)
                                                 for n, p in r.consumers],
             r.bytes, r.rate, r.bits) for r in load.rows]
    assert rows == [
        # SYNC of the PLC: 0x1006 = 10000 µs -> 100/s, no counter: 0 bytes, 55 bits
        (0x080, "SYNC", "plc", [("io", "TPDO1")], 0, 100.0, 55),
        # io TPDO1: type 1 -> 100/s; 8+8+16 bits = 4 bytes, 95 bits
        (0x182, "TPDO1", "io", [("plc", "RPDO1")], 4, 100.0, 95),
        # plc TPDO1: type 255, event timer 50 ms -> 20/s; 2 bytes, 75 bits
        (0x202, "TPDO1", "plc", [("io", "RPDO1")], 2, 20.0, 75),
        # plc TPDO2: event timer 100 ms -> 10/s; 1 byte, 65 bits
        (0x302, "TPDO2", "plc", [("io", "RPDO2")], 1, 10.0, 65),
        # heartbeats: plc every 100 ms (10/s), io every 200 ms (5/s); 1 byte, 65 bits;
        # io3 produces none (0x1017 = 0)
        (0x701, "heartbeat", "plc", [("io", None), ("io3", None)], 1, 10.0, 65),
        (0x702, "heartbeat", "io", [("plc", None)], 1, 5.0, 65),
    ]
    # 100·55 + 100·95 + 20·75 + 10·65 + 10·65 + 5·65 = 5500 + 9500 + 1500 + 650 + 650 + 325
    # = 18125 bit/s of 500000: 3.625 %
    assert load.total == pytest.approx(3.625)
    assert [round(r.share, 4) for r in load.rows] == [1.1, 1.9, 0.3, 0.13, 0.13, 0.065]
    assert load.unknown == []


def test_unknown_rates_are_listed_and_count_zero():
    m = Node("plc", 1, MASTER)
    s = Node("drive", 2, SLAVE, pdos=[
        _tpdo(255),                                       # unknown
        Pdo(2, TPDO, 2, 0x282, transmission=254, event_timer=10,
            mapping=[Mapped(0x6041, 0, 16), Mapped(0x6064, 0, 32)]),
    ])
    load = estimate(Network("bus.yml", nodes=[m, s], bitrate=250_000))
    assert [(r.can_id, r.rate) for r in load.rows] == [(0x182, None), (0x282, 100.0)]
    assert [r.can_id for r in load.unknown] == [0x182]
    # TPDO2: 6 bytes -> 47 + 48 + ⌊81/4⌋ = 95 + 20 = 115 bits × 100/s = 11500 bit/s of
    # 250000 = 4.6 %
    assert load.total == pytest.approx(4.6)


def test_each_cob_id_is_counted_once_at_its_producer():
    a = Node("a", 2, SLAVE, pdos=[Pdo(2, TPDO, 1, 0x182, 255, event_timer=10,
                                      mapping=[Mapped(0x6000, 1, 8)])])
    b = Node("b", 3, SLAVE, pdos=[
        Pdo(3, TPDO, 1, 0x182, 255, event_timer=1, mapping=[Mapped(0x6000, 1, 8)]),
        Pdo(3, RPDO, 1, 0x182, 255, mapping=[Mapped(0x6200, 1, 8)]),
        Pdo(3, TPDO, 2, 0x282 | COB_INVALID, 255, event_timer=1,     # does not exist
            mapping=[Mapped(0x6000, 1, 8)]),
        Pdo(3, TPDO, 3, 0x382, 255, event_timer=1),                   # maps nothing
    ])
    load = estimate(Network("bus.yml", nodes=[a, b]))
    assert [(r.can_id, r.producer.name, r.rate) for r in load.rows] == [(0x182, "a", 100.0)]
    assert [(n.name, p.label) for n, p in load.rows[0].consumers] == [("b", "RPDO1")]


def test_extended_ids_sync_counter_and_bitrate():
    m = Node("plc", 1, MASTER, sync_producer=True, sync_period=2000, sync_counter=16,
             pdos=[Pdo(1, TPDO, 1, 0x1234567 | COB_EXTENDED, 2,
                       mapping=[Mapped(0x2000, 0, 64)])], heartbeat_producer=50)
    s = Node("io", 2, SLAVE, heartbeat_consumers=[Heartbeat(1, 150)])
    load = estimate(Network("bus.yml", nodes=[m, s], bitrate=1_000_000))
    assert [(r.can_id, r.extended, r.what, r.bytes, r.rate, r.bits) for r in load.rows] == [
        # SYNC: 10^6 / 2000 µs = 500/s; a counter (0x1019 = 16): 1 byte, 65 bits
        (0x80, False, "SYNC", 1, 500.0, 65),
        # heartbeat: 1000 / 50 ms = 20/s, 65 bits
        (0x701, False, "heartbeat", 1, 20.0, 65),
        # 29-bit TPDO1, type 2: 250/s, 8 bytes: 160 bits
        (0x1234567, True, "TPDO1", 8, 250.0, 160),
    ]
    # 500·65 + 20·65 + 250·160 = 32500 + 1300 + 40000 = 73800 bit/s of 10^6: 7.38 %
    assert load.total == pytest.approx(7.38)
    assert load.rows[1].consumers == [(s, None)]


def test_no_sync_producer_synchronous_pdos_count_zero():
    s = Node("io", 2, SLAVE, pdos=[_tpdo(1)])
    load = estimate(Network("bus.yml", nodes=[s]))
    assert [(r.can_id, r.rate, r.share) for r in load.rows] == [(0x182, 0.0, 0.0)]
    assert load.unknown == [] and load.total == 0.0

"""Open a ``canopen.Network`` on a python-can interface, and name SDO abort codes.

Interface, channel and bitrate left out are taken from python-can's own
configuration (the ``CAN_INTERFACE``/``CAN_CHANNEL``/``CAN_BITRATE`` environment
variables, ``~/.canrc`` and the other files python-can reads), as ``can.Bus()`` does.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass

from dcf2bin.diagnostics import shorten

# The notifier thread wakes this often to see whether it should stop; python-can's
# default (1 s) would make every disconnect wait up to a second.
NOTIFIER_CYCLE = 0.05

# CiA 301 abort codes that canopen's table (SdoAbortedError.CODES) does not name
_MORE_ABORTS = {
    0x06040041: "Object cannot be mapped to the PDO",
    0x08000020: "Data cannot be transferred or stored to the application",
}


# why a node in another process is never heard on python-can's virtual interface
VIRTUAL_NOTE = ("python-can's virtual bus reaches only this process: a node run by another "
                "process cannot answer")


class BusError(Exception):
    """The CAN interface could not be opened or used (one line for the user)."""


@dataclass
class BusConfig:
    interface: str | None = None
    channel: str | None = None
    bitrate: int | None = None

    def kwargs(self) -> dict:
        return {k: v for k, v in (("interface", self.interface), ("channel", self.channel),
                                  ("bitrate", self.bitrate)) if v is not None}

    def describe(self) -> str:
        parts = [f"{k} {v}" for k, v in self.kwargs().items()]
        return ", ".join(parts) or "python-can's configuration"


def quiet_libraries() -> None:
    """canopen and python-can log warnings (retries, aborts) that would print through
    logging's last-resort handler; the commands report those themselves."""
    for name in ("canopen", "can"):
        logger = logging.getLogger(name)
        if not any(isinstance(h, logging.NullHandler) for h in logger.handlers):
            logger.addHandler(logging.NullHandler())


def open_network(config: BusConfig):
    """A connected ``canopen.Network``; ``BusError`` when python-can cannot open it."""
    import can
    import canopen
    net = canopen.Network()
    net.NOTIFIER_CYCLE = NOTIFIER_CYCLE
    try:
        net.connect(**config.kwargs())
    except can.CanInterfaceNotImplementedError as exc:
        if config.interface is None:
            raise BusError("no CAN interface given: use --interface and --channel, or a "
                           "python-can configuration file") from None
        raise BusError(f"CAN interface {shorten(config.interface)!r}: {exc}") from None
    except (can.CanError, OSError, ValueError, ImportError, TypeError) as exc:
        raise BusError(f"cannot open the CAN interface ({config.describe()}): "
                       f"{exc}") from None
    return net


def is_virtual(net) -> bool:
    """The network is on python-can's virtual interface (whose buses are those of one
    process), given by name or by python-can's configuration."""
    return type(getattr(net, "bus", None)).__name__ == "VirtualBus"


def close_network(net) -> None:
    """Disconnect (stops the notifier thread and the periodic tasks of the bus)."""
    if net is not None and net.bus is not None:
        net.disconnect()


def abort_text(code: int) -> str:
    """The CiA 301 meaning of an SDO abort code (canopen's table first)."""
    from canopen import SdoAbortedError
    text = SdoAbortedError.CODES.get(code) or _MORE_ABORTS.get(code)
    return text or "not an abort code CiA 301 defines"


def abort_message(code: int) -> str:
    """An SDO abort as every message says it: its code and its meaning."""
    return f"SDO abort 0x{code:08X}: {abort_text(code)}"

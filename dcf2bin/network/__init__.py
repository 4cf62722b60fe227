"""``dcf2bin network``: a PLC's CANopen network from its network file (SPEC §10).

* :func:`load_network` reads a network file (YAML: lely's ``dcfgen`` / ros2_canopen's
  ``bus.yml``) into the :class:`~dcf2bin.network.model.Network` model;
* :func:`configure` applies the configuration in memory (links, COB-IDs, variables, the
  PLC's NMT entries, the slaves' write lists);
* :func:`build_network` does both and makes the outputs (the PLC's DCF, per slave a
  concise DCF ``.bin`` and a ``.dcf``) as bytes, writing them when asked.

Nothing here imports click; the command line is ``dcf2bin/cli/network/``.
"""
from __future__ import annotations

from dcf2bin.network.model import Network


def load_network(path: str, data: bytes | None = None) -> Network:
    """Read a network file (``.yml``/``.yaml``); findings in ``network.diagnostics``.
    A file that cannot be read raises OSError."""
    from dcf2bin.network.yamlfile import load_network as _load
    return _load(path, data)


def configure(network: Network) -> Network:
    """Configure ``network`` in place (D-17, D-18) and return it."""
    from dcf2bin.network.configuration import configure as _configure
    return _configure(network)


def build_network(path: str, outdir: str | None = None, *, data: bytes | None = None,
                  master: str | None = None, select=None, ignore=None):
    """Read, configure, check and build a network; see :mod:`dcf2bin.network.build`."""
    from dcf2bin.network.build import build_network as _build
    return _build(path, outdir, data=data, master=master, select=select, ignore=ignore)


__all__ = ["Network", "build_network", "check_network", "configure", "load_network"]

from dcf2bin.network.check import check_network  # noqa: E402  (network check's)

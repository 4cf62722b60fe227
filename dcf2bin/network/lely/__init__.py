"""A lely master (SPEC §10.2a, D-21): what ``dcfgen -r`` writes for a master without
``dcf:`` -- ros2_canopen's ``canopen_master_driver`` runs lely's master from it.

* :mod:`.order` -- the slaves in the order dcfgen sees them, and the master's PDO numbers
  in that order (called by ``configure``, so that ``check`` and ``show`` number them as
  ``build`` does);
* :mod:`.identity` -- 0x1F84-0x1F88 as dcfgen fills them, and the master's own writes
  (``master.bin``);
* :mod:`.layout` -- the master's PDOs mapped to the application objects 0x2000/0x2200 and
  the remote-PDO records 0x5800-0x5FFF;
* :mod:`.masterdcf` -- ``master.dcf`` as text;
* :func:`make_outputs` -- every output as (file name, bytes), in the order they are
  written.

lely dcf-tools 2.4.2 is the reference wherever it is right; docs/network.md "dcf2bin as
dcfgen" lists where dcf2bin differs and why.
"""
from __future__ import annotations

from dcf2bin.diagnostics import Diagnostics
from dcf2bin.network.model import Network


def make_outputs(net: Network, names: dict[str, str], diags: Diagnostics) -> dict[str, bytes]:
    """``<master>.dcf``, ``<master>.bin`` when the master has writes of its own, and one
    concise DCF ``<slave>.bin`` per slave (D-18) in dcfgen's order. ``names``: node name
    -> output base name."""
    from dcf2bin.network.concise import concise_dcf
    from dcf2bin.network.lely.identity import master_writes
    from dcf2bin.network.lely.masterdcf import master_dcf
    master = net.master
    outputs: dict[str, bytes] = {}
    base = names[master.name]
    outputs[base + ".dcf"] = master_dcf(net, names).encode("utf-8")
    own = master_writes(net)
    if own:
        from dcf2bin.network.model import Node
        outputs[base + ".bin"] = concise_dcf(Node(master.name, master.node_id, master.role,
                                                  writes=own))
    from dcf2bin.network.lely.order import dcfgen_order
    for s in dcfgen_order(net):
        outputs[names[s.name] + ".bin"] = concise_dcf(s)
    return outputs

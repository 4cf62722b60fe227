"""On the bus: download a configuration by SDO, read one back, configure and scan a
network, and run a software CANopen node.

Everything here stands on ``canopen`` (SDO server, LocalNode, PDO maps, NMT, the
network and its notifier) over ``python-can`` (every interface it supports). The SDO
client is dcf2bin's own (sdo.py): canopen's reads a segmented upload for as long as the
node sends segments, and lets a malformed answer escape as ``struct.error``; every
transfer here is bounded in time and bytes and ends as data or one ``SdoError``. Nothing
here drives a CAN adapter itself or imports click.
LSS is spoken by ``lss`` and ``lss_slave`` (canopen's LssMaster falls short; see lss.py).

    link.py      open a canopen.Network on a python-can interface; abort-code texts
    sdo.py       the SDO client: upload and download, bounded; Upload/Download machines
    download.py  plan (the writes of a container, each with its DCF line), run, verify
    upload.py    a node read back into a DCF: which entries, each value checked against its
                 type, refusals as comments; several nodes at once
    netconf.py   a network's slaves configured in node-ID order, each after its identity
    scan.py      which node-IDs answer (all 127 asked at once) and who they say they are
    node.py      a LocalNode from an EDS/DCF or an emulated SYS TEC target
    lss.py       the LSS master (CiA 305): every answer matched to its request
    lssnet.py    a network's slaves given their node-IDs by LSS: find, check, assign
    lss_slave.py the software node's LSS slave (hooked into node.py as ``node.lss``)
"""

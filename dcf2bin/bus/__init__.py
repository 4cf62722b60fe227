"""On the bus: download a configuration by SDO and run a software CANopen node.

Everything here stands on ``canopen`` (SDO client and server, LocalNode, PDO maps,
NMT) over ``python-can`` (every interface it supports). Nothing here speaks the SDO
protocol or drives a CAN adapter itself, and nothing here imports click.

    link.py      open a canopen.Network on a python-can interface; abort-code texts
    download.py  plan (the writes of a container, each with its DCF line), run, verify
    node.py      a LocalNode from an EDS/DCF or an emulated SYS TEC target
"""

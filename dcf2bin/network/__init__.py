"""The network (SPEC §10): a PLC and its slaves configured as one, from a lely/ros2_canopen
``bus.yml`` or a CiA 306-3 ``.cpj`` project. ``model`` is the configured network every
command reads; this package never imports click (the commands are ``dcf2bin.cli.network``).
"""

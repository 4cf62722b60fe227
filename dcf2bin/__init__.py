"""dcf2bin: CANopen DCF/EDS <-> SYS TEC binary DCF segment container.

Importing the package is cheap: it must not pull in canopen or construct,
so that ``dcf2bin --help`` and ``--version`` stay fast.
"""

__version__ = "0.1.0"

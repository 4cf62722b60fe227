"""The codes of the network file reader (NET001-NET099), of the configuration and of
build's output folder (NET100-NET199): id, severity, one line. Plain data: ``network
check`` builds its rule table (and ``--select``/``--ignore``) from this and its own NET2xx
rules; docs/network.md lists the same table (a test compares them).
"""
from __future__ import annotations

ERROR, WARNING, INFO = "error", "warning", "info"

# (code, severity, description)
CODES: list[tuple[str, str, str]] = [
    # -- the network file (D-16) ----------------------------------------------------------
    ("NET001", ERROR, "the network file cannot be read: YAML syntax, encoding, not a mapping"),
    ("NET002", ERROR, "a key repeated in one YAML mapping (both lines named)"),
    ("NET003", ERROR, "the YAML expands too far: alias bomb, recursive alias, deep nesting"),
    ("NET004", ERROR, "a value of the wrong type or out of range (integer, boolean, "
                      "list, mapping, PDO number, node-ID)"),
    ("NET005", ERROR, "a required key is missing: master, a slave, node_id, a slave's dcf"),
    ("NET006", WARNING, "a key that resembles a key dcf2bin reads (a misspelling?)"),
    ("NET007", INFO, "a key dcf2bin does not use (ros2_canopen's driver, package, ...): "
                     "ignored"),
    ("NET008", WARNING, "eds: is read as dcf:"),
    ("NET009", WARNING, "a key given in both defaults: and the node: the node's is taken "
                        "(ros2_canopen's generator takes the one of defaults:)"),
    ("NET010", ERROR, "a node's file (EDS, DCF, XDD, XDC) cannot be read (missing, a "
                      "directory, no permission)"),
    ("NET011", ERROR, "a node's file is no device description (EDS, DCF, XDD, XDC): a "
                      "binary container, its JSON form, a concise DCF, another kind of "
                      "file: it is not read"),
    ("NET012", ERROR, "build reads a YAML network file: a .cpj project has no master and "
                      "nothing to build"),
    # -- the configuration (D-17, D-18) ---------------------------------------------------
    ("NET101", ERROR, "a YAML PDO that the node's file does not have"),
    ("NET102", ERROR, "a mapped object that the slave's file lacks"),
    ("NET103", ERROR, "an object not mappable in that direction (TPDO: readable and not "
                      "rww; RPDO: writable and not rwr)"),
    ("NET104", ERROR, "a linked object whose data type has no CiA 405 range"),
    ("NET105", ERROR, "a PDO kept from a file maps a zero entry among its subs 1..n: an "
                      "error when the YAML lists that PDO, else a warning (the slave keeps "
                      "it, nothing links it)"),
    ("NET106", ERROR, "a name: that is not an IEC 61131-3 identifier"),
    ("NET107", ERROR, "two names for one object, or one name for two objects"),
    ("NET108", ERROR, "the PLC cannot take a link: no free PDO (one finding for all the "
                      "links of one kind that find none), no sub for the inhibit "
                      "time/event timer, too few mapping subs"),
    ("NET109", ERROR, "no free COB-ID is left to assign"),
    ("NET110", WARNING, "the PLC's file lacks an NMT entry: it is not written"),
    ("NET111", ERROR, "an NMT entry beyond the subs of the PLC's object"),
    ("NET112", ERROR, "a configured field out of range (retry_factor, guard_time, a "
                      "heartbeat time over 65535 ms)"),
    ("NET113", WARNING, "the identity of [DeviceInfo] differs from the file's 0x1018"),
    ("NET114", ERROR, "a write into an entry the slave's file lacks or marks read-only"),
    ("NET115", ERROR, "no free 0x1016 sub for the slave's heartbeat consumer"),
    ("NET116", WARNING, "heartbeat_consumer is true but the master produces no heartbeat"),
    ("NET117", ERROR, "an sdo: value that its entry's data type cannot hold"),
    ("NET118", ERROR, "the PLC's file cannot take the variables ([DynamicChannels], a "
                      "range full)"),
    ("NET119", ERROR, "build needs the PLC's EDS/DCF as the master's dcf:"),
    ("NET120", ERROR, "an output cannot be made: a node name that cannot be a file name, "
                      "two nodes with one output file, an entry the file only implies "
                      "(CompactPDO) with no section to state its value in"),
    ("NET121", WARNING, "a listed PDO with an empty mapping: (null or []) is enabled with no "
                        "object: it exists on the device, but nothing links it"),
    ("NET122", WARNING, "one object mapped twice in one PDO's mapping:"),
    ("NET123", WARNING, "a names: entry for an object that no linked PDO of that slave "
                        "maps: the name is not used"),
    ("NET124", WARNING, "a key of lely's dcfgen that a PLC master does not use (its own "
                        "identity, dcf_path, configuration_file, software_file): what dcfgen "
                        "would do for a lely master is not done"),
    ("NET125", ERROR, "a mapping: of more than 64 bits: a PDO is one classic CAN frame of "
                      "at most 8 bytes"),
    # -- build's output folder ------------------------------------------------------------
    ("NET130", WARNING, "a file an earlier build wrote in the output folder that this "
                        "network does not make (a slave that left it): kept, never deleted"),
    ("NET131", WARNING, "a build stopped while writing its files (SIGKILL, power loss) was "
                        "undone in the output folder before this one wrote"),
]

BY_CODE = {c: (sev, text) for c, sev, text in CODES}

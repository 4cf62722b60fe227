"""The CiA 301 default: disable with bit 31, enable with the final COB-ID."""
from dcf2bin.profiles import Profile

PROFILE = Profile("cia301", "CiA 301 PDO reconfiguration (default)")

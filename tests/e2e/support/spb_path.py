"""Puts tests/e2e/sparkplug on the import path: the Python e2e tests share its spb_e2e package's
process handling (processes: started processes ended by their ids, free ports, deadlines) and
named checks (checks)."""
import os
import sys

_sparkplug = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "sparkplug")
if os.path.normpath(_sparkplug) not in (os.path.normpath(p) for p in sys.path):
    sys.path.insert(0, os.path.normpath(_sparkplug))

"""tshark, Debian's reader of Wireshark's dissectors, as the e2e tests read a capture with it:
each packet's fields, the project's Lua dissectors loaded, and a home of the test's own so no
one's preferences apply."""
import os
import subprocess

SOURCE_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
LUA = os.path.join(SOURCE_DIR, "packaging", "wireshark", "tiltgate.lua")


def tshark_fields(path, fields, home, extra=(), display_filter=None):
    """Each packet of `path` as a list of `fields` (the first occurrence of each)."""
    argv = ["tshark", "-r", path, "-X", "lua_script:" + LUA, "-T", "fields", "-E", "separator=|",
            "-E", "occurrence=f"]
    argv += list(extra)
    if display_filter:
        argv += ["-Y", display_filter]
    for f in fields:
        argv += ["-e", f]
    done = subprocess.run(argv, capture_output=True, text=True, timeout=120,
                          env=dict(os.environ, HOME=home))
    if done.returncode != 0:
        raise RuntimeError("tshark failed:\n" + done.stderr)
    return [line.split("|") for line in done.stdout.splitlines() if line]

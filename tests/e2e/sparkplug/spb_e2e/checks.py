"""Named checks, counted like tests/e2e/support/script_lib.sh's `check`: a failure prints its
name and what was seen, and the script's exit status says whether all passed. A check that
cannot be made (the gateway exited, a message never came) fails, never skips."""
import os
import shutil
import sys
import tempfile
import traceback

from . import processes


class Checks:
    def __init__(self, name):
        self.name = name
        self.passes = 0
        self.failures = 0
        self.dir = tempfile.mkdtemp(prefix="tiltgate-%s-" % name)
        self.logs = []  # (title, path) shown after a failure

    def check(self, name, ok, seen=""):
        if ok:
            self.passes += 1
            print("ok: " + name)
        else:
            self.failures += 1
            print("FAIL: %s\n  seen: %s" % (name, seen))
        sys.stdout.flush()
        return bool(ok)

    def run(self, body):
        """Runs body(self), ends every process it started, reports; the exit status."""
        try:
            body(self)
        except Exception:  # a scenario that could not go on is a failure, with why
            self.failures += 1
            print("FAIL: the scenario stopped:\n" + traceback.format_exc())
        finally:
            processes.end_all()
        if self.failures:
            for title, path in self.logs:
                print("--- %s (%s)\n%s" % (title, path, processes.tail(path, 40)))
        print("%d passed, %d failed" % (self.passes, self.failures))
        if not os.environ.get("KEEP_DIR"):
            shutil.rmtree(self.dir, ignore_errors=True)
        else:
            print("kept " + self.dir)
        return 0 if self.failures == 0 and self.passes > 0 else 1


def arguments():
    """tiltgate binary (argv[1]); the source tree from this file's place in it."""
    if len(sys.argv) < 2:
        sys.exit("usage: %s path/to/tiltgate" % sys.argv[0])
    source = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", "..", ".."))
    return os.path.abspath(sys.argv[1]), source

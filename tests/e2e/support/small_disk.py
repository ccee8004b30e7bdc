"""A small disk of a test's own for the tests of what a full disk does (store_disk_test.py,
audit_disk_test.py): the script runs again in a mount namespace of its own (unshare -m), so no
mount outlives it whatever happens, and mounts a tmpfs of a few KiB it fills to ENOSPC on
demand. Needs root, as CI runs: without it, or without a private mount namespace (a chroot
whose root is no mount point), the script is skipped (exit 77)."""
import errno
import os
import subprocess
import sys


def run_in_own_mount_namespace():
    """Call first: returns in the script run again in a private mount namespace, or exits 77."""
    if os.geteuid() != 0:
        print("skipped: needs root to mount a tmpfs")
        sys.exit(77)
    if os.environ.get("TILTGATE_OWN_MOUNTS") == "1":
        return
    probe = subprocess.run(["unshare", "-m", "--propagation", "private", "true"],
                           capture_output=True, text=True)
    if probe.returncode != 0:
        print("skipped: no private mount namespace here (%s)" % probe.stderr.strip())
        sys.exit(77)
    os.environ["TILTGATE_OWN_MOUNTS"] = "1"
    os.execvp("unshare", ["unshare", "-m", "--propagation", "private", sys.executable] + sys.argv)


class SmallDisk:
    """A tmpfs of `kib` KiB at `path`, in this process's own mount namespace."""

    def __init__(self, path, kib):
        self.path = path
        os.makedirs(path, exist_ok=True)
        subprocess.run(["mount", "-t", "tmpfs", "-o", "size=%dk" % kib, "tmpfs", path], check=True)

    def fill(self):
        """Every free block taken: the next write that needs one gets ENOSPC."""
        with open(os.path.join(self.path, "filler"), "ab", buffering=0) as f:
            for size in (65536, 4096, 512, 64, 8, 1):
                try:
                    while True:
                        f.write(b"x" * size)
                except OSError as e:
                    if e.errno != errno.ENOSPC:
                        raise

    def free(self):
        os.remove(os.path.join(self.path, "filler"))

    def unmount(self):
        subprocess.run(["umount", "-l", self.path])

"""What `ip netns add` leaves behind: the first namespace made on a machine bind-mounts
/run/netns over itself, and `ip netns del` never takes that mount away. A test that makes a
namespace notes whether the mount was there before (`was_mounted()`) and, once its namespace is
gone, gives the mount back (`release(before)`) if it made it and nothing else uses it, so the
machine (or a chroot that is removed afterwards) is left as it was found."""
import os
import subprocess

RUN_NETNS = "/run/netns"


def _mounted():
    """From the mount table: a bind mount on the same file system is no mount to ismount()."""
    try:
        with open("/proc/self/mountinfo") as table:
            return any(line.split()[4] == RUN_NETNS for line in table if len(line.split()) > 4)
    except OSError:
        return False


def was_mounted():
    return _mounted()


def release(before):
    if before or not _mounted():
        return
    try:
        if os.listdir(RUN_NETNS):
            return  # another namespace is still named there
    except OSError:
        return
    for _ in range(3):  # `ip` may have stacked more than one
        if not _mounted():
            return
        subprocess.run(["umount", RUN_NETNS], stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)

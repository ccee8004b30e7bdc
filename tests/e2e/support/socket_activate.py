#!/usr/bin/env python3
"""Starts a command the way systemd's socket activation does (sd_listen_fds(3)): binds and
listens on each --listen ADDRESS:PORT as the caller (root, for a port below 1024), passes the
sockets as fds 3, 4, ... with LISTEN_FDS and LISTEN_PID, optionally switches to --user first,
and execs the command in this same process (LISTEN_PID must be the command's own pid).

usage: socket_activate.py [--user NAME] --listen 127.0.0.1:502 [...] -- COMMAND [ARGS...]
"""
import fcntl
import os
import pwd
import socket
import sys


def main(argv):
    user = None
    listens = []
    while argv and argv[0] != "--":
        option, value = argv[0], argv[1]
        argv = argv[2:]
        if option == "--user":
            user = value
        elif option == "--listen":
            host, port = value.rsplit(":", 1)
            listens.append((host, int(port)))
        else:
            sys.exit(f"unknown option {option}")
    command = argv[1:]
    if not command or not listens:
        sys.exit(__doc__)
    sockets = []
    for host, port in listens:
        s = socket.socket(socket.AF_INET6 if ":" in host else socket.AF_INET, socket.SOCK_STREAM)
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        s.bind((host, port))
        s.listen(64)
        sockets.append(s)
    # Out of the way first: a socket may already sit on fd 3, 4, ... (and close-on-exec).
    high = [fcntl.fcntl(s.fileno(), fcntl.F_DUPFD, 100 + i) for i, s in enumerate(sockets)]
    for s in sockets:
        s.close()
    for i, fd in enumerate(high):
        os.dup2(fd, 3 + i)
        os.set_inheritable(3 + i, True)
        os.close(fd)
    if user is not None:
        entry = pwd.getpwnam(user)
        os.setgroups([])
        os.setgid(entry.pw_gid)
        os.setuid(entry.pw_uid)
    os.environ["LISTEN_FDS"] = str(len(sockets))
    os.environ["LISTEN_PID"] = str(os.getpid())
    os.execvp(command[0], command)


if __name__ == "__main__":
    main(sys.argv[1:])

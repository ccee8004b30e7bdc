#!/usr/bin/env bash
# `tiltgate user` (accounts/user_command.h, docs/web-console.md "Accounts") as a script uses it:
# the password as one line of standard input; add, list, passwd, remove; the exit codes (0 done,
# 1 failed, 2 usage); the users file with no password in clear, mode 0640, and a new file in
# the group of its folder (when root can give it one); at a terminal (a pseudo-terminal), the
# password typed twice without echo.
set -u
tiltgate=${1:?usage: user_command_test.sh path/to/build/tiltgate}
source "$(dirname "$0")/support/script_lib.sh"
script_setup tiltgate-user

users=$dir/etc/users
mkdir -p "$dir/etc"
[ "$(id -u)" = 0 ] && chgrp nogroup "$dir/etc"
user() { "$tiltgate" user "$@" --users-file "$users"; }
# exits CODE COMMAND...: the command exits with CODE.
exits() { local code=$1; shift; "$@"; test $? = "$code"; }

check "add makes the file, the password read from standard input" \
  bash -c "echo 'alice-Secret-1' | '$tiltgate' user add alice --role admin --users-file '$users'"
check "add a second account" bash -c "printf 'bob-Secret-2\n' | '$tiltgate' user add bob --role viewer --users-file '$users'"
check "the file is mode 0640" test "$(stat -c %a "$users")" = 640
if [ "$(id -u)" = 0 ]; then
  check "a new file takes its folder's group" test "$(stat -c %G "$users")" = nogroup
fi
check "the file holds no password in clear" bash -c "! grep -q Secret '$users'"
check "each account is an argon2id hash" test "$(grep -c '^[a-z]*:[a-z]*:\$argon2id\$v=19\$m=19456,t=3,p=1\$' "$users")" = 2
list=$(user list)
check "list shows names and roles" test "$list" = "$(printf 'alice  admin\nbob    viewer')"
check "list shows no hash" bash -c "! grep -q argon2 <<<'$list'"

hash_before=$(grep '^bob:' "$users")
check "passwd sets a new password" bash -c "echo 'bob-Secret-3' | '$tiltgate' user passwd bob --users-file '$users'"
check "  which is a new hash" test "$(grep '^bob:' "$users")" != "$hash_before"
check "  and alice's is untouched" grep -q '^alice:admin:' "$users"
check "  with no password in clear" bash -c "! grep -q Secret '$users'"

check "add refuses an existing name (1)" exits 1 bash -c "echo x | '$tiltgate' user add bob --role admin --users-file '$users'"
check "add refuses an empty password (1)" exits 1 bash -c "echo | '$tiltgate' user add carol --role viewer --users-file '$users'"
check "add without a password on standard input fails (1)" exits 1 bash -c "'$tiltgate' user add carol --role viewer --users-file '$users' </dev/null"
check "passwd of an unknown account fails (1)" exits 1 bash -c "echo x | '$tiltgate' user passwd carol --users-file '$users'"
check "remove of an unknown account fails (1)" exits 1 user remove carol
check "list of a missing file fails (1)" exits 1 "$tiltgate" user list --users-file "$dir/none"
check "  saying the file is missing" bash -c "'$tiltgate' user list --users-file '$dir/none' 2>&1 | grep -q 'No such file'"
check "an unknown role is a usage error (2)" exits 2 bash -c "echo x | '$tiltgate' user add carol --role boss --users-file '$users'"
check "add without --role is a usage error (2)" exits 2 bash -c "echo x | '$tiltgate' user add carol --users-file '$users'"
check "a name with a colon is a usage error (2)" exits 2 bash -c "echo x | '$tiltgate' user add 'ca:rol' --role viewer --users-file '$users'"
check "user without an action is a usage error (2)" exits 2 "$tiltgate" user
check "the failures changed nothing" test "$(user list)" = "$(printf 'alice  admin\nbob    viewer')"

# The password rules (docs/web-console.md, "Password rules"; issue 52, item 8).
check "add refuses a password of 1 character (1)" exits 1 bash -c "echo x | '$tiltgate' user add carol --role viewer --users-file '$users'"
check "  saying it needs 10" bash -c "echo x | '$tiltgate' user add carol --role viewer --users-file '$users' 2>&1 | grep -q 'at least 10 characters'"
check "add refuses a password of 9 characters (1)" exits 1 bash -c "echo 'abcdefgh9' | '$tiltgate' user add nine --role viewer --users-file '$users'"
check "add refuses the account's name as its password (1)" exits 1 bash -c "echo 'carol.shift' | '$tiltgate' user add carol.shift --role viewer --users-file '$users'"
check "add refuses a common password (1)" exits 1 bash -c "echo 'password123' | '$tiltgate' user add common --role viewer --users-file '$users'"
bob_line=$(grep '^bob:' "$users")
check "passwd refuses a short password (1)" exits 1 bash -c "echo 'short' | '$tiltgate' user passwd bob --users-file '$users'"
check "  and bob's hash is untouched" test "$(grep '^bob:' "$users")" = "$bob_line"
check "the refusals changed nothing" test "$(user list)" = "$(printf 'alice  admin\nbob    viewer')"
check "add --allow-weak takes a short password, for a test rig" bash -c "echo x | '$tiltgate' user add rig --role viewer --allow-weak --users-file '$users'"
check "passwd --allow-weak takes one too" bash -c "echo y | '$tiltgate' user passwd rig --allow-weak --users-file '$users'"
user remove rig >/dev/null

# At a terminal: the password typed twice, never echoed. TYPED... are the lines typed; prints
# what the terminal showed, exits with the command's code.
at_terminal() {
  /usr/bin/python3 - "$tiltgate" "$users" "$@" <<'PY'
import os, pty, signal, sys
tiltgate, users, name, *typed = sys.argv[1:]
pid, fd = pty.fork()
if pid == 0:
    os.execv(tiltgate, [tiltgate, "user", "add", name, "--role", "operator", "--users-file", users])
# A command that waits for a line it never gets fails the test rather than hang it.
def give_up(*_):
    os.kill(pid, signal.SIGKILL)
    sys.stdout.write("no answer in 30 s\n")
    sys.exit(3)
signal.signal(signal.SIGALRM, give_up)
signal.alarm(30)
shown = b""
def read_until(text):
    global shown
    while text not in shown:
        chunk = os.read(fd, 1024)
        if not chunk: return
        shown += chunk
for line in typed:
    read_until(b": ")
    shown = shown.replace(b": ", b":_", 1)  # the next prompt is another ": "
    os.write(fd, line.encode() + b"\n")
try:
    while True:
        chunk = os.read(fd, 1024)
        if not chunk: break
        shown += chunk
except OSError:
    pass
sys.stdout.write(shown.decode(errors="replace"))
sys.exit(os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1]))
PY
}
shown=$(at_terminal dave 'dave-Secret-4' 'dave-Secret-4')
check "at a terminal: the password typed twice adds the account" test $? = 0
check "  asked for twice" bash -c "grep -q 'New password for dave' <<<'$shown' && grep -q 'Again' <<<'$shown'"
check "  never shown" bash -c "! grep -q Secret <<<'$shown'"
check "  and kept as a hash" grep -q '^dave:operator:\$argon2id' "$users"
shown=$(at_terminal erin 'erin-Secret-5' 'erin-Secret-6')
check "at a terminal: two different passwords add nothing (1)" test $? = 1
check "  saying why" bash -c "grep -q 'the two passwords typed differ' <<<'$shown'"
check "  and no account" bash -c "! grep -q '^erin:' '$users'"

echo "# a comment kept" >>"$users"
check "remove an account" user remove bob
check "  leaving the others" test "$(user list)" = "$(printf 'alice  admin\ndave   operator')"
check "  and the comment" grep -qx '# a comment kept' "$users"
check "  still mode 0640" test "$(stat -c %a "$users")" = 640
echo "bob:admin:bob-Secret-2" >>"$users"
check "a line with a password in clear is an error at its line (1)" exits 1 user list
check "  without repeating it" bash -c "'$tiltgate' user list --users-file '$users' 2>&1 | grep -v Secret | grep -q 'users:[0-9]*: bob: the third field is not an argon2id hash'"
# `tiltgate user` rewrites the whole file: on a file with a malformed line it refuses, naming the
# line, rather than drop it (issue 54, defect 7).
before=$(cat "$users")
check "an edit of a file with a malformed line is refused (1)" exits 1 user remove dave
check "  naming the line and saying to fix it by hand" bash -c "'$tiltgate' user remove dave --users-file '$users' 2>&1 | grep -v Secret | grep -q 'users:[0-9]*: bob: the third field.*' && '$tiltgate' user role dave --role admin --users-file '$users' 2>&1 | grep -q 'fix or delete the line(s) above by hand'"
check "  and the file is as it was" test "$(cat "$users")" = "$before"

echo "$passes passed, $failures failed"
[ "$failures" = 0 ]

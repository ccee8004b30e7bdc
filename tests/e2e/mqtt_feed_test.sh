#!/usr/bin/env bash
# The MQTT feed end to end with Debian's broker and client: `tiltgate run` on a simulated
# Rieker bus publishes to a `mosquitto` of the test's own (a free loopback port, its own config:
# never a system broker), and `mosquitto_sub` checks: a broker that comes after the gateway, the
# topics and payloads, the retained info and status a fresh subscriber gets, recovery after the
# broker restarts (the backlog sent, its drops counted), "offline" on a clean shutdown, and the
# last will when the gateway is killed.
# A missing broker or client is a failure, never a skip: scripts/setup installs them.
set -u
tiltgate=${1:?usage: mqtt_feed_test.sh path/to/tiltgate}
source "$(dirname "$0")/support/script_lib.sh"
script_setup tiltgate-mqtt

require_broker
broker_pid=""

prefix=e2e/gw-1
# sub FILE TOPIC...: a subscriber in the background, printing "topic payload" lines to FILE.
sub() {
  local file=$1; shift
  local topics=()
  for t in "$@"; do topics+=(-t "$t"); done
  mosquitto_sub -h 127.0.0.1 -p "$broker_port" -v "${topics[@]}" >"$file" 2>>"$dir/sub.err" &
  pids+=($!)
  last_sub=$!
}
# fresh TOPIC COUNT: the first COUNT messages a new subscriber gets (the retained ones first).
fresh() {
  timeout 5 mosquitto_sub -h 127.0.0.1 -p "$broker_port" -v -t "$1" -C "$2" 2>>"$dir/sub.err"
}
# states FILE SENSOR: how many state messages FILE holds for SENSOR.
states() { grep -c "^$prefix/$2/state " "$1"; }
at_least() { [ "$(states "$1" "$2")" -ge "$3" ]; }

start_sim "$tiltgate" rieker h6:223,h4360:101 "$dir/ttyUSB0"
modbus_port=$(free_port)
http_port=$(free_port)
cat >"$dir/plant.toml" <<TOML
[server]
listen = "127.0.0.1"
port = $modbus_port
control_socket = ""

[http]
port = $http_port

[mqtt]
host = "127.0.0.1"
port = $broker_port
client_id = "e2e-gw-1"
topic_prefix = "$prefix"
interval_ms = 500
keepalive_s = 5
backlog = 5
state_dir = "$dir/state"

[[bus]]
name = "line1"
port = "$dir/ttyUSB0"
protocol = "rieker"

[[sensor]]
name = "boom"
bus = "line1"
model = "h6"
address = 223
unit_id = 1
poll_ms = 50

[[sensor]]
name = "mast"
bus = "line1"
model = "h4360"
address = 101
unit_id = 2
poll_ms = 50
TOML
gateway_pid=""
start_gateway() {
  "$tiltgate" run --config "$dir/plant.toml" 2>>"$dir/gateway.err" &
  gateway_pid=$!
  pids+=($gateway_pid)
}

# The gateway starts before its broker: it keeps trying until the broker is there.
start_gateway
sleep 1.5
start_broker
sub "$dir/live.txt" "$prefix/#"

# Every sensor's state, several times, as JSON with the documented fields and moving angles.
both_flowing() { at_least "$dir/live.txt" boom 6 && at_least "$dir/live.txt" mast 6; }
check "state messages arrive for every sensor, the broker started after the gateway" \
  wait_for 15 both_flowing
state_json_ok() {
  /usr/bin/python3 - "$dir/live.txt" "$prefix" <<'PY'
import json, sys
path, prefix = sys.argv[1], sys.argv[2]
by_sensor = {}
for line in open(path):
    topic, _, payload = line.rstrip("\n").partition(" ")
    if topic.endswith("/state"):
        by_sensor.setdefault(topic[len(prefix) + 1:-len("/state")], []).append(json.loads(payload))
assert set(by_sensor) == {"boom", "mast"}, by_sensor.keys()
for name, states in by_sensor.items():
    for s in states:
        assert {"ts", "x", "y", "online", "tilt", "age_ms", "alarms"} <= set(s), s
        assert isinstance(s["ts"], int) and s["ts"] > 1.6e12, s  # Unix ms
    read = [s for s in states if s["x"] is not None]
    assert read and all(s["online"] for s in read[-3:]), (name, states[-3:])
    assert len({s["x"] for s in read}) > 1, (name, "x never changes", read)
    if name == "mast":  # single-axis
        assert all(s["y"] is None for s in read), read
    else:
        assert all(isinstance(s["y"], float) for s in read), read
PY
}
check "state payloads are JSON with ts, x, y (null on a single axis), online, and x changes" state_json_ok

# A fresh subscriber gets the retained identity and status at once.
retained_ok() {
  fresh "$prefix/+/info" 2 >"$dir/info.txt" && fresh "$prefix/status" 1 >"$dir/status.txt" &&
    grep -q "^$prefix/boom/info .*\"model\":\"h6\".*\"serial\":\"9600223\"" "$dir/info.txt" &&
    grep -q "^$prefix/mast/info .*\"address\":101.*\"model\":\"h4360\"" "$dir/info.txt" &&
    grep -qx "$prefix/status online" "$dir/status.txt"
}
check "a fresh subscriber gets the retained info of every sensor and status online" \
  wait_for 5 retained_ok

# The broker goes away: the gateway keeps its newest 5 messages, counts the rest, and sends the
# 5 once the broker is back; a broker without persistence lost the retained messages, so the
# gateway sends them again.
stop_broker
sleep 2
modbus_alive() { (exec 3<>"/dev/tcp/127.0.0.1/$modbus_port") 2>/dev/null; }
check "the gateway still serves Modbus while the broker is away" modbus_alive
start_broker
sub "$dir/after.txt" "$prefix/#"
flowing_again() { at_least "$dir/after.txt" boom 3 && at_least "$dir/after.txt" mast 3; }
check "state messages flow again after the broker restarts" wait_for 20 flowing_again
check "the info and status are retained again on the restarted broker" wait_for 5 retained_ok
dropped_logged() { grep -q "backlog full while the broker is away: [0-9]* messages dropped" "$dir/gateway.err"; }
check "messages beyond the backlog are dropped and counted" dropped_logged
# /metrics shows the feed connected again, with what it published and dropped.
metric() {
  python3 -c "import urllib.request; print(urllib.request.urlopen('http://127.0.0.1:$http_port/metrics').read().decode())" |
    awk -v name="$1" '$1 == name { print $2 }'
}
metrics_ok() {
  [ "$(metric tiltgate_mqtt_connected)" = 1 ] && [ "$(metric tiltgate_mqtt_dropped_total)" -gt 0 ] &&
    [ "$(metric tiltgate_mqtt_published_total)" -gt 10 ] && [ "$(metric tiltgate_mqtt_reconnects_total)" -ge 1 ]
}
check "/metrics shows the feed connected, with messages published, dropped and a reconnect" \
  wait_for 5 metrics_ok
# The first connection sent a full backlog too (the gateway started before the broker).
backlog_sent() {
  [ "$(grep -c "sending 5 messages kept while the broker was away" "$dir/gateway.err")" -ge 2 ]
}
check "the 5 messages of the backlog are sent on reconnect" backlog_sent

# A clean shutdown leaves status offline (retained).
kill -TERM "$gateway_pid"
wait "$gateway_pid" 2>/dev/null
offline_retained() { fresh "$prefix/status" 1 | grep -qx "$prefix/status offline"; }
check "a clean shutdown leaves status offline" offline_retained

# Killed, it cannot say so: the broker sends its last will.
start_gateway
online_retained() { fresh "$prefix/status" 1 | grep -qx "$prefix/status online"; }
check "a restarted gateway is online again" wait_for 10 online_retained
sub "$dir/will.txt" "$prefix/status"
wait_for 5 grep -q "online" "$dir/will.txt"
kill -KILL "$gateway_pid"
wait "$gateway_pid" 2>/dev/null
will_sent() { tail -1 "$dir/will.txt" | grep -qx "$prefix/status offline"; }
check "killed, the gateway's last will sets status offline" wait_for 15 will_sent

[ "$failures" -eq 0 ] || { echo "--- gateway log"; tail -30 "$dir/gateway.err"; }
echo "$passes passed, $failures failed"
[ "$failures" -eq 0 ]

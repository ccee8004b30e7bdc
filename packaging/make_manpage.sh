#!/usr/bin/env bash
# Writes the man page tiltgate(1) from the program's own --help and that of each command (and
# each command's commands, e.g. `sim rieker`), so the page says what the binary does.
# Usage: make_manpage.sh OUT.1 VERSION COMMAND...   (COMMAND: the binary, after an emulator
#        such as qemu-aarch64-static when cross-compiling)
set -euo pipefail
out=${1:?usage: make_manpage.sh OUT.1 VERSION COMMAND...}
version=${2:?usage: make_manpage.sh OUT.1 VERSION COMMAND...}
shift 2
tiltgate=("$@")

# A CLI11 --help as roff: the headings ("Options:", "Subcommands:", ...) as bold lines, each
# "  NAME   DESCRIPTION" entry as a tagged paragraph, other lines (the description, footers) as
# text. Backslashes and hyphens escaped, and a line starting with . or ' kept from roff.
help_to_roff() {
  awk '
    function roff(text) {
      gsub(/\\/, "\\e", text)
      gsub(/-/, "\\-", text)
      if (text ~ /^[.\x27]/) text = "\\&" text
      return text
    }
    # The usage line names the binary as it was run (build/tiltgate): name it tiltgate.
    /^Usage: / {
      usage = substr($0, 8)
      sub(/^[^ ]+/, "tiltgate", usage)
      print ".PP"; print "Usage: \\fB" roff(usage) "\\fR"; next
    }
    # Examples: command lines as they are, one a line.
    /^Examples?:$/ { print ".PP"; print "\\fB" $0 "\\fR"; print ".nf"; in_example = 1; next }
    in_example && /^  / { sub(/^  /, ""); print roff($0); next }
    in_example { print ".fi"; in_example = 0 }
    /^[A-Za-z][^:]*:$/ { print ".PP"; print "\\fB" roff($0) "\\fR"; in_list = 1; next }
    /^$/ { if (!in_list) print ".PP"; in_list = 0; next }
    in_list && /^  [^ ]/ {
      line = substr($0, 3)
      split_at = match(line, /  +/)
      name = split_at ? substr(line, 1, split_at - 1) : line
      text = split_at ? substr(line, split_at + RLENGTH) : ""
      print ".TP"
      print "\\fB" roff(name) "\\fR"
      if (text != "") print roff(text)
      next
    }
    in_list && /^   / { sub(/^ +/, ""); print roff($0); next }
    in_list { print ".PP"; in_list = 0 }
    { sub(/^ +/, ""); print roff($0) }
    END { if (in_example) print ".fi" }
  '
}

# The commands under COMMAND...: its --help's "Subcommands:" entries.
subcommands_of() {
  "$@" --help | awk '/^[A-Za-z][^:]*:$/ { section = $0; next }
                     section == "Subcommands:" && /^  [^ ]/ { print $1 }'
}

# The section of each command below COMMAND..., depth first.
command_sections() {
  local name
  for name in $(subcommands_of "$@"); do
    local words=("${@:${#tiltgate[@]}+1}" "$name")
    printf '.SS "tiltgate %s"\n' "${words[*]}"
    "$@" "$name" --help | help_to_roff
    command_sections "$@" "$name"
  done
}

{
  cat <<ROFF
.TH TILTGATE 1 "" "tiltgate $version" "User Commands"
.SH NAME
tiltgate \\- Modbus/TCP gateway for RS485 inclinometers
.SH SYNOPSIS
.B tiltgate
[\\fIOPTIONS\\fR] \\fICOMMAND\\fR [\\fICOMMAND OPTIONS\\fR]
.SH DESCRIPTION
ROFF
  "${tiltgate[@]}" --help | help_to_roff
  echo ".SH COMMANDS"
  echo "Each command's own options; \\fBtiltgate COMMAND \\-\\-help\\fR prints the same."
  command_sections "${tiltgate[@]}"
  cat <<'ROFF'
.SH FILES
.TP
.I /etc/tiltgate/tiltgate.toml
the configuration the service runs (a conffile: kept on upgrades)
.TP
.I /lib/systemd/system/tiltgate.service
the systemd service: \fBsystemctl enable \-\-now tiltgate\fR, \fBsystemctl reload tiltgate\fR,
\fBjournalctl \-u tiltgate\fR
.TP
.I /usr/share/doc/tiltgate/README.md
what tiltgate is, a short tour and the list of the manual's pages
.TP
.I /usr/share/doc/tiltgate/docs/
the manual: \fIcommissioning.md\fR, \fIconfiguration.md\fR (the configuration reference:
every key, its default, range and when it applies), \fIregister\-maps.md\fR (and the
built\-in maps, \fIdefault\-maps.md\fR), \fIoperations.md\fR (install, reload, failures,
access control, wiring), \fInorthbound.md\fR (HTTP status API, metrics, MQTT),
\fIprotocols.md\fR, \fIperformance.md\fR and \fIdevelopment.md\fR
.TP
.I /usr/share/doc/tiltgate/examples/
example configurations, register maps and device profiles
.SH EXIT STATUS
0 on success, 1 when a configuration is invalid or the gateway cannot start, 2 on a usage error.
.SH SEE ALSO
.BR systemctl (1),
.BR journalctl (1)
ROFF
} >"$out"

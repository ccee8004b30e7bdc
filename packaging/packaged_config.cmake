# The packaged /etc/tiltgate/tiltgate.toml, made from examples/tiltgate.toml: the same comments
# and settings, but serving this machine only and refusing writes until edited. Each change
# must find its line: an edit of the example that moves one fails the build instead of
# shipping a configuration that serves the network.
# Usage: cmake -DINPUT=examples/tiltgate.toml -DOUTPUT=tiltgate.toml -P packaged_config.cmake
file(READ ${INPUT} text)

function(replace_once from to)
  string(FIND "${text}" "${from}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${INPUT}: no \"${from}\" to change for the packaged configuration")
  endif()
  string(REPLACE "${from}" "${to}" changed "${text}")
  set(text "${changed}" PARENT_SCOPE)
endfunction()

replace_once("# tiltgate example configuration: three Rieker inclinometers on one RS485 line.\n"
"# /etc/tiltgate/tiltgate.toml: the configuration the tiltgate service runs (tiltgate.service).
#
# As installed it serves this machine only (listen = \"127.0.0.1\") and refuses every write
# (writes = false) until you edit it: set your buses and sensors, the address to serve on,
# then `tiltgate check --config /etc/tiltgate/tiltgate.toml` and `systemctl enable --now
# tiltgate` (`systemctl reload tiltgate` after later edits). Below: the example of three
# Rieker inclinometers on one RS485 line (/usr/share/doc/tiltgate/examples/tiltgate.toml).
")
replace_once("`tiltgate check --config examples/tiltgate.toml`"
             "`tiltgate check --config /etc/tiltgate/tiltgate.toml`")
# The configuration reference, where the package installs it; the example names it by its place
# in the source tree.
replace_once("docs/configuration.md" "/usr/share/doc/tiltgate/docs/configuration.md")
replace_once("listen = \"0.0.0.0\"          # address to bind; \"127.0.0.1\" to serve this machine only\n"
"listen = \"127.0.0.1\"        # packaged: this machine only until edited; \"0.0.0.0\" to serve the PLCs
control_socket = \"/run/tiltgate/control.sock\"  # in the service's RuntimeDirectory
")
replace_once("writes = false              # false: every write is refused with exception 0x01\n"
"writes = false              # packaged: off until edited; false: every write is refused with exception 0x01
")
replace_once("# allow = [\"127.0.0.1\", \"10.0.0.0/8\"]     # who may connect; default: [server] allow\n"
"# allow = [\"127.0.0.1\", \"10.0.0.0/8\"]     # who may connect; default: [server] allow
# The web console over HTTPS: the package made a self-signed certificate for this machine
# (replace both files with the plant's own if it has one; docs/web-console.md).
# tls_cert_file = \"/etc/tiltgate/console.crt\"
# tls_key_file = \"/etc/tiltgate/console.key\"
")
file(WRITE ${OUTPUT} "${text}")

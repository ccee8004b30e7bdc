// Text from outside (a login name, a raw command's data, a client's address string, a map's
// description) made safe to put in a log line, an audit record or the journal: one function the
// whole codebase uses, so no door can write a forged line. Printable UTF-8 is kept as it is; a
// control character (C0, DEL, C1, the Unicode line and paragraph separators) is shown as an
// escape (\n, \r, \t, \x1B, \u0085, \u2028) and a backslash as \\, so what is shown reads back
// unambiguously; a byte that is not valid UTF-8 is shown as \xHH.
#pragma once

#include <string>
#include <string_view>

namespace tiltgate {

std::string visible_text(std::string_view untrusted);

}  // namespace tiltgate

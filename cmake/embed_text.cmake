# cmake -DINPUT=status/status_page.js -DOUTPUT=status_page_js.h -DVARIABLE=kStatusPageJs
#       -DSOURCE=status/status_page.js -P cmake/embed_text.cmake
# Writes a text file as a C++ raw string literal named VARIABLE, in a header made at build time
# so an edit of the file rebuilds what uses it: the status page's files (http/http_routes.cpp
# serves them) and the configuration reference (config/key_reference.cpp reads its tables).
file(READ ${INPUT} page)
string(FIND "${page}" ")tiltgate_page\"" clash)
if(NOT clash EQUAL -1)
  message(FATAL_ERROR "${INPUT} contains the raw string's end marker")
endif()
file(WRITE ${OUTPUT}.tmp
  "// Generated from ${SOURCE} by cmake/embed_text.cmake: edit that file.\n"
  "#pragma once\n#include <string_view>\nnamespace tiltgate {\n"
  "inline constexpr std::string_view ${VARIABLE} = R\"tiltgate_page(${page})tiltgate_page\";\n"
  "}  // namespace tiltgate\n")
file(COPY_FILE ${OUTPUT}.tmp ${OUTPUT} ONLY_IF_DIFFERENT)
file(REMOVE ${OUTPUT}.tmp)

# cmake -DINPUT=status_page.js -DOUTPUT=status_page_js.h -DVARIABLE=kStatusPageJs -P embed_page.cmake
# Writes one of the page's files as a C++ raw string literal named VARIABLE
# (http/http_routes.cpp serves it).
file(READ ${INPUT} page)
string(FIND "${page}" ")tiltgate_page\"" clash)
if(NOT clash EQUAL -1)
  message(FATAL_ERROR "${INPUT} contains the raw string's end marker")
endif()
get_filename_component(source ${INPUT} NAME)
file(WRITE ${OUTPUT}.tmp
  "// Generated from status/${source} by status/embed_page.cmake: edit that file.\n"
  "#pragma once\n#include <string_view>\nnamespace tiltgate {\n"
  "inline constexpr std::string_view ${VARIABLE} = R\"tiltgate_page(${page})tiltgate_page\";\n"
  "}  // namespace tiltgate\n")
file(COPY_FILE ${OUTPUT}.tmp ${OUTPUT} ONLY_IF_DIFFERENT)
file(REMOVE ${OUTPUT}.tmp)

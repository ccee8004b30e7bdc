# cmake -DINPUT=page.html -DOUTPUT=status_page.h -P embed_page.cmake
# Writes the page as a C++ raw string literal, kStatusPage (status/http_routes.cpp serves it).
file(READ ${INPUT} page)
string(FIND "${page}" ")tiltgate_page\"" clash)
if(NOT clash EQUAL -1)
  message(FATAL_ERROR "${INPUT} contains the raw string's end marker")
endif()
file(WRITE ${OUTPUT}.tmp
  "// Generated from status/status_page.html by status/embed_page.cmake: edit the page.\n"
  "#pragma once\n#include <string_view>\nnamespace tiltgate {\n"
  "inline constexpr std::string_view kStatusPage = R\"tiltgate_page(${page})tiltgate_page\";\n"
  "}  // namespace tiltgate\n")
file(COPY_FILE ${OUTPUT}.tmp ${OUTPUT} ONLY_IF_DIFFERENT)
file(REMOVE ${OUTPUT}.tmp)

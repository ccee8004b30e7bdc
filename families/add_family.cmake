# tiltgate_add_family(): a sensor family's libraries, declared the same way for every folder
# families/families.cmake names (docs/development.md, "Adding a sensor family"). Called from
# the folder's CMakeLists.txt; FOLDER is the folder's name:
#   CODEC  the pure protocol (no Asio, no I/O: unit tested and fuzzed on its own) and the
#          simulated devices             -> tiltgate_FOLDER_codec, on the driver interface
#   SIM    the simulator on a pty        -> tiltgate_FOLDER_sim, on the codec and serial/
#   DRIVER the SensorDriver and its scan probes -> tiltgate_FOLDER, on the codec
#   FAMILY the descriptors (family.cpp), default maps, raw requests
#          -> tiltgate_FOLDER_family, linking all the others (PUBLIC) and mapping/, so that
#             the binary and the tests get the whole family from families/
#   CODEC_LINKS, FAMILY_LINKS  more libraries the codec or the family library needs
function(tiltgate_add_family)
  cmake_parse_arguments(PARSE_ARGV 0 arg "" "" "CODEC;SIM;DRIVER;FAMILY;CODEC_LINKS;FAMILY_LINKS")
  get_filename_component(folder ${CMAKE_CURRENT_SOURCE_DIR} NAME)
  set(prefix tiltgate_${folder})

  add_library(${prefix}_codec STATIC ${arg_CODEC})
  target_link_libraries(${prefix}_codec PUBLIC tiltgate_driver ${arg_CODEC_LINKS})

  add_library(${prefix}_sim STATIC ${arg_SIM})
  target_link_libraries(${prefix}_sim PUBLIC ${prefix}_codec tiltgate_serial Boost::headers)

  add_library(${prefix} STATIC ${arg_DRIVER})
  target_link_libraries(${prefix} PUBLIC ${prefix}_codec tiltgate_driver Boost::headers
                        spdlog::spdlog fmt::fmt)

  add_library(${prefix}_family STATIC ${arg_FAMILY})
  target_link_libraries(${prefix}_family PUBLIC ${prefix} ${prefix}_sim tiltgate_mapping
                        ${arg_FAMILY_LINKS})

  foreach(library ${prefix}_codec ${prefix}_sim ${prefix} ${prefix}_family)
    target_include_directories(${library} PUBLIC ${PROJECT_SOURCE_DIR})
  endforeach()
endfunction()

# tiltgate_modbus: the Modbus TCP server side. Requests are framed and checked by our own pure
# parser (modbus_request) and answered by our own pure formatter (modbus_reply_format, tested
# byte for byte against libmodbus's modbus_reply; 43 / 14 in device_identification); Asio does
# all socket I/O (modbus_tcp_server).
add_library(tiltgate_modbus STATIC
  ${CMAKE_CURRENT_LIST_DIR}/modbus_request.cpp
  ${CMAKE_CURRENT_LIST_DIR}/connection_admission.cpp
  ${CMAKE_CURRENT_LIST_DIR}/device_identification.cpp
  ${CMAKE_CURRENT_LIST_DIR}/modbus_reply_format.cpp
  ${CMAKE_CURRENT_LIST_DIR}/log_throttle.cpp
  ${CMAKE_CURRENT_LIST_DIR}/modbus_request_counts.cpp
  ${CMAKE_CURRENT_LIST_DIR}/modbus_stream.cpp
  ${CMAKE_CURRENT_LIST_DIR}/modbus_tcp_server.cpp ${CMAKE_CURRENT_LIST_DIR}/modbus_tcp_listeners.cpp
  ${CMAKE_CURRENT_LIST_DIR}/modbus_tcp_server_log.cpp ${CMAKE_CURRENT_LIST_DIR}/tcp_worker_pool.cpp
  ${CMAKE_CURRENT_LIST_DIR}/tcp_listen.cpp ${CMAKE_CURRENT_LIST_DIR}/inherited_sockets.cpp)
target_include_directories(tiltgate_modbus PUBLIC ${PROJECT_SOURCE_DIR})
target_link_libraries(tiltgate_modbus PUBLIC tiltgate_address_allow_list Boost::headers spdlog::spdlog fmt::fmt
                      OpenSSL::SSL OpenSSL::Crypto Threads::Threads PRIVATE PkgConfig::SYSTEMD)

// A libmodbus TCP client for end-to-end tests: the same library PLC-side tools use.
#pragma once

#include <cerrno>
#include <cstdint>
#include <modbus/modbus.h>
#include <stdexcept>
#include <string>
#include <vector>

namespace tiltgate::test {

class ModbusClient {
 public:
  ModbusClient(std::uint16_t port, int unit) : ctx_(modbus_new_tcp("127.0.0.1", port)) {
    if (ctx_ == nullptr) throw std::runtime_error("modbus_new_tcp failed");
    modbus_set_slave(ctx_, unit);
    modbus_set_response_timeout(ctx_, 5, 0);  // generous: writes wait for the sensor
    if (modbus_connect(ctx_) != 0) {
      modbus_free(ctx_);
      throw std::runtime_error(std::string("modbus_connect: ") + modbus_strerror(errno));
    }
  }
  ~ModbusClient() {
    modbus_close(ctx_);
    modbus_free(ctx_);
  }
  ModbusClient(const ModbusClient&) = delete;
  ModbusClient& operator=(const ModbusClient&) = delete;

  void unit(int id) { modbus_set_slave(ctx_, id); }

  // The registers, or empty with error() set to errno (MODBUS_ENOBASE + exception code).
  std::vector<std::uint16_t> input(int address, int count) {
    std::vector<std::uint16_t> words(count);
    return done(modbus_read_input_registers(ctx_, address, count, words.data()), words);
  }
  std::vector<std::uint16_t> holding(int address, int count) {
    std::vector<std::uint16_t> words(count);
    return done(modbus_read_registers(ctx_, address, count, words.data()), words);
  }
  std::vector<std::uint8_t> discrete(int address, int count) {
    std::vector<std::uint8_t> bits(count);
    return done(modbus_read_input_bits(ctx_, address, count, bits.data()), bits);
  }
  std::vector<std::uint8_t> coils(int address, int count) {
    std::vector<std::uint8_t> bits(count);
    return done(modbus_read_bits(ctx_, address, count, bits.data()), bits);
  }
  bool write(int address, std::uint16_t value) {
    return check(modbus_write_register(ctx_, address, value));
  }
  bool write(int address, const std::vector<std::uint16_t>& values) {
    return check(modbus_write_registers(ctx_, address, int(values.size()), values.data()));
  }
  bool write_coil(int address, bool on) { return check(modbus_write_bit(ctx_, address, on)); }

  int error() const { return error_; }  // errno of the last failed call
  int exception() const { return error_ > MODBUS_ENOBASE ? error_ - MODBUS_ENOBASE : 0; }
  modbus_t* raw() { return ctx_; }

 private:
  template <class V>
  V done(int rc, V& values) {
    if (rc < 0) {
      error_ = errno;
      return {};
    }
    error_ = 0;
    return values;
  }
  bool check(int rc) {
    error_ = rc < 0 ? errno : 0;
    return rc >= 0;
  }

  modbus_t* ctx_;
  int error_ = 0;
};

}  // namespace tiltgate::test

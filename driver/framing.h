// How bytes go on the wire: what a sensor family's protocol tells the serial transport.
#pragma once

namespace tiltgate {

enum class Framing {
  eight_none_one,  // 8 data bits, no parity, 1 stop bit
  eight_even_one,  // 8 data bits, even parity, 1 stop bit
  eight_odd_one,   // 8 data bits, odd parity, 1 stop bit
  eight_none_two,  // 8 data bits, no parity, 2 stop bits (the Modbus serial line without parity)
  nine_bit,        // 9-bit addressing: address bytes with mark parity, data bytes with space
};

// The stop bits a framing sends: 2 for 8N2, 1 for the others.
constexpr int stop_bits_of(Framing framing) { return framing == Framing::eight_none_two ? 2 : 1; }

}  // namespace tiltgate

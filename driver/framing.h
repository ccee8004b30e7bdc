// How bytes go on the wire: what a sensor family's protocol tells the serial transport.
#pragma once

namespace tiltgate {

enum class Framing {
  eight_none_one,  // 8 data bits, no parity, 1 stop bit
  eight_even_one,  // 8 data bits, even parity, 1 stop bit
  nine_bit,        // 9-bit addressing: address bytes with mark parity, data bytes with space
};

}  // namespace tiltgate

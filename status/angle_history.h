// The recent angles of one sensor, for the status page's graph and its CSV download (docs/northbound.md,
// "HTTP status API and metrics"): a fixed-size ring of samples, oldest overwritten first. The
// gateway samples every sensor into its ring on a timer; the memory is fixed when the ring is
// made (16 bytes a sample, 4 more for a sensor that reports a temperature), so a gateway's
// history never grows.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

namespace tiltgate {

struct AngleSample {
  std::int64_t unix_ms = 0;  // wall-clock time the sample was taken
  // Degrees as the register map serves them; none while the sensor has no fresh reading (the
  // graph shows a gap). float: 7 significant digits are ample for an inclinometer's degrees and
  // halve the ring.
  std::optional<float> x;
  std::optional<float> y;
  std::optional<float> temperature = std::nullopt;  // degC, kept by a ring made with temperatures only
};

class AngleRing {
 public:
  // `temperatures`: the ring keeps each sample's temperature too (a sensor that reports one).
  explicit AngleRing(std::size_t capacity, bool temperatures = false);

  // Adds a sample; once full, the oldest is dropped. A ring of capacity 0 keeps nothing.
  void push(const AngleSample& sample);
  // The samples kept, oldest first.
  std::vector<AngleSample> samples() const;
  std::size_t size() const { return size_; }
  std::size_t capacity() const { return slots_.size(); }
  bool keeps_temperatures() const { return !temperatures_.empty(); }

 private:
  // NaN marks a missing angle, so a slot is 16 bytes rather than an optional's 24.
  struct Slot {
    std::int64_t unix_ms = 0;
    float x = 0;
    float y = 0;
  };
  std::vector<Slot> slots_;
  std::vector<float> temperatures_;  // beside slots_, or empty: most sensors have none
  std::size_t next_ = 0;  // the slot the next sample goes into
  std::size_t size_ = 0;
};

}  // namespace tiltgate

#include "monitoring/baseline_book.h"

#include <fstream>
#include <sstream>

#include "status/json_values.h"
#include "store/whole_file_write.h"

namespace tiltgate::monitoring {

namespace {

std::string book_json(const std::map<std::string, StoredBaseline>& stored) {
  Json book = Json::object();
  for (const auto& [sensor, entry] : stored)
    book[sensor] = {{"x", json_number(entry.baseline.x)}, {"y", json_number(entry.baseline.y)},
                    {"unix_ms", entry.unix_ms}, {"by", entry.by}};
  return book.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

}  // namespace

BaselineBook::BaselineBook(std::filesystem::path dir) : dir_(std::move(dir)) {
  if (dir_.empty()) return;  // no state directory (the demo): kept in memory only
  std::ifstream in(file());
  if (!in) return;  // no baseline set yet
  std::stringstream text;
  text << in.rdbuf();
  const nlohmann::json book = nlohmann::json::parse(text.str(), nullptr, false);
  if (!book.is_object()) {
    load_error_ = file().string() + " is not a JSON object: the configuration's baselines apply";
    return;
  }
  for (const auto& [sensor, entry] : book.items()) {
    const auto x = entry.find("x");
    const auto y = entry.find("y");
    if (!entry.is_object() || x == entry.end() || !x->is_number() || y == entry.end() ||
        !y->is_number()) {
      load_error_ = file().string() + ": the baseline of \"" + sensor + "\" is not {x, y}";
      continue;
    }
    StoredBaseline stored{{x->get<double>(), y->get<double>()}, 0, {}};
    if (const auto ms = entry.find("unix_ms"); ms != entry.end() && ms->is_number_integer())
      stored.unix_ms = ms->get<std::int64_t>();
    if (const auto by = entry.find("by"); by != entry.end() && by->is_string())
      stored.by = by->get<std::string>();
    stored_[sensor] = stored;
  }
}

std::optional<StoredBaseline> BaselineBook::find(const std::string& sensor) const {
  std::lock_guard lock(mutex_);
  const auto it = stored_.find(sensor);
  if (it == stored_.end()) return std::nullopt;
  return it->second;
}

Baseline BaselineBook::effective(const SensorConfig& sensor) const {
  if (auto stored = find(sensor.name)) return stored->baseline;
  return sensor.baseline.value_or(Baseline{});
}

Expected<Done, std::string> BaselineBook::set(const std::string& sensor,
                                              std::optional<StoredBaseline> value) {
  std::lock_guard lock(mutex_);
  std::map<std::string, StoredBaseline> next = stored_;
  if (value) next[sensor] = *value;
  else next.erase(sensor);
  if (dir_.empty()) {
    stored_ = std::move(next);
    return Done{};
  }
  std::error_code ignored;
  std::filesystem::create_directories(dir_, ignored);
  auto written = write_whole_file(file().string(), book_json(next), 0640, FileMode::given);
  if (!written) return Unexpected(written.error());
  stored_ = std::move(next);
  load_error_.reset();
  return Done{};
}

}  // namespace tiltgate::monitoring

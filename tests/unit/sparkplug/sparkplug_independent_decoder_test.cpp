// Our payloads decoded by another decoder: protoc's Python output of sparkplug/sparkplug_b.proto
// with Debian's python3-protobuf (tests/unit/sparkplug/sparkplug_decode.py), which shares no code with
// protobuf-c. What it prints is compared with what the session meant to send.
#include <doctest/doctest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "unit/sparkplug/sparkplug_session_support.h"

using namespace tiltgate::sparkplug;
using namespace tiltgate::sparkplug::test;

namespace {

// A scratch directory with sparkplug_b_pb2.py in it, removed at the end.
class PythonDecoder {
 public:
  PythonDecoder() {
    std::string pattern = (std::filesystem::temp_directory_path() / "tiltgate-spb-XXXXXX").string();
    REQUIRE(::mkdtemp(pattern.data()) != nullptr);
    dir_ = pattern;
    const std::string source = TILTGATE_SOURCE_DIR;
    REQUIRE(run("/usr/bin/protoc --proto_path=" + source + "/sparkplug --python_out=" +
                dir_.string() + " " + source + "/sparkplug/sparkplug_b.proto") == "");
  }
  ~PythonDecoder() { std::filesystem::remove_all(dir_); }

  // What sparkplug_decode.py prints for these bytes.
  std::string decode(const std::vector<std::uint8_t>& bytes) {
    const auto file = dir_ / "payload.bin";
    std::ofstream(file, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()),
               static_cast<std::streamsize>(bytes.size()));
    return run("/usr/bin/python3 " + std::string(TILTGATE_SOURCE_DIR) +
               "/tests/unit/sparkplug/sparkplug_decode.py " + dir_.string() + " " + file.string());
  }

 private:
  std::string run(const std::string& command) {
    const auto out = dir_ / "out.txt";
    const int status = std::system((command + " >" + out.string() + " 2>&1").c_str());
    std::ifstream in(out);
    std::stringstream text;
    text << in.rdbuf();
    INFO(command);
    INFO(text.str());
    REQUIRE(status == 0);
    return text.str();
  }

  std::filesystem::path dir_;
};

// `text` with @T for the tests' start time, @R for `read` and @P for `published` ms after it.
std::string expect(std::string text, std::int64_t read = 0, std::int64_t published = 0) {
  const std::pair<std::string, std::int64_t> times[] = {{"@T", 0}, {"@R", read}, {"@P", published}};
  for (const auto& [mark, ms] : times) {
    for (auto at = text.find(mark); at != std::string::npos; at = text.find(mark)) {
      text.replace(at, mark.size(), std::to_string(kUnixStart + ms));
    }
  }
  return text;
}

}  // namespace

TEST_CASE("tck-id-message-flow-edge-node-birth-publish-nbirth-payload: NBIRTH decodes with protoc's Python decoder") {
  PythonDecoder python;
  auto session = make_session(options(), 4);
  (void)session.begin_connect(at(0));
  const Publish nbirth = publishes(session.on_connected(at(0))).at(0);
  CHECK(python.decode(nbirth.bytes()) == expect(R"(timestamp @T
seq 0
metric name='bdSeq' alias=- timestamp=@T datatype=4 historical=- long_value=5
metric name='Node Control/Rebirth' alias=- timestamp=@T datatype=11 historical=- boolean_value=False
metric name='Properties/version' alias=1 timestamp=@T datatype=12 historical=- string_value='0.1.0'
metric name='Properties/buses' alias=2 timestamp=@T datatype=7 historical=- long_value=2
metric name='Clock/synchronised' alias=3 timestamp=@T datatype=11 historical=- boolean_value=False
metric name='Clock/error_ms' alias=4 timestamp=@T datatype=10 historical=- null
)"));
}

TEST_CASE("tck-id-topics-ndata-payload: the node's clock in an NBIRTH and an NDATA decodes with protoc's Python decoder") {
  PythonDecoder python;
  auto session = make_session(options(), 4);
  (void)session.update_node(NodeSample{true, 12.5}, at(0));
  (void)session.begin_connect(at(0));
  const Publish nbirth = publishes(session.on_connected(at(0))).at(0);
  CHECK(python.decode(nbirth.bytes()).ends_with(expect(R"(
metric name='Clock/synchronised' alias=3 timestamp=@T datatype=11 historical=- boolean_value=True
metric name='Clock/error_ms' alias=4 timestamp=@T datatype=10 historical=- double_value=12.5
)")));
  const Publish ndata = publishes(session.update_node(NodeSample{false, std::nullopt}, at(300))).at(0);
  CHECK(python.decode(ndata.bytes()) == expect(R"(timestamp @P
seq 1
metric name=- alias=3 timestamp=@P datatype=11 historical=- boolean_value=False
metric name=- alias=4 timestamp=@P datatype=10 historical=- null
)", 0, 300));
}

TEST_CASE("tck-id-message-flow-device-birth-publish-dbirth-payload: DBIRTH decodes with protoc's Python decoder") {
  PythonDecoder python;
  LiveSession live;
  const Publish dbirth = publishes(live.connected).at(2);  // mast: single-axis, no serial yet
  CHECK(python.decode(dbirth.bytes()) == expect(R"(timestamp @T
seq 2
metric name='angle_x' alias=513 timestamp=@T datatype=10 historical=- double_value=3.0 properties=engUnit:12:string_value='deg'
metric name='tilt' alias=515 timestamp=@T datatype=10 historical=- double_value=3.0 properties=engUnit:12:string_value='deg'
metric name='relative_x' alias=525 timestamp=@T datatype=10 historical=- null properties=engUnit:12:string_value='deg'
metric name='status' alias=516 timestamp=@T datatype=6 historical=- int_value=0
metric name='online' alias=517 timestamp=@T datatype=11 historical=- boolean_value=True
metric name='stale' alias=518 timestamp=@T datatype=11 historical=- boolean_value=False
metric name='wrong_device' alias=524 timestamp=@T datatype=11 historical=- boolean_value=False
metric name='alarms' alias=519 timestamp=@T datatype=6 historical=- int_value=0
metric name='alarms_danger' alias=529 timestamp=@T datatype=6 historical=- int_value=0
metric name='alarms_latched' alias=530 timestamp=@T datatype=6 historical=- int_value=0
metric name='age_ms' alias=520 timestamp=@T datatype=4 historical=- long_value=70
metric name='Properties/model' alias=521 timestamp=@T datatype=12 historical=- string_value='h4360'
metric name='Properties/serial' alias=522 timestamp=@T datatype=12 historical=- null
metric name='Properties/firmware' alias=523 timestamp=@T datatype=12 historical=- null
)"));
}

TEST_CASE("tck-id-payloads-alias-data-cmd-requirement: DDATA and a replayed historical DDATA decode with protoc's Python decoder") {
  PythonDecoder python;
  LiveSession live;
  const DeviceSample samples[] = {boom(-1.25, 0.5, 180)};
  const Publish ddata = publishes(live.session.update(samples, at(200))).at(0);
  CHECK(python.decode(ddata.bytes()) == expect(R"(timestamp @P
seq 3
metric name=- alias=257 timestamp=@R datatype=10 historical=- double_value=-1.25
metric name=- alias=258 timestamp=@R datatype=10 historical=- double_value=0.5
metric name=- alias=259 timestamp=@R datatype=10 historical=- double_value=1.25
)", 180, 200));

  live.session.on_connection_lost();
  auto s = boom(2.0, 0.5, 1000);
  s.alarms = 3;
  const DeviceSample outage[] = {s};
  const Keep kept = all_of<Keep>(live.session.update(outage, at(1000))).at(0);
  (void)live.session.begin_connect(at(2000));
  (void)live.session.on_connected(at(2000));
  const auto replayed = live.session.replay(kept.topic, encode(kept.payload), at(2100));
  REQUIRE(replayed.has_value());
  CHECK(python.decode(replayed->bytes()) == expect(R"(timestamp @P
seq 3
metric name=- alias=257 timestamp=@R datatype=10 historical=True double_value=2.0
metric name=- alias=259 timestamp=@R datatype=10 historical=True double_value=2.0
metric name=- alias=263 timestamp=@R datatype=6 historical=True int_value=3
)", 1000, 2100));
}

TEST_CASE("signed values travel as the specification's two's complement: Python sees the raw uint32 and uint64") {
  PythonDecoder python;
  const Payload payload{7,
                        std::nullopt,
                        {Metric{"i8", {}, {}, DataType::Int8, false, std::int32_t{-5}, {}},
                         Metric{"i64", {}, {}, DataType::Int64, false, std::int64_t{-2}, {}},
                         Metric{"f", {}, {}, DataType::Float, false, 0.5f, {}}}};
  CHECK(python.decode(encode(payload)) == R"(timestamp 7
seq -
metric name='i8' alias=- timestamp=- datatype=1 historical=- int_value=4294967291
metric name='i64' alias=- timestamp=- datatype=4 historical=- long_value=18446744073709551614
metric name='f' alias=- timestamp=- datatype=9 historical=- float_value=0.5
)");
}

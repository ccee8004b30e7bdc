// The baselines set since the configuration (monitoring/baseline_book.h): kept in a file across
// a reopen, winning over the configuration's until cleared, a damaged file ignored with a reason.
#include <doctest/doctest.h>

#include <fstream>

#include "monitoring/baseline_book.h"
#include "unit/support/scratch_dir.h"

using namespace tiltgate;
using namespace tiltgate::monitoring;

TEST_CASE("baseline book: a stored baseline wins, survives a reopen, and clears") {
  test::ScratchDir scratch("tiltgate-baselines");
  const std::filesystem::path dir = scratch.path("state");
  SensorConfig mast;
  mast.name = "mast";
  mast.baseline = Baseline{1.0, 2.0};
  SensorConfig pier;
  pier.name = "pier";
  {
    BaselineBook book(dir);
    CHECK(book.effective(mast) == Baseline{1.0, 2.0});  // the configuration's
    CHECK(book.effective(pier) == Baseline{0.0, 0.0});
    REQUIRE(book.set("mast", StoredBaseline{{0.5, -0.25}, 1796638502250, "console admin"}));
  }
  BaselineBook reopened(dir);
  CHECK_FALSE(reopened.load_error().has_value());
  CHECK(reopened.effective(mast) == Baseline{0.5, -0.25});
  REQUIRE(reopened.find("mast").has_value());
  CHECK(reopened.find("mast")->by == "console admin");
  CHECK(reopened.find("mast")->unix_ms == 1796638502250);
  REQUIRE(reopened.set("mast", std::nullopt));
  CHECK(BaselineBook(dir).effective(mast) == Baseline{1.0, 2.0});
}

TEST_CASE("baseline book: a damaged file leaves the configuration's in force, with a reason") {
  test::ScratchDir scratch("tiltgate-baselines-bad");
  const std::filesystem::path dir = scratch.path("state");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "baselines.json") << "{not json";
  BaselineBook book(dir);
  REQUIRE(book.load_error().has_value());
  SensorConfig mast;
  mast.name = "mast";
  CHECK(book.effective(mast) == Baseline{});
  // The next change writes a good file.
  REQUIRE(book.set("mast", StoredBaseline{{1.0, 0.0}, 1, "tiltgate baseline"}));
  CHECK_FALSE(BaselineBook(dir).load_error().has_value());
}

TEST_CASE("baseline book: without a state directory it keeps baselines in memory") {
  BaselineBook book{std::filesystem::path{}};
  SensorConfig mast;
  mast.name = "mast";
  REQUIRE(book.set("mast", StoredBaseline{{3.0, 0.0}, 1, "demo"}));
  CHECK(book.effective(mast) == Baseline{3.0, 0.0});
  CHECK_FALSE(std::filesystem::exists("baselines.json"));
}

// CsvWriter: numbers in their shortest round-trip form; a text holding a comma, a quote or a
// line break is quoted with its quotes doubled (RFC 4180, section 2, rules
// 6-7), so that a list-valued sweep column stays one column.
#include <doctest/doctest.h>

#include "io/csv_writer.hpp"
#include "support/scenes.hpp"

using namespace fibrodem;

TEST_CASE("csv: texts with commas or quotes are quoted, others written as they are") {
  const auto file = testing::scratch_dir("csv_writer") / "t.csv";
  {
    CsvWriter csv(file, {"a", "b", "c", "d"});
    csv.cell(std::string(R"(["electrophysiology","coupling"])")).cell(std::string("plain")).cell(0.1).cell(7LL);
    csv.end_row();
    csv.flush();
  }
  CHECK(testing::read_file(file) ==
        "a,b,c,d\n"
        R"("[""electrophysiology"",""coupling""]",plain,0.1,7)"
        "\n");
}

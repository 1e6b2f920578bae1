// The one CSV reader (include/uascma/common/csv.h) on the cases of RFC 4180 §2 (rules 1-7, with its own examples),
// and the readers built on it (drag tables, OCV tables) reading the same table written plainly, quoted and with
// CRLF line breaks: the same numbers each way.
#include "uascma/common/csv.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "uascma/common/error.h"
#include "uascma/models/drag.h"
#include "uascma/models/ocv_table.h"

namespace uascma {
namespace {

using Fields = std::vector<std::string>;

std::vector<Fields> FieldsOf(const std::string& text, const CsvOptions& options = {}) {
  std::vector<Fields> out;
  for (const CsvRecord& record : SplitCsv(text, "t.csv", options)) out.push_back(record.fields);
  return out;
}

// Rule 1: records on separate lines, delimited by a line break (CRLF).
TEST(CsvRfc4180Test, Rule1RecordsEndAtCrlf) {
  EXPECT_EQ(FieldsOf("aaa,bbb,ccc\r\nzzz,yyy,xxx\r\n"), (std::vector<Fields>{{"aaa", "bbb", "ccc"}, {"zzz", "yyy", "xxx"}}));
  EXPECT_EQ(FieldsOf("aaa,bbb,ccc\nzzz,yyy,xxx\n"), FieldsOf("aaa,bbb,ccc\r\nzzz,yyy,xxx\r\n"));  // LF read alike
}

// Rule 2: the last record may or may not end with a line break.
TEST(CsvRfc4180Test, Rule2TheLastLineBreakIsOptional) {
  EXPECT_EQ(FieldsOf("aaa,bbb,ccc\r\nzzz,yyy,xxx"), FieldsOf("aaa,bbb,ccc\r\nzzz,yyy,xxx\r\n"));
}

// Rule 3: an optional header line of the same format (a record like any other).
TEST(CsvRfc4180Test, Rule3AHeaderIsARecord) {
  const std::vector<CsvRecord> records = SplitCsv("field_name,field_name\r\naaa,bbb\r\n", "t.csv");
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[0].line, 1);
  EXPECT_EQ(records[1].line, 2);
}

// Rule 4: fields separated by commas; the last field is not followed by one. (The RFC keeps spaces in a field; we
// drop them around an unquoted field, csv.h, and keep them inside quotes.)
TEST(CsvRfc4180Test, Rule4CommasSeparateFieldsEmptyOnesIncluded) {
  EXPECT_EQ(FieldsOf("aaa,,ccc,\r\n"), (std::vector<Fields>{{"aaa", "", "ccc", ""}}));
  EXPECT_EQ(FieldsOf(" a a , \" b \" \r\n"), (std::vector<Fields>{{"a a", " b "}}));
}

// Rule 5: a field may be enclosed in double quotes.
TEST(CsvRfc4180Test, Rule5QuotedFieldsAreUnquoted) {
  EXPECT_EQ(FieldsOf("\"aaa\",\"bbb\",\"ccc\"\r\nzzz,yyy,xxx"),
            (std::vector<Fields>{{"aaa", "bbb", "ccc"}, {"zzz", "yyy", "xxx"}}));
}

// Rule 6: a quoted field may hold line breaks, quotes and commas; the record's line is where it starts.
TEST(CsvRfc4180Test, Rule6QuotedFieldsHoldLineBreaksAndCommas) {
  const std::vector<CsvRecord> records = SplitCsv("\"aaa\",\"b\r\nbb\",\"c,cc\"\r\nzzz,yyy,xxx\r\n", "t.csv");
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[0].fields, (Fields{"aaa", "b\r\nbb", "c,cc"}));
  EXPECT_EQ(records[1].line, 3);
}

// Rule 7: a quote inside a quoted field is written twice.
TEST(CsvRfc4180Test, Rule7DoubledQuotesAreOneQuote) {
  EXPECT_EQ(FieldsOf("\"aaa\",\"b\"\"bb\",\"ccc\""), (std::vector<Fields>{{"aaa", "b\"bb", "ccc"}}));
}

TEST(CsvRfc4180Test, MalformedQuotingIsAnInputErrorNamingTheLine) {
  for (const std::string& text : {std::string("a,b\r\n\"open,c\r\n"), std::string("a,b\r\nx\"y,c\r\n"),
                                  std::string("a,b\r\n\"q\"z,c\r\n")}) {
    try {
      SplitCsv(text, "t.csv");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find("t.csv: line 2"), std::string::npos) << error.what();
    }
  }
}

TEST(CsvRfc4180Test, CommentLinesOnlyWhenAsked) {
  const std::string text = "# a \"quoted\" note, with a comma\r\na,b\r\n  # another\nc,d\n";
  EXPECT_EQ(FieldsOf(text, CsvOptions{.comment_lines = true}), (std::vector<Fields>{{"a", "b"}, {"c", "d"}}));
  EXPECT_THROW(FieldsOf(text), InputError);  // without: the quote inside the first field is malformed
  EXPECT_EQ(FieldsOf("\"#x\",y\n", CsvOptions{.comment_lines = true}), (std::vector<Fields>{{"#x", "y"}}));
}

// --- the readers built on it -------------------------------------------------------------------------------------
// The same small table as every reader sees it: plain with LF, quoted with CRLF.
std::string Plainly(const std::vector<Fields>& rows) {
  std::string text;
  for (const Fields& row : rows) {
    for (std::size_t i = 0; i < row.size(); ++i) text += (i ? "," : "") + row[i];
    text += "\n";
  }
  return text;
}
std::string QuotedCrlf(const std::vector<Fields>& rows) {
  std::string text;
  for (const Fields& row : rows) {
    for (std::size_t i = 0; i < row.size(); ++i) text += (i ? ",\"" : "\"") + row[i] + "\"";
    text += "\r\n";
  }
  return text;
}

TEST(CsvRfc4180Test, OcvTablesReadQuotedAndCrlfAsPlain) {
  const std::vector<Fields> rows = {{"soc_percent", "ocv_v"}, {"0", "3.27"}, {"50", "3.84"}, {"100", "4.2"}};
  const models::OcvTable plain = models::ParseOcvTableCsv(Plainly(rows), "ocv.csv");
  const models::OcvTable quoted = models::ParseOcvTableCsv(QuotedCrlf(rows), "ocv.csv");
  EXPECT_EQ(plain.soc_fraction(), quoted.soc_fraction());
  EXPECT_EQ(plain.voltage_v(), quoted.voltage_v());
  EXPECT_EQ(plain.point_count(), 3);
}

TEST(CsvRfc4180Test, DragTablesReadQuotedAndCrlfAsPlain) {
  const std::vector<Fields> rows = {
      {"airspeed_mps", "-10", "0", "10"}, {"0", "0", "0", "0"}, {"5", "0.8", "0.7", "0.8"}, {"10", "3.1", "3", "3.2"}};
  const auto dir = std::filesystem::temp_directory_path() / "uascma_csv_rfc4180_test";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "plain.csv", std::ios::binary) << Plainly(rows);
  std::ofstream(dir / "quoted.csv", std::ios::binary) << QuotedCrlf(rows);
  const models::DragTable plain = models::DragTable::FromCsv(dir / "plain.csv");
  const models::DragTable quoted = models::DragTable::FromCsv(dir / "quoted.csv");
  std::filesystem::remove_all(dir);
  for (double airspeed = 0.0; airspeed <= 10.0; airspeed += 0.5) {
    for (double pitch = -0.17; pitch <= 0.17; pitch += 0.017) {
      EXPECT_EQ(plain.DragSlope(airspeed, pitch), quoted.DragSlope(airspeed, pitch)) << airspeed << " " << pitch;
    }
  }
}

}  // namespace
}  // namespace uascma

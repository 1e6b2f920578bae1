// RFC 4180 splitting (include/uascma/common/csv.h) and the landing-site reader built on it.
#include "uascma/common/csv.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "uascma/common/error.h"
#include "uascma/planning/map_import.h"
#include "uascma/planning/map_sites_csv.h"

namespace uascma::planning {
namespace {

using Fields = std::vector<std::string>;

std::string InputErrorOf(const std::string& text) {
  try {
    SplitCsv(text, "t.csv");
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(CsvTest, PlainFieldsAreTrimmedAndBlankLinesSkipped) {
  const auto records = SplitCsv("a, b ,c\r\n\r\n  \n1,,3\n", "t.csv");
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[0].fields, (Fields{"a", "b", "c"}));
  EXPECT_EQ(records[0].line, 1);
  EXPECT_EQ(records[1].fields, (Fields{"1", "", "3"}));
  EXPECT_EQ(records[1].line, 4);
  // No line break after the last record, and a lone carriage return at the end.
  EXPECT_EQ(SplitCsv("x,y", "t.csv").front().fields, (Fields{"x", "y"}));
  EXPECT_EQ(SplitCsv("x,y\r", "t.csv").front().fields, (Fields{"x", "y"}));
}

TEST(CsvTest, QuotedFieldsHoldCommasDoubledQuotesAndLineBreaks) {
  const auto records = SplitCsv(
      "id,name,note\n"
      "1,\"Roof, north\",\"say \"\"hi\"\"\"\n"
      "2, \"two\nlines\" ,\"\"\n"
      "3,\" kept \",end\n",
      "t.csv");
  ASSERT_EQ(records.size(), 4u);
  EXPECT_EQ(records[1].fields, (Fields{"1", "Roof, north", "say \"hi\""}));
  EXPECT_EQ(records[2].fields, (Fields{"2", "two\nlines", ""}));
  EXPECT_EQ(records[2].line, 3);
  // The record after a quoted line break starts on the line after it.
  EXPECT_EQ(records[3].line, 5);
  EXPECT_EQ(records[3].fields, (Fields{"3", " kept ", "end"}));  // quoted spaces stay
}

TEST(CsvTest, MalformedQuotingNamesTheLine) {
  const std::string unclosed = InputErrorOf("a,b\n1,\"open\n2,3\n");
  EXPECT_NE(unclosed.find("t.csv: line 2"), std::string::npos) << unclosed;
  EXPECT_NE(unclosed.find("closing double quote"), std::string::npos) << unclosed;
  const std::string after = InputErrorOf("a,b\n\"x\"y,2\n");
  EXPECT_NE(after.find("line 2"), std::string::npos) << after;
  const std::string inside = InputErrorOf("a,b\nx\"y,2\n");
  EXPECT_NE(inside.find("line 2"), std::string::npos) << inside;
}

TEST(CsvTest, LandingSiteReaderReadsQuotedIdsAndNumbers) {
  GeoMapData data;
  ParseLandingSitesCsv(
      "\"osm_id\",\"lat\",lon,alt,risk,radius\n"
      "\"way/1, roof\",\"40.74\",-73.99,12.5,0.25,3\n"
      "\"say \"\"B\"\"\",40.75,-73.98,0,0.5,\"4\"\n",
      "sites.csv", {}, &data);
  ASSERT_EQ(data.sites.size(), 2u);
  EXPECT_EQ(data.sites[0].id, "way/1, roof");
  EXPECT_NEAR(data.sites[0].position.lat_deg, 40.74, 1e-12);
  EXPECT_NEAR(data.sites[0].altitude, 12.5, 1e-12);
  EXPECT_EQ(data.sites[1].id, "say \"B\"");
  EXPECT_NEAR(data.sites[1].radius, 4.0, 1e-12);
  // A row with a quoted comma still has the right number of fields; an error names the record's line.
  GeoMapData bad;
  try {
    ParseLandingSitesCsv("osm_id,lat,lon,alt,risk,radius\n\"a\nb\",40,-73,0,2,1\n", "sites.csv", {}, &bad);
    ADD_FAILURE() << "risk 2 accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("line 2"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace uascma::planning

// The JSON edge of the grid routes (api/grid_json.h): request bodies to typed requests with the documented errors,
// typed results to the documents clients see.
#include "api/grid_json.h"

#include <gtest/gtest.h>

#include "schema/error.h"

namespace anchordb::api::grid_json {
namespace grid_json_test {

using services::LayerSpec;

Error ParseError(const std::string& body, const std::string& layer = "new") {
  try {
    ParseLayerSpec(Json::parse(body), layer);
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "no error for " << body;
  return Error(ErrorCode::kInternal, "none");
}

TEST(GridJsonTest, EachKindParsesIntoItsSpec) {
  const LayerSpec p = ParseLayerSpec(Json::parse(R"({"kind":"probability","base":"occ","log_odds":{"hit":0.8}})"), "p");
  EXPECT_EQ(std::get<services::ProbabilityLayerSpec>(p).log_odds.hit_probability, 0.8);
  const LayerSpec f = ParseLayerSpec(
      Json::parse(R"({"kind":"fused","op":"xor","operands":[{"layer":"a"},{"layer":"b","threshold":0.2}]})"), "f");
  const auto& fused = std::get<services::FusedLayerSpec>(f);
  EXPECT_EQ(fused.op, FuseOp::kXor);
  EXPECT_EQ(fused.operands[0].threshold, 0.5);
  EXPECT_EQ(fused.operands[1].threshold, 0.2);
  const LayerSpec l = ParseLayerSpec(Json::parse(R"({"kind":"label","base":"occ","labels":{"2":"hall"}})"), "l");
  EXPECT_EQ(std::get<services::LabelLayerSpec>(l).labels.at(2), "hall");
}

TEST(GridJsonTest, AnUnknownKindNamesTheKindsThatExist) {
  const Error e = ParseError(R"({"kind":"voxel"})");
  EXPECT_EQ(e.code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(e.field(), "kind");
  EXPECT_STREQ(e.what(), "kind must be probability, fused or label (occupancy layers are imported as multipart yaml + image)");
}

TEST(GridJsonTest, BadSpecsNameTheirField) {
  EXPECT_EQ(ParseError(R"({"kind":"fused","op":"nand","operands":[]})").field(), "op");
  EXPECT_EQ(ParseError(R"({"kind":"fused","op":"and","operands":[{"layer":"a"}]})").field(), "operands");
  EXPECT_EQ(ParseError(R"({"kind":"fused","op":"and","operands":[{"layer":"new"},{"layer":"a"}]})").field(),
            "operands[0].layer");
  EXPECT_EQ(ParseError(R"({"kind":"fused","op":"and","operands":[{"layer":"a","threshold":2},{"layer":"b"}]})").field(),
            "operands[0].threshold");
  EXPECT_EQ(ParseError(R"({"kind":"label","base":"occ","labels":{"0":"x"}})").field(), "labels.0");
  EXPECT_EQ(ParseError(R"({"kind":"probability","base":"occ","colour":1})").field(), "colour");
  EXPECT_EQ(ParseError(R"({"kind":"probability","base":"occ","log_odds":{"hit":0.2}})").field(), "log_odds.hit");
}

TEST(GridJsonTest, FormatsAreTheFourExportFormats) {
  EXPECT_EQ(ParseLayerFormat("raw"), services::LayerFormat::kRaw);
  EXPECT_EQ(ParseLayerFormat("yaml"), services::LayerFormat::kYaml);
  EXPECT_THROW(ParseLayerFormat("bmp"), Error);
  EXPECT_THROW(ParseLayerFormat(""), Error);
}

TEST(GridJsonTest, ALayerShowsItsRecordFieldsMetadataAndStatistics) {
  services::LayerInfo info;
  info.map = "m";
  info.name = "lab";
  info.kind = LayerKind::kLabel;
  info.version = 3;
  info.stored_bytes = 99;
  storage::LabelLayerMeta meta;
  meta.geometry.width_cells = 2;
  meta.geometry.height_cells = 1;
  meta.base = "occ";
  meta.labels = {{1, "hall"}, {12, "bath"}};
  info.meta = meta;
  info.statistics = engine::LabelStatistics{{{12, 5}}};
  const Json j = ToJson(info);
  EXPECT_EQ(j["kind"], "label");
  EXPECT_EQ(j["version"], 3);
  EXPECT_EQ(j["stored_bytes"], 99);
  EXPECT_EQ(j["base"], "occ");
  EXPECT_EQ(j["labels"], Json::parse(R"({"1":"hall","12":"bath"})"));
  EXPECT_EQ(j["geometry"]["width_cells"], 2);
  EXPECT_EQ(j["statistics"], Json::parse(R"({"cells_per_label":{"12":5}})"));
}

TEST(GridJsonTest, AMapPageHasANullCursorAtTheEnd) {
  EXPECT_EQ(ToJson(services::MapPage{{{"a", "A", 1}}, std::nullopt}),
            Json::parse(R"({"maps":[{"id":"a","name":"A","created_ns":1}],"next_cursor":null})"));
  EXPECT_EQ(ToJson(services::MapPage{{}, "a"})["next_cursor"], "a");
}

}  // namespace
}  // namespace anchordb::api::grid_json
